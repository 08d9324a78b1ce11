"""The integrator name `auto`: the C method the bench measured cheapest at the requested
tolerance (runtime/integrate/methods.py, AUTO_VERN9_BELOW_TOL), usable wherever an integrator is
named, recorded as the method that ran, and refused in one line with a fixed step."""
from __future__ import annotations

import json

import numpy as np
import pytest

from levitron.runtime.scan import stability_map as sc
from levitron.runtime.errors import UserError
from levitron.runtime.integrate.run import integrate
from levitron.runtime.integrate.methods import (
    AUTO,
    AUTO_VERN9_BELOW_TOL,
    METHODS,
    TABLE,
    lookup,
    resolve,
)
from levitron.runtime.simulate.run import simulate

SET = ["top.mass=0.0515"]        # the `model` fixture's setting (tests/conftest.py LIGHT_TOP)
OSC = dict(x0=[1.0, 0.0, 0.0, 1.0], scale=[1.0, 1.0, 1.0, 1.0])   # the unit oscillator of tests/c/systems.c


def test_the_rule_and_its_crossover():
    def ran(*args):
        return resolve(*args).name
    assert ran(AUTO, 1e-6) == "dop853"
    assert ran(AUTO, 1e-9) == "dop853"
    assert ran(AUTO, AUTO_VERN9_BELOW_TOL) == "dop853"
    assert ran(AUTO, AUTO_VERN9_BELOW_TOL * (1 - 1e-12)) == "vern9"
    assert ran(AUTO, 1e-12) == "vern9"
    for e in TABLE:                                   # every other name is itself
        assert ran(e.name, 1e-12, 0.1 if e.fixed_step else None) == e.name
    assert AUTO in METHODS and AUTO not in {e.name for e in TABLE}
    assert {ran(AUTO, t) for t in np.logspace(-15, -2, 53)} == {"dop853", "vern9"}
    assert all(lookup(ran(AUTO, t)).backend == "c" for t in (1e-5, 1e-13))


def test_a_choice_carries_what_governs_its_method():
    """resolve() is the one place a name becomes the method that runs (a Choice): an adaptive
    method keeps the tolerance and no step, a fixed-step one the step and no tolerance; the step
    given to an adaptive method (auto included) is refused there, in one line."""
    from levitron.runtime.errors import UserError
    c = resolve(AUTO, 1e-12)
    assert (c.name, c.requested, c.tol, c.h, c.fixed_step) == ("vern9", AUTO, 1e-12, None, False)
    assert c.details() == {"integrator_requested": AUTO, "auto": c.details()["auto"]}
    f = resolve("rk4", 1e-9, 1e-3)
    assert (f.name, f.requested, f.tol, f.h, f.fixed_step, f.details()) == ("rk4", "rk4", None, 1e-3, True, {})
    assert resolve("rk4", 1e-9).with_step(2e-3).h == 2e-3
    for name in ("dop853", AUTO):
        with pytest.raises(UserError) as e:
            resolve(name, 1e-9, 1e-3)
        assert e.value.param == "step" and "\n" not in str(e.value), str(e.value)


@pytest.mark.parametrize("tol, method", [(1e-6, "dop853"), (1e-12, "vern9")])
def test_integrate_auto_is_the_chosen_method_bit_for_bit(osc, tol, method):
    runs = {m: integrate(osc, OSC["x0"], 7.0, method=m, tol=tol, scale=OSC["scale"],
                         n_out=20, monitor_energy=True) for m in (AUTO, method)}
    a, b = runs[AUTO], runs[method]
    np.testing.assert_array_equal(a.x_final, b.x_final)
    np.testing.assert_array_equal(a.X, b.X)
    assert (a.rhs_evals, a.steps, a.status) == (b.rhs_evals, b.steps, b.status)
    assert a.method == method and a.backend == "c"
    assert a.details["integrator_requested"] == AUTO and method in a.details["auto"]
    assert "integrator_requested" not in b.details


def test_run_c_takes_auto_too(osc):
    from levitron.runtime.integrate.c_backend import run_c
    for tol, method in ((1e-6, "dop853"), (1e-12, "vern9")):
        a, b = (run_c(osc.lib, m, osc.c_function("rhs"), OSC["x0"], osc.p, 5.0, rtol=tol, atol=tol)
                for m in (AUTO, method))
        np.testing.assert_array_equal(a.x_final, b.x_final)
        assert a.method == method and a.details["integrator_requested"] == AUTO
    with pytest.raises(UserError, match="name a fixed-step method"):
        run_c(osc.lib, AUTO, osc.c_function("rhs"), OSC["x0"], osc.p, 5.0, h=0.01)


@pytest.mark.parametrize("tol, method", [(1e-6, "dop853"), (1e-12, "vern9")])
def test_simulate_auto_on_the_full_model(model, tol, method):
    kw = dict(spin=1000.0, tilt=0.02, t_end=0.05, tol=tol, n_out=10)
    a = simulate(model, integrator=AUTO, **kw)
    b = simulate(model, integrator=method, **kw)
    assert a["final_state"] == b["final_state"]                  # the same floats, bit for bit
    assert a["rhs_evals"] == b["rhs_evals"] and a["status"] == b["status"]
    assert a["integrator"] == method and a["integrator_requested"] == AUTO
    assert method in a["integrator_choice"]
    assert b["integrator_requested"] == method and "integrator_choice" not in b


def test_scan_auto_equals_the_chosen_method(model):
    """Through the C chunk driver and the Python path alike (runtime/scan/runners.py)."""
    grid = dict(spins=np.array([600.0, 2500.0]), axis="tilt", others=np.array([0.02]), t_end=0.2,
                tol=1e-11, quiet=True)
    for engine in ("c", "python"):
        ref = sc.scan(model, integrator="vern9", engine=engine, **grid)
        got = sc.scan(model, integrator=AUTO, engine=engine, **grid)
        assert got.status == ref.status and got.runner["engine"] == engine
        assert got.as_json()["integrator"] == "vern9"
        assert got.as_json()["integrator_requested"] == AUTO
        np.testing.assert_array_equal(got.t_survived, ref.t_survived)
        np.testing.assert_array_equal(got.levitating, ref.levitating)
        assert got.rhs_evals == ref.rhs_evals          # dop853's differ: the same method ran
        assert got.rhs_evals != sc.scan(model, integrator="dop853", engine=engine,
                                        **grid).rhs_evals
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.scan.runners import Common, run_chunk
    common = Common("thesis", tuple(SET), "tilt", 0.2, AUTO, 1e-6, 0.0, (hover_height(model),))
    assert run_chunk(common, [(0, 0, 600.0, 0.02)])["method"] == "dop853"


@pytest.mark.parametrize("kwargs, words", [
    ({"h": 1e-3, "tol": None}, "name a fixed-step method"),
    ({"h": 1e-3, "tol": 1e-9}, "name a fixed-step method"),
    ({"tol": None}, "tolerance"),
    ({"tol": -1.0}, "tolerance"),
    ({"tol": float("nan")}, "tolerance"),
    ({"tol": 1e-16}, "below double precision"),     # the chosen method's own checks still apply
    ({"tol": 1.0}, "too loose"),
])
def test_bad_combinations_are_one_line(osc, kwargs, words):
    with pytest.raises(UserError, match=words) as err:
        integrate(osc, OSC["x0"], 1.0, method=AUTO, scale=OSC["scale"], **kwargs)
    assert "\n" not in str(err.value)


def _cli(argv, capsys):
    from levitron.runtime.cli.main import main
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_simulate_auto(capsys):
    code, out, err = _cli(["simulate", "thesis", "--spin", "1000", "--tilt", "0.01", "--t-end", "0.02",
                           "--integrator", "auto", "--tol", "1e-12", "--json"], capsys)
    assert code == 0, err
    r = json.loads(out)
    assert r["integrator"] == "vern9" and r["integrator_requested"] == "auto" and r["backend"] == "c"


@pytest.mark.parametrize("args, words", [
    (["--integrator", "auto", "--step", "1e-4"], "name a fixed-step method"),
    (["--integrator", "auto", "--tol", "0"], "tolerance"),
    (["--integrator", "automatic"], "auto"),          # the choices listed include auto
])
def test_cli_bad_auto_is_one_line_exit_2(capsys, args, words):
    code, out, err = _cli(["simulate", "thesis", "--spin", "1000", "--t-end", "0.02", *args], capsys)
    lines = [ln for ln in err.splitlines() if ln.strip() and not ln.startswith("levitron: deriv")]
    assert code == 2 and out.strip() == ""
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in err
