"""Taylor's method: the generated coefficients (derive/emit/taylor.py) and LEV_TAYLOR (integrators.c).

The coefficients are checked against the solution itself (the polynomial of order p misses
x(h) by C^[p+1] h^(p+1) to leading order, with x(h) from an accurate fixed-step run), to degree 10,
on the scenes' plates and on an expression plate that uses every recurrence (exp, log, sin, cos, a
real power, 1/a, sqrt, products); degree 1 against the generated rhs and degree 2 against the
generated Jacobian (J f / 2). The integrator is checked on
the oscillator of tests/c/systems.c (a hand-written Taylor function, exact solution known) and
on the scenes' reduced models against the bench's reference.
"""
from __future__ import annotations

import ctypes
import json
import math

import numpy as np
import pytest

from levitron.derive.emit.heyoka import lowered_rhs
from levitron.derive.emit.taylor import TAYLOR_MAX_ORDER, Unsupported, taylor_tape
from levitron.scene.load import load_scene
from levitron.runtime.errors import UserError
from levitron.runtime.integrate.run import Box, CSystem, integrate, run_c
from levitron.runtime.model.load import load_model

DP = ctypes.POINTER(ctypes.c_double)
SCENES = ("thesis_stable", "ring_magnet", "square", "loop")


def coefficients(fn, x, p, order: int) -> np.ndarray:
    x, p = np.ascontiguousarray(x, float), np.ascontiguousarray(p, float)
    out = np.full(len(x) * (order + 1), np.nan)
    assert fn(x.ctypes.data_as(DP), p.ctypes.data_as(DP), order, out.ctypes.data_as(DP)) == 0
    return out.reshape(len(x), order + 1)


def accurate(part, x, p, h) -> np.ndarray:
    """x(h) from x by the fixed-step DOP853 formula at h / 40 (error below round-off here)."""
    r = run_c(part.model.lib, "dop853-fixed", part.c_function("rhs"), x, p, h, h=h / 40)
    assert r.status == "completed"
    return r.x_final


def assert_predicts(part, x, p, C):
    """What the polynomial of order q misses of the solution is its next two terms,
    x(h) - sum_{j<=q} C^[j] h^j = C^[q+1] h^(q+1) + C^[q+2] h^(q+2) (1 + O((h / rho)^2)): checked
    for q = 1 .. order - 2 at h = rho / 50 and rho / 10 (rho: the radius the coefficients show), on
    every component where those terms stand above round-off, so each coefficient to degree 10 is
    held against the solution."""
    order = C.shape[1] - 1
    w = np.abs(C[:, 0]) + np.abs(C[:, 1]) + 1e-300
    norm = np.max(np.abs(C[:, 1:]) / w[:, None], axis=0)
    rho = min(norm[j - 1] ** (-1.0 / j) for j in range(1, order + 1) if norm[j - 1] > 0)
    checked = set()
    for h in (0.02 * rho, 0.1 * rho):
        exact = accurate(part, C[:, 0], p, h)
        terms = C * h ** np.arange(order + 1)
        for q in range(1, order - 1):
            err = exact - terms[:, :q + 1].sum(axis=1)
            pred = terms[:, q + 1] + terms[:, q + 2]
            size = np.abs(terms[:, q + 1]) + np.abs(terms[:, q + 2])
            big = size > 1e-12 * w
            np.testing.assert_array_less(np.abs(err - pred)[big], 0.1 * size[big] + 1e-15 * w[big])
            checked |= {(k, q + 1) for k in np.flatnonzero(big)} | {(k, q + 2) for k in np.flatnonzero(big)}
    degrees = {d for _, d in checked}
    assert degrees == set(range(2, order + 1)), sorted(degrees)


def hover_state(model):
    from levitron.runtime.bench import work_precision as wp
    su = wp.setup(model)
    part, x0, scale = wp.start(model, "reduced", su)
    return su, part, np.asarray(x0, float), scale


@pytest.mark.parametrize("name", SCENES)
def test_coefficients_predict_the_solution(name):
    model = load_model(load_scene(name))
    su, part, x0, _ = hover_state(model)
    x = x0 * [1.05, 1.0, 1.0, 1.0] + [0.0, 0.3, 0.2 * abs(x0[3]) + 1e-9, 0.0]   # moving, off the hover
    C = coefficients(part.taylor_function(), x, su.p, 10)
    f, J = part.rhs(x, su.p), part.jac(x, su.p)
    np.testing.assert_allclose(C[:, 1], f, rtol=1e-14, atol=1e-300)            # degree 1: the rhs
    np.testing.assert_allclose(C[:, 2], J @ f / 2, rtol=1e-12, atol=1e-12 * np.abs(J @ f).max())
    assert_predicts(part, x, su.p, C)


EVERY_OP = ('rho*exp(-z/b)*sin(z/b)*log(1 + z/b) + rho*cos(z/b)/(z + b)**(1/3) + rho*sqrt(z*z + b*b)'
            ' + rho*tan(z/b)*tanh(z/b) + rho*sinh(z/b)/cosh(z)')


def test_every_recurrence_on_an_expression_plate(derived_model, tmp_path):
    """exp, log, sin, cos, a cube root, products, 1/a and sqrt (and tan, sinh, cosh, tanh through
    them) through the whole chain: scene -> derive -> C -> coefficients that predict the solution."""
    scene = tmp_path / "every_op.toml"
    scene.write_text("\n".join([
        'name = "every_op"', "g = 1.0", "[top]", "mass = 1.0", "A = 0.01", "C = 0.006",
        "moment = 1.0", "[plate]", 'kind = "expression"', f'phi0 = "{EVERY_OP}"',
        "[plate.params]", "rho = 0.7", "b = 0.3", "[field]", "order = 2", "[model]",
        'needs = ["reduced"]']) + "\n")
    model = derived_model(str(scene))
    part = model.part("reduced")
    ops = {op for _, op, _ in taylor_tape(lowered_rhs(model.scene, "reduced")).nodes}
    assert {"exp", "log", "sin", "cos", "pow", "mul", "inv", "sqrt", "lin"} <= ops
    x = np.array([0.42, 0.1, -0.3, 0.05])
    C = coefficients(part.taylor_function(), x, model.p, 10)
    np.testing.assert_allclose(C[:, 1], part.rhs(x, model.p), rtol=1e-14, atol=1e-300)
    assert_predicts(part, x, model.p, C)


def test_an_operation_without_recurrence_gets_no_taylor_function(derived_model, tmp_path):
    """atan has no recurrence here (z^2 atan(z/b) keeps an atan in the derivatives the rhs uses): the model has no
    Taylor function, and integrator taylor says what to use instead."""
    scene = tmp_path / "atan_plate.toml"
    scene.write_text("\n".join([
        'name = "atan_plate"', "g = 1.0", "[top]", "mass = 1.0", "A = 0.01", "C = 0.006",
        "moment = 1.0", "[plate]", 'kind = "expression"', 'phi0 = "rho*z*z*atan(z/b)"',
        "[plate.params]", "rho = 0.7", "b = 0.3", "[field]", "order = 2", "[model]",
        'needs = ["reduced"]']) + "\n")
    model = derived_model(str(scene))
    with pytest.raises(Unsupported, match="atan"):
        taylor_tape(lowered_rhs(model.scene, "reduced"))
    assert model.part("reduced").taylor_function() is None and not model.manifest.taylor
    with pytest.raises(UserError, match=r"has none \(its rhs has an operation without a recurrence"):
        integrate(model.part("reduced"), [0.5, 0, 0, 0.01], 1.0, method="taylor", tol=1e-9)


def test_out_of_range_order_is_refused_and_writes_nothing():
    model = load_model(load_scene("thesis_stable"))
    fn = model.part("reduced").taylor_function()
    assert model.manifest.taylor["reduced"].max_order == TAYLOR_MAX_ORDER
    x, p = np.array([0.1, 0, 0, 1e-3]), np.asarray(model.p, float)
    for order in (0, -3, TAYLOR_MAX_ORDER + 1):
        out = np.full(4 * (TAYLOR_MAX_ORDER + 3), 7.0)
        assert fn(x.ctypes.data_as(DP), p.ctypes.data_as(DP), order, out.ctypes.data_as(DP)) == -1
        assert (out == 7.0).all()


def test_the_full_model_has_none_and_taylor_says_so():
    model = load_model(load_scene("thesis_stable"))
    assert set(model.manifest.taylor) == {"reduced"}
    full = model.part("full")
    with pytest.raises(UserError, match=r"the full model of scene 'thesis_stable' has none \(derive "
                                         r"generates them for the reduced model only\)"):
        integrate(full, np.r_[0.0, 0.0, 0.1, np.zeros(9)] + 1e-3, 0.01, method="taylor", tol=1e-9)


def test_order_from_the_tolerance(lib):
    for tol, order in ((1e-2, 4), (1e-8, 11), (1e-9, 12), (1e-15, 19), (1e-40, TAYLOR_MAX_ORDER),
                       (0.5, 2), (10.0, 2)):
        assert lib.lev_taylor_order(tol) == order, tol
        assert order == max(2, min(TAYLOR_MAX_ORDER, math.ceil(-math.log(tol) / 2 + 1)))


@pytest.mark.parametrize("tol", [1e-6, 1e-9, 1e-12])
def test_oscillator_within_the_tolerance_over_ten_turns(osc, tol):
    """x'' = -x from (1, 0, 0, 1): the circle; Jorba & Zou's step keeps the error below tol per turn."""
    t = 20 * math.pi
    r = run_c(osc.lib, "taylor", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, t, rtol=tol, atol=tol,
              taylor=osc.taylor_function(), energy=osc.c_function("energy"))
    assert r.status == "completed" and r.rhs_evals == 0 and r.iterations == r.steps
    exact = [math.cos(t), math.sin(t), -math.sin(t), math.cos(t)]
    assert np.abs(r.x_final - exact).max() < 10 * tol
    assert r.energy_max_dev < 10 * tol


def test_dense_output_is_the_steps_polynomial(osc):
    t_out = np.concatenate([[0.0], np.sort(np.random.default_rng(3).uniform(0, 10, 41)), [10.0]])
    r = run_c(osc.lib, "taylor", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 10.0, rtol=1e-12,
              atol=1e-12, t_out=t_out, taylor=osc.taylor_function())
    assert r.status == "completed" and r.steps < len(t_out)
    np.testing.assert_array_equal(r.t, t_out)
    exact = np.c_[np.cos(t_out), np.sin(t_out), -np.sin(t_out), np.cos(t_out)]
    assert np.abs(r.X - exact).max() < 1e-11


def test_box_event_on_the_polynomial(lib):
    """The unstable oscillator leaves x <= 1 at acosh(10), located on the step's polynomial."""
    fly = CSystem(lib, "lev_oscillator", ["x", "y", "vx", "vy"], [-1.0])
    r = integrate(fly, [0.1, 0, 0, 0], 10.0, method="taylor", tol=1e-11,
                  box=Box(iz=0, z_lo=-1.0, z_hi=1.0), n_out=10, scale=[1, 1, 1, 1])
    assert r.status == "left_box"
    assert r.t_final == pytest.approx(math.acosh(10.0), abs=1e-9)
    assert r.x_final[0] == pytest.approx(1.0, abs=1e-10) and r.t[-1] == r.t_final


def test_no_taylor_function_or_no_rtol_is_bad_input(osc):
    r = run_c(osc.lib, "taylor", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 1.0, rtol=1e-9, atol=1e-9)
    assert r.status == "bad_input"
    r = run_c(osc.lib, "taylor", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 1.0, rtol=0.0, atol=1e-9,
              taylor=osc.taylor_function())
    assert r.status == "bad_input"


def _vector_path_compiled() -> bool:
    """Whether the default flags (-march=native) give lev_tay_old its AVX2 + fma vector path."""
    import subprocess
    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compiler
    macros = subprocess.run([compiler(), *[f for f in DEFAULT_FLAGS if f.startswith("-m")], "-dM", "-E", "-"],
                            input="", capture_output=True, text=True, check=True).stdout.split("\n")
    return {"#define __AVX2__ 1", "#define __FMA__ 1"} <= {m.strip() for m in macros}


@pytest.mark.parametrize("name", ("thesis_stable", "ring_magnet"))
def test_vector_sums_give_the_scalar_bits(name):
    """lev_tay_old's vector path (runtime/csrc/lev_taylor.h: the four chains as the lanes of one AVX2 register), as
    the model's library runs it, against its scalar path (the same generated model.c built with
    -DLEV_TAYLOR_SCALAR): every coefficient of every order 1 .. max at random states near the hover
    height equal bit for bit (the recurrences that sum through it: products, 1/a, sqrt; the largest
    tape)."""
    if not _vector_path_compiled():
        pytest.skip("this compiler and machine give no AVX2 + fma: only the scalar path is built")
    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compile_shared
    model = load_model(load_scene(name))
    folder = model.folder
    from levitron.runtime.model.load import CSRC
    scalar = ctypes.CDLL(str(compile_shared([folder / "model.c"], DEFAULT_FLAGS + ("-DLEV_TAYLOR_SCALAR",),
                                            (folder, CSRC))))
    fns = [model.part("reduced").taylor_function(), getattr(scalar, model.symbol("reduced_taylor"))]
    su, part, x0, scale = hover_state(model)
    rng = np.random.default_rng(7)
    for order in range(1, TAYLOR_MAX_ORDER + 1):
        x = x0 + scale * rng.uniform(-0.2, 0.2, len(x0))
        vec, sca = (coefficients(fn, x, su.p, order) for fn in fns)
        assert np.isfinite(vec).all()
        np.testing.assert_array_equal(vec.view(np.int64), sca.view(np.int64), err_msg=f"order {order}")


@pytest.mark.parametrize("name", SCENES)
def test_reduced_runs_meet_the_reference(name):
    """The bench's run of each scene (runtime/bench/work_precision.py): within 10 tol of its
    reference; at the tight tolerance in fewer (longer) steps than dop853 takes."""
    from levitron.runtime.bench import work_precision as wp
    model = load_model(load_scene(name))
    su, part, x0, scale = hover_state(model)
    ref, _ = wp.reference(part, x0, su, scale)
    for tol in (1e-7, 1e-10):
        r = integrate(part, x0, su.t_end, method="taylor", tol=tol, p=su.p, scale=scale, n_out=1)
        assert r.status == "completed"
        assert np.max(np.abs(r.x_final - ref) / scale) < 10 * tol
    d = integrate(part, x0, su.t_end, method="dop853", tol=1e-10, p=su.p, scale=scale, n_out=1)
    assert r.steps < d.steps                        # at 1e-10: fewer, longer steps than dop853


def test_info_names_the_parts_with_taylor_coefficients(capsys):
    from levitron.runtime.cli.main import main
    assert main(["info", "thesis_stable", "--json"]) == 0
    got = json.loads(capsys.readouterr().out)["taylor"]
    assert got == {"reduced": {"function": "reduced_taylor", "max_order": TAYLOR_MAX_ORDER,
                               "nodes": load_model(load_scene("thesis_stable")).manifest.taylor["reduced"].nodes}}
    assert main(["info", "thesis_stable"]) == 0
    assert "taylor coefficients: reduced (reduced_taylor, " in capsys.readouterr().out
