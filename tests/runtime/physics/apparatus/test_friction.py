"""Air friction (derive/friction.py) and a real launch (runtime/physics/apparatus/friction.py,
runtime/scan/launch_odds.py).

The checks are exact laws, not fits: with friction the spin decays as omega_3(0) exp(-k_spin t)
along every trajectory (the magnetic torque is perpendicular to the axis), the energy obeys
dH/dt = -2F, and the generated generalised forces equal a hand-derived closed form.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from levitron.scene.load import SceneError, load_scene
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.simulate import run as sim, rotations, start
from levitron.runtime.physics.equilibrium import finder as equilibrium
from levitron.runtime.cli.main import main
from levitron.runtime.errors import UserError
from levitron.runtime.model.load import load_model

RATES = {"k_spin": 1 / 150.0, "k_tilt": 1 / 20.0, "k_trans": 1 / 30.0}


@pytest.fixture(scope="module")
def air_zxz(derived_model):
    return derived_model("thesis_air", 'model.coordinates="euler-zxz"')


def hand_forces(coords: str, x: np.ndarray, names: list[str], k: dict) -> np.ndarray:
    """Q_j = -dF/d(qdot_j) by hand: -k_trans p for the position; for the angles
    -k_tilt p_a + (k_tilt - k_spin) p_spin * (dn_spin/da) with the spin's direction cosine
    (Tait-Bryan: omega_3 = -p_zeta/C, p_phi's share sin(vartheta); z-x-z: cos(theta))."""
    s = dict(zip(names, x))
    q = np.zeros(len(names))
    for a in ("x", "y", "z"):
        q[names.index("p_" + a)] = -k["k_trans"] * s["p_" + a]
    if coords == "tait-bryan":
        spin, first, second, lean = "p_zeta", "p_phi", "p_vartheta", math.sin(s["vartheta"])
    else:
        spin, first, second, lean = "p_psi", "p_phi", "p_theta", math.cos(s["theta"])
    q[names.index(first)] = -k["k_tilt"] * s[first] + (k["k_tilt"] - k["k_spin"]) * s[spin] * lean
    q[names.index(second)] = -k["k_tilt"] * s[second]
    q[names.index(spin)] = -k["k_spin"] * s[spin]
    return q


@pytest.mark.parametrize("which", ["air", "air_zxz"])
def test_generated_dissipative_terms_match_the_hand_form(which, request):
    model = request.getfixturevalue(which)
    pt = model.part("full")
    coords = rotations.coordinates_of(pt)
    p = model.with_params(RATES)
    p0 = model.with_params({r: 0.0 for r in RATES})
    rng = np.random.default_rng(7)
    for _ in range(20):
        x = rng.uniform(-1, 1, pt.nx) * np.array([0.01, 0.01, 0.1, 0.5, 0.5, 3,
                                                   1e-3, 1e-3, 1e-3, 1e-5, 1e-5, 1e-3])
        x[pt.states.index("z")] = 0.1 + 0.01 * rng.uniform()
        if coords == "euler-zxz":
            x[pt.states.index("theta")] = 0.3 + 0.2 * rng.uniform()
        for backend in ("c", "casadi"):
            got = pt.rhs(x, p, backend) - pt.rhs(x, p0, backend)
            want = hand_forces(coords, x, list(pt.states), RATES)
            size = np.abs(pt.rhs(x, p, backend)) + np.abs(want) + 1e-300
            assert np.all(np.abs(got - want) <= 1e-12 * size), (backend, got, want)


@pytest.mark.parametrize("which,tilt", [("air", 0.01), ("air_zxz", 0.05)])
def test_spin_decays_exactly_exponentially_for_60_s(which, tilt, request):
    """omega_3(t) = omega_3(0) exp(-t/tau) along a levitating 60 s run, to 10x the tolerance, with
    tilt and translation friction on as well (neither exerts a torque about the axis)."""
    model = request.getfixturevalue(which)
    tol = 1e-10
    r = sim.simulate(model, spin=1000.0, tilt=tilt, t_end=60.0, tol=tol, params=RATES, n_out=600)
    assert r["levitating"] is True and r["t_survived"] == 60.0
    assert r["flight"]["spin_decay_deviation"] <= 10 * tol
    w_end = 1000.0 * math.exp(-60.0 / 150.0)
    assert abs(r["flight"]["spin_final"] - w_end) <= 10 * tol * 1000.0


def test_decay_times_are_times_and_rates_are_rates(air, capsys):
    """The flight block and `info` name a decay time (s) by what decays and a rate (1/s) by its
    parameter: the spin's named decay time is the one the spin decays with, exp(-t / tau), and the
    rate is its inverse (issue 26: {"k_spin": 200.0} was a time under a rate's name)."""
    r = sim.simulate(air, spin=1000.0, tilt=0.01, t_end=2.0, params=RATES, n_out=50)
    fl = r["flight"]
    assert fl["decay_times"] == pytest.approx({"spin": 150.0, "tilt": 20.0, "translation": 30.0}, rel=1e-12)
    assert fl["friction_rates"] == pytest.approx(RATES, rel=1e-12)
    assert fl["spin_final"] == pytest.approx(1000.0 * math.exp(-2.0 / fl["decay_times"]["spin"]), rel=1e-8)
    assert fl["spin_final"] == pytest.approx(1000.0 * math.exp(-2.0 * fl["friction_rates"]["k_spin"]), rel=1e-8)
    assert main(["info", "thesis_air", "--json"]) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["decay_times"] == {"spin": 150.0, "tilt": None, "translation": None}
    assert info["friction_rates"] == {"k_spin": pytest.approx(1 / 150.0, rel=1e-15), "k_tilt": 0.0, "k_trans": 0.0}
    assert main(["info", "thesis_air"]) == 0
    assert "air friction: decay times spin 2 min 30 s, tilt none, translation none" in capsys.readouterr().out


def test_energy_balance_along_a_run(air):
    """E(t) - E(0) = -integral of 2F dt, the energy lost integrated beside the state (scipy DOP853
    at rtol 1e-12 on the generated rhs and full_dissipation): friction strong enough to lose a
    good part of the energy in 2 s."""
    k = {"k_spin": 0.5, "k_tilt": 2.0, "k_trans": 1.0}
    pt = air.part("full")
    p = air.with_params(k)
    z_s = equilibrium.hover_height(air, p)
    x0 = start.initial_state(pt, z_s, 1500.0, 0.02, 0.001, p)
    power = air.fast("full_dissipation", p)

    def f(t, y):
        return np.concatenate([pt.rhs(y[:-1], p), power(y[:-1])])

    sol = solve_ivp(f, (0, 2.0), np.concatenate([x0, [0.0]]), method="DOP853", rtol=1e-12,
                    atol=np.concatenate([1e-14 * np.maximum(np.abs(x0), 1e-3), [1e-16]]), dense_output=True)
    assert sol.success
    ts = np.linspace(0, 2.0, 41)
    E = np.array([pt.energy(sol.sol(t)[:-1], p) for t in ts])
    lost = sol.sol(ts)[-1]
    assert lost[-1] > 0.3 * abs(E[0] - air.pvals(p)["m"] * air.pvals(p)["g"] * z_s)   # a real loss
    np.testing.assert_allclose(E - E[0], -lost, rtol=0, atol=1e-9 * lost[-1])


def test_a_scene_without_friction_gets_the_conservative_model():
    """No decay time: no friction parameters, no full_dissipation, and the structure hashed for
    derive is that of a scene that never heard of friction (generated/ byte-identity itself is
    tests/runtime/model/test_artefacts.py's)."""
    from levitron.scene.inputs import structure
    still = load_model(load_scene("thesis_stable"))
    assert not any(r in still.param_names for r in RATES)
    assert not still.has_function("full_dissipation")
    assert "friction" not in structure(load_scene("thesis_stable").data)
    air = load_scene("thesis_air")
    assert structure(air.data)["friction"] is True
    # the conservative parts are the same functions with or without friction: the reduced model
    sa, ss = load_model(air), still
    x = np.array([0.1, 0.3, 1e-3, -1.3e-3])
    np.testing.assert_array_equal(sa.part("reduced").rhs(x), ss.part("reduced").rhs(x))


def test_flight_time_against_the_adiabatic_prediction(air):
    r = sim.simulate(air, spin=1000.0, tilt=0.005, t_end=300.0)
    fl = r["flight"]
    lo = fl["spin_interval"][0]
    assert fl["fell"] and r["levitating"] is False
    assert fl["t_cross"] == pytest.approx(150.0 * math.log(1000.0 / lo), rel=1e-12)
    assert abs(fl["flight_time"] - fl["t_cross"]) < 5.0          # falls within seconds of the crossing
    assert fl["fall_spin"] == pytest.approx(1000.0 * math.exp(-fl["flight_time"] / 150.0), rel=1e-8)
    assert fl["fall_spin"] < lo * 1.01


def test_friction_run_is_one_person_sized_answer(capsys):
    assert main(["simulate", "thesis_air", "--spin", "1000", "--t-end", "300"]) == 0
    out = capsys.readouterr().out
    first = out.splitlines()[0]
    assert first.startswith("floats ") and "falls at" in first and "after the spin crosses" in first
    assert "adiabatic prediction" in out


def test_unperturbed_launch_is_never_a_plain_levitating(capsys, thesis_model):
    """thesis_stable at 100 rad/s (below sigma_lo = 460): the old default launch on the invariant
    set said 'levitating: yes'."""
    assert main(["simulate", "thesis_stable", "--spin", "100", "--t-end", "2"]) == 0
    assert capsys.readouterr().out.startswith("levitating: no")
    assert main(["simulate", "thesis_stable", "--spin", "100", "--t-end", "2", "--tilt", "0"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("levitating: untested") and "tests no stability" in out
    r = sim.simulate(thesis_model, spin=1500.0, tilt=0.0, t_end=0.1)
    assert r["levitating"] is None and "invariant set" in r["untested"]
    assert main(["scan", "thesis_stable", "--spin", "100:3000:3", "--tilt", "0:0.1:3"]) == 2
    assert "invariant set" in capsys.readouterr().err
    assert main(["scan", "thesis_stable", "--spin", "100:3000:3", "--mass", "0.05:0.052:3",
                 "--base-tilt", "0"]) == 2


def test_api_simulation_does_not_turn_untested_into_false():
    import levitron as lev
    s = lev.load("thesis_stable").simulate(spin=1500.0, tilt=0.0, t_end=0.05)
    assert s.levitating is None
    assert lev.load("thesis_stable").simulate(spin=100.0, t_end=1.0).levitating is False


def test_wilson_interval_matches_scipy():
    from scipy.stats import binomtest
    for k, n in ((0, 10), (5, 10), (37, 50), (1000, 1000), (1, 2000)):
        ci = binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
        assert mc.wilson(k, n) == pytest.approx((ci.low, ci.high), abs=1e-12)
    assert mc.wilson(5, 10) == pytest.approx((0.23659309, 0.76340691), abs=1e-8)   # Wilson 1927 form
    assert [mc.wilson(0, n)[0] for n in (7, 200, 1000)] == [0.0] * 3       # exactly: "0 %", never 1.7e-16
    assert [mc.wilson(n, n)[1] for n in (7, 200, 1000)] == [1.0] * 3


def test_launch_is_the_same_serially_with_processes_and_on_dask(air):
    distributed = pytest.importorskip("dask.distributed")
    kw = dict(n=12, seed=3, t_end=3.0, quiet=True)
    a = mc.monte_carlo(air, {}, **kw)
    b = mc.monte_carlo(air, {}, workers=2, **kw)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, host="127.0.0.1",
                                  protocol="tcp", dashboard_address=None) as c:
        d = mc.monte_carlo(air, {}, scheduler=c.scheduler_address, **kw)
    assert a["verdicts"] == b["verdicts"] == d["verdicts"]
    assert a["flight_time"]["values"] == b["flight_time"]["values"] == d["flight_time"]["values"]
    assert 0 < a["successes"] < a["n"]          # the spread matters: some launches fall
    assert [e["input"] for e in a["ranking"]] == [e["input"] for e in d["ranking"]]


def test_launch_reads_the_scene_table_and_flags(tmp_path, capsys):
    scene = tmp_path / "kit.toml"
    text = open(load_scene("thesis_air").path).read().replace('name = "thesis_air"', 'name = "kit"')
    scene.write_text(text + '\n[launch]\nspin = "normal:1000,50"\ntilt = 0.01\nn = 6\nt_end = 2.0\n')
    assert main(["launch", str(scene), "--json", "--seed", "5"]) == 0
    import json
    r = json.loads(capsys.readouterr().out)
    assert r["n"] == 6 and r["t_end"] == 2.0 and r["inputs"]["spin"] == "normal:1000.0,50.0"
    assert r["inputs"]["tilt"] == "0.01" and r["seed"] == 5
    assert "spin" not in r["defaulted"] and "offset" in r["defaulted"]
    lo, hi = r["probability_ci95"]
    assert lo <= r["probability"] <= hi


@pytest.mark.parametrize("argv,needle", [
    (["--spin", "normal:1000,-5"], "negative"),
    (["--tilt", "gamma:1,2"], "unknown distribution"),
    (["--spin", "uniform:2,1"], "reversed"),
    (["--n", "0"], "--n 0"),
    (["--mass", "rel:normal:0,0.5"], "non-positive"),
    (["--temperature", "-300"], "absolute zero"),
    (["--success-time", "5", "--t-end", "2"], "longer than"),
])
def test_launch_bad_input_is_one_line(argv, needle, capsys):
    assert main(["launch", "thesis_air", "--n", "4", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and "\n" not in err


@pytest.mark.parametrize("override,needle", [
    ("top.spin_decay_time=-5", "must be positive"),
    ("top.spin_decay_time=0", "must be positive"),
    ("top.tilt_decay_time=\"fast\"", "not a number"),
    ("temperature=-274", "absolute zero"),
    ("plate.temperature_coefficient=0.5", "relative change"),
])
def test_bad_friction_and_temperature_keys(override, needle):
    with pytest.raises(SceneError, match=needle):
        load_scene("thesis_air", [override])


def test_friction_on_a_reduced_only_scene_is_explained():
    with pytest.raises(SceneError, match="needs the full model"):
        load_scene("reduced_only", ["top.spin_decay_time=100"])


def test_temperature_scales_the_magnets():
    """28 degC: the ferrite plate loses 8 x 0.2 %, the NdFeB top 8 x 0.12 % (scenes/thesis_air.toml);
    only the product mu x strength enters the dynamics (thesis 2.2.1)."""
    warm = load_scene("thesis_air", ["temperature=28"])
    cold = load_scene("thesis_air")
    assert warm.params["mu"] / cold.params["mu"] == pytest.approx((1 - 0.016) * (1 - 0.0096), rel=1e-14)
    assert warm.field_factor == pytest.approx(1 - 0.016, rel=1e-14)
    assert main(["equilibrium", "thesis_air", "--temperature", "28", "--json"]) == 0


def test_launch_without_spin_interval_needs_a_spin():
    model = load_model(load_scene("thesis"))         # the thesis's own top: no stable interval
    with pytest.raises(UserError):
        mc.monte_carlo(model, {}, n=2, t_end=0.5, quiet=True)


def test_api_launch_matches_the_command():
    import levitron as lev
    odds = lev.load("thesis_air").launch(n=6, seed=1, t_end=2.0)
    r = mc.monte_carlo(load_model(load_scene("thesis_air")), {}, n=6, seed=1,
                       t_end=2.0, quiet=True)
    assert odds.probability == r["probability"] and list(odds.probability_ci95) == r["probability_ci95"]
    assert odds.details["verdicts"] == r["verdicts"]
    head = f"launch odds: {100 * r['probability']:.3g}% of 6 launches float at least 2 s"
    assert odds.success and odds.message.startswith(head)
    assert repr(odds).startswith(f"LaunchOdds({head}") and "success=True" in repr(odds)
    failed = type(odds)(**{**odds.__dict__, "details": {**odds.details, "outcomes": {"completed": 5,
                                                                                      "step_budget": 1}}})
    assert not failed.success and "outcomes: completed 5, step_budget 1" in failed.message


def test_bench_launch_runs_quick(tmp_path):
    """The launch benchmark through the benchmarks' one seam (runtime/bench/kinds.py)."""
    assert main(["bench", "thesis_air", "--kind", "launch", "--quick", "--out", str(tmp_path)]) == 0
    import json
    r = json.loads((tmp_path / "launch.json").read_text())
    assert r["flight"]["wall_s"] > 0 and r["monte_carlo"]["n"] == 8
    assert (tmp_path / "launch_histogram.png").stat().st_size > 0
