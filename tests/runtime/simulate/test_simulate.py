"""`simulate` on the generated models: the initial state (thesis 3.2.9, 3.3.2), the hard cases of
the acceptance case (axis within 1e-6 rad of vertical in both coordinate sets, a 100 s run at 200 rad/s with
its conserved quantities, a top that falls off), the JSON contract and bad options."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from levitron.scene.load import load_scene
from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium.finder import hover_height
from levitron.runtime.integrate.run import integrate
from levitron.runtime.model.load import load_model
from levitron.runtime.simulate.run import simulate
from levitron.runtime.simulate.invariants import angular_momentum_z
from levitron.runtime.simulate.rotations import ANGLES, coordinates_of, rotation_bs
from levitron.runtime.simulate.start import initial_state, state_scales

ROOT = Path(__file__).resolve().parents[3]
DESIGN_KEYS = ("levitating", "t_survived", "max_excursion", "energy_drift", "rhs_evals", "wall_s",
               "final_state")


@pytest.fixture(scope="module")
def model():
    return load_model(load_scene("thesis"))


@pytest.fixture(scope="module")
def zxz_model(tmp_path_factory):
    """The thesis scene in the z-x-z Euler angles of thesis 2.1.9 (derived into the cache)."""
    text = (ROOT / "scenes" / "thesis.toml").read_text()
    text = text.replace('coordinates = "tait-bryan"', 'coordinates = "euler-zxz"')
    text = text.replace('name = "thesis"', 'name = "thesis-zxz"')
    assert 'coordinates = "euler-zxz"' in text
    path = tmp_path_factory.mktemp("scenes") / "thesis-zxz.toml"
    path.write_text(text)
    return load_model(load_scene(str(path)))


def heavy_top(model) -> dict:
    """Parameters of a top inside the stable band of the thesis plate (runtime.physics.equilibrium.finder: band
    9.95-11.02 cm) that 200 rad/s stabilises: m = 51.4 g, A and C eight times the thesis's."""
    names = model.param_names
    pv = dict(zip(names, model.p))
    return {"m": 0.0514, "A": 8 * pv["A"], "C": 8 * pv["C"]}


def pvec(model, over):
    names = model.param_names
    p = model.p.copy()
    for k, v in over.items():
        p[names.index(k)] = v
    return p


def nvec(part, x):
    kind = coordinates_of(part)
    return rotation_bs(kind, [x[part.states.index(a)] for a in ANGLES[kind]])[:, 2]


def test_eq_3_3_2_hover_height(model):
    """z_s solves m g + mu Phi_2(z) = 0 (3.3.2), relative to the size m g of its terms, and is
    vertically stable, mu Phi_3 > 0 (3.3.3)."""
    z_s = hover_height(model)
    m, g, mu = model.param("m"), model.param("g"), model.param("mu")
    ph = model.onaxis(z_s)
    assert abs(m * g + mu * ph[2]) < 1e-12 * m * g
    assert mu * ph[3] > 0


def test_eq_3_2_9_initial_state_spin_and_momenta(model):
    """omega = spin n: the spin angle's rate is -spin (omega_3 = -(zeta_dot + phi_dot sin
    vartheta), 3.2.9), p_zeta = -C omega_3, the velocities of the generated rhs are exactly the
    requested ones, and the energy is U + C spin^2 / 2."""
    part = model.part("full")
    z_s, spin, tilt = hover_height(model), 200.0, 0.3
    x0 = initial_state(part, z_s, spin, tilt, 1e-3)
    s = part.states
    C = model.param("C")
    assert x0[s.index("p_zeta")] == pytest.approx(-C * spin, rel=1e-14)
    qdot = part.rhs(x0)[[s.index(c) for c in s if not c.startswith("p_")]]
    expect = np.zeros(6)
    expect[s.index("zeta")] = -spin
    np.testing.assert_allclose(qdot, expect, atol=1e-12 * spin)
    at_rest = initial_state(part, z_s, 0.0, tilt, 1e-3)
    assert part.energy(x0) - part.energy(at_rest) == pytest.approx(0.5 * C * spin ** 2, rel=1e-12)
    np.testing.assert_allclose(nvec(part, x0), [0, math.sin(tilt), math.cos(tilt)], atol=1e-15)


def test_simulate_json_contract_and_plot(model, tmp_path):
    run = simulate(model, spin=200.0, tilt=0.01, offset=1e-3, t_end=0.05)
    out = run.as_json()
    for k in DESIGN_KEYS:
        assert k in out
    json.dumps(out)   # serialisable
    assert len(run.plot(tmp_path / "t.png").axes) == 3   # the Figure, written to the path
    assert (tmp_path / "t.png").stat().st_size > 5000
    assert set(out["final_state"]) == set(model.part("full").states)
    assert out["box"]["z"][1] - out["z_s"] == pytest.approx(0.5 * out["z_s"])   # scales with z_s


def test_hard_case_top_falls_off_event_stops_cleanly(model):
    """The thesis top at its hover height is not spin-stabilisable (see runtime.physics.stability.analysis): tilted by
    0.01 rad it falls within a second; the box event stops the run, and nothing is NaN."""
    out = simulate(model, spin=200.0, tilt=0.01, offset=1e-3, t_end=5.0)
    assert out["levitating"] is False and out["status"] == "left_box"
    assert 0 < out["t_survived"] < 5.0
    vals = [out["t_survived"], out["max_excursion"], out["energy_drift"], *out["final_state"].values()]
    assert all(math.isfinite(v) for v in vals)
    z = out["final_state"]["z"]
    r = math.hypot(out["final_state"]["x"], out["final_state"]["y"])
    lo, hi = out["box"]["z"]
    # stopped at the box's boundary (bisection on the dense output), not somewhere outside
    assert min(abs(z - lo), abs(z - hi), abs(r - out["box"]["r_max"])) < 1e-9 * out["z_s"]
    assert out["energy_drift"] < 1e-6


def test_hard_case_long_run_100s_at_200_rad_s_conserves(model):
    """100 s at 200 rad/s of a top in the stable band: it levitates, and energy, p_zeta and the
    z-component of the total angular momentum are conserved at the end (relative to their size)."""
    over = heavy_top(model)
    for integrator, kw, e_tol in [("dop853", dict(tol=1e-11), 1e-9), ("gauss4", dict(h=1e-3), 1e-12)]:
        out = simulate(model, spin=200.0, tilt=0.01, offset=1e-3, t_end=100.0, integrator=integrator,
                       params=over, n_out=500, **kw)
        assert out["levitating"] is True and out["t_survived"] == 100.0, integrator
        assert out["max_tilt"] > 0.005            # it did precess/nutate, not a trivial fixed point
        H0, H1 = out["conserved"]["energy"]
        assert abs(H1 - H0) < e_tol * out["energy_scale"], integrator
        L0, L1 = out["conserved"]["L_z"]
        assert abs(L1 - L0) < 1e-9 * abs(L0), integrator
        P0, P1 = out["conserved"]["p_zeta"]
        assert P1 == P0                          # zeta is cyclic: dp_zeta/dt is exactly zero


def test_angular_momentum_z_is_conserved_along_the_flow(model):
    """L_z = x p_y - y p_x + sum p_a da/dalpha stays constant sample by sample (Noether), while
    its orbital and spin parts exchange."""
    over = heavy_top(model)
    p = pvec(model, over)
    part = model.part("full")
    z_s = hover_height(model, p)
    x0 = initial_state(part, z_s, 200.0, 0.02, 2e-3, p)
    pv = model.pvals(p)
    r = integrate(part, x0, 5.0, method="dop853", tol=1e-12, p=p, n_out=200,
                  scale=state_scales(part, z_s, 200.0, pv))
    L = np.array([angular_momentum_z(part, x) for x in r.X])
    s = part.states
    orbital = r.X[:, s.index("x")] * r.X[:, s.index("p_y")] - r.X[:, s.index("y")] * r.X[:, s.index("p_x")]
    assert np.ptp(orbital) > 1e3 * np.ptp(L)
    assert np.ptp(L) < 1e-11 * abs(L[0])


def test_hard_case_axis_near_vertical_euler_vs_tait_bryan(model, zxz_model):
    """Axis within 1e-6 rad of vertical: both charts start with the exact energy (the z-x-z one in
    the factored form of derive/zxz_form.py; expanded, its terms cancelled and the run stopped on
    its step budget) and both complete; they agree to the z-x-z chart's floor, where the stored
    p_phi's rounding (an ulp of L.n) is a transverse angular momentum ulp / sin(theta), which
    nutates the fast top's axis by about that over C spin. At 1e-2 rad they agree to 1e-8."""
    over = heavy_top(model)
    runs = {}
    for tilt in (1e-2, 1e-6):
        for mod in (model, zxz_model):
            part = mod.part("full")
            p = pvec(mod, over)
            z_s = hover_height(mod, p)
            pv = mod.pvals(p)
            x0 = initial_state(part, z_s, 200.0, tilt, 0.0, p)
            r = integrate(part, x0, 0.02, method="dop853", tol=1e-10, p=p, n_out=4,
                          scale=state_scales(part, z_s, 200.0, pv), max_steps=100_000)
            e_spin = 0.5 * pv["C"] * 200.0 ** 2
            at_rest = part.energy(initial_state(part, z_s, 0.0, tilt, 0.0, p), p)
            runs[tilt, coordinates_of(part)] = (r, nvec(part, r.x_final), part.energy(x0, p) - at_rest - e_spin)
    # both coordinate sets describe the same top: at 1e-2 rad they agree
    (ra, na, _), (rb, nb, _) = runs[1e-2, "tait-bryan"], runs[1e-2, "euler-zxz"]
    assert ra.status == rb.status == "completed"
    assert np.abs(na - nb).max() < 1e-6 * 1e-2
    # at 1e-6 rad: both exact in energy (the launch's spin energy to round-off) and complete ...
    r, n_tb, e_err = runs[1e-6, "tait-bryan"]
    assert r.status == "completed" and r.rhs_evals < 2000
    assert abs(e_err) < 1e-13 * 0.5 * 8 * 1.32e-6 * 200.0 ** 2
    r, n_ex, e_err = runs[1e-6, "euler-zxz"]
    assert abs(e_err) < 1e-13 * 0.5 * 8 * 1.32e-6 * 200.0 ** 2
    assert r.status == "completed" and r.rhs_evals < 2000
    # ... and agree to the z-x-z floor (measured 4.2e-10 against a floor of 8.2e-10)
    p_psi = r.x_final[list(zxz_model.part("full").states).index("p_psi")]
    floor = 4 * np.spacing(abs(p_psi)) / (1e-6 * abs(p_psi))
    assert np.abs(n_ex[:2] - n_tb[:2]).max() < floor


def test_near_upright_euler_zxz_completes_and_a_budget_stop_gives_no_verdict(zxz_model, monkeypatch):
    """Near the upright top the z-x-z run used to stop on its default step budget (`simulate --set
    model.coordinates=euler-zxz --tilt 1e-6` never returned before the budget): its expanded
    Hamilton's equations cancelled. In the factored forms (derive/zxz_form.py) it completes with a
    verdict and the energy kept to 1e-12 (measured 5e-16). A run that does use up its budget (here
    a budget of 50 steps) stops with status "step_budget", reported, no exception, and no verdict
    (levitating None: it says nothing of the top; it used to answer False)."""
    out = simulate(zxz_model, spin=1000.0, tilt=1e-6, t_end=1.0)
    assert out["status"] == "completed" and out["levitating"] is True and out["t_survived"] == 1.0
    assert out["energy_drift"] < 1e-12
    import levitron.runtime.integrate.run as run_module
    monkeypatch.setattr(run_module, "default_budget", lambda *a, **k: 50)
    out = simulate(zxz_model, spin=1000.0, tilt=1e-6, t_end=1.0)
    assert out["status"] == "step_budget" and out["levitating"] is None
    assert out["untested"].startswith("the run stopped early (step_budget) before t_end")
    assert "step budget of 50" in out["message"] and out["t_survived"] < 1.0
    for k in DESIGN_KEYS:
        assert k in out


@pytest.mark.parametrize("chart", ["tait-bryan", "euler-zxz"])
@pytest.mark.parametrize("tilt", [1e-8, 1e-7, 1e-6, 1e-4, 0.3])
def test_launch_momenta_are_exact_near_the_upright_top(model, zxz_model, chart, tilt):
    """The launch (thesis eq. 2.3.8, p = dL/d(qdot)) at the hover height, at rest but for the spin:
    exactly L.n = C spin, L_z = C spin cos(tilt), no linear momentum, kinetic energy C spin^2 / 2
    (omega = spin n). The momenta used to come from inverting the generated map dq/dt = M^-1 p;
    in z-x-z M^-1 has entries 1/(A sin^2 theta) beside 1/C, so at theta = 1e-8 the 1/C was lost
    to rounding: p_phi came out -2^-9 instead of C spin = 1.32e-3 (energy off by 45 %, `simulate
    --set model.coordinates=euler-zxz --tilt 1e-8`), and on a dimensionless scene (A = 0.01,
    C = 0.006) numpy raised 'Singular matrix'. Checked against the generated invariants
    (derive/invariants.py) and, where its form allows, the generated energy: second routes."""
    mod = model if chart == "tait-bryan" else zxz_model
    part = mod.part("full")
    p = mod.p
    pv = mod.pvals(p)
    z_s = hover_height(mod, p)
    spin = 1000.0
    x0 = initial_state(part, z_s, spin, tilt, 0.0, p)
    c_spin = pv["C"] * spin
    inv = mod.rows("full_invariants", x0[None, :], p)[0]
    assert abs(inv[1] - c_spin) <= 1e-13 * c_spin, (inv[1], c_spin)
    assert abs(inv[0] - c_spin * math.cos(tilt)) <= 1e-13 * c_spin, (inv[0], c_spin * math.cos(tilt))
    s = list(part.states)
    assert all(x0[s.index(k)] == 0.0 for k in ("p_x", "p_y", "p_z"))
    at_rest = initial_state(part, z_s, 0.0, tilt, 0.0, p)
    t_rot = part.energy(x0, p) - part.energy(at_rest, p)
    assert abs(t_rot - 0.5 * pv["C"] * spin**2) <= 1e-12 * 0.5 * pv["C"] * spin**2


def test_launch_momenta_invert_the_generated_legendre_map(model, zxz_model):
    """Where the chart is regular (tilt 0.3 rad), the momenta of the launch (p = M qdot from the
    rotations of thesis 2.1.9/3.2.2 and I = diag(A, A, C)) are mapped back to the launch's rates by
    the generated Hamilton equations dq/dt = dH/dp: the two routes to the Legendre map agree."""
    from levitron.runtime.simulate.start import coordinate_names, launch
    for mod in (model, zxz_model):
        part = mod.part("full")
        z_s = hover_height(mod, mod.p)
        for az in (0.0, 1.0):
            la = launch(part, z_s, 0.3, 0.01, mod.p, az)
            x0 = initial_state(part, z_s, 700.0, 0.3, 0.01, mod.p, az)
            qdot = np.asarray(part.rhs(x0, mod.p))[la.ic]
            want = np.zeros(len(coordinate_names(part)))
            want[la.i_spin] = 700.0 / la.along
            assert np.abs(qdot - want).max() <= 1e-12 * 700.0, (qdot, want)


def test_reduced_model_vertical_bounce(model):
    """The reduced model (thesis 3.2.12) started at the hover height with spin stays there to the
    tolerance (DOP853 takes steps near its stability limit, ~ the 0.5 s bounce period, so the
    excursion is the dense output's error, ~ tol); the box is applied in z only. The run lies on the
    invariant set, so it gives no verdict: the thesis's top has no stable spin at all, and 200 rad/s
    would not hold it."""
    out = simulate(model, spin=200.0, t_end=10.0, part="reduced", tol=1e-12)
    assert out["status"] == "completed" and out["max_excursion"] < 1e-10 * out["z_s"]
    assert out["levitating"] is None and "reduced model is the motion on the invariant set" in out["untested"]
    assert out["conserved"]["p_zeta"][0] == pytest.approx(-model.param("C") * 200.0)


@pytest.mark.parametrize("kwargs, words", [
    (dict(tol=-1e-9), "tolerance"),
    (dict(tol=1.0), "too loose"),
    (dict(t_end=1e9), "budget cap"),
    (dict(spin=1e12), "spin period"),
    (dict(integrator="rk4", h=1e-12), "below 1e-09 of the"),
    (dict(h=1e-4), "adaptive"),
    (dict(n_out=10**9), r"«n_out» .*at most 1000000"),      # the flag and its limit (issue 31)
    (dict(integrator="rk4", h=-1e-4), "step"),
    (dict(integrator="verlet"), "unknown integrator"),
    (dict(t_end=0.0), "run length"),
    (dict(box=-0.01), "box"),
    (dict(offset=1.0), "outside the box"),
])
def test_bad_options(model, kwargs, words):
    args = dict(spin=200.0, tilt=0.0, offset=0.0, t_end=0.1)
    args.update(kwargs)
    with pytest.raises(UserError, match=words):
        simulate(model, **args)


def test_cli_simulate_json(capsys):
    from levitron.runtime.cli.main import main
    rc = main(["simulate", "thesis", "--spin", "200", "--tilt", "0.01", "--t-end", "0.02", "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    for k in DESIGN_KEYS:
        assert k in out
    rc = main(["simulate", "thesis", "--spin", "200", "--tol", "-1", "--json"])
    assert rc == 2
    err = capsys.readouterr().err
    assert "tolerance" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("args, words", [
    (["--tol", "1"], "too loose"),
    (["--t-end", "1e9"], "budget cap"),
    (["--spin", "1e12"], "spin period"),
    (["--integrator", "rk4", "--step", "1e-12"], "below 1e-09"),
    (["--n-out", "1000000000"], "--n-out = 1000000000 must be at least 1 and at most 1000000"),
])
def test_cli_refuses_unbounded_work_in_one_line(capsys, args, words):
    """Each of these once ran without end, or raised MemoryError, or (--tol 1) flipped a verdict."""
    from levitron.runtime.cli.main import main
    rc = main(["simulate", "thesis", "--spin", "200", "--tilt", "0.01", *args])
    err = capsys.readouterr().err
    assert rc == 2 and words in err and len(err.strip().splitlines()) == 1


def test_the_default_run_length_scales_with_the_scene_and_sees_the_fall():
    """Without --t-end a run lasts the scan's default, 3 slow periods of the top at its hover
    height (thesis 3.3.3/3.3.5), not a fixed time unit: before, 1 s called a top spun above the
    linear interval (3500 > 2740 rad/s, its tilt grown 30-fold) levitating, and in a dimensionless
    scene (one time unit is a fraction of a bounce) so was a top spun at half sigma_lo."""
    from levitron.runtime.scan.stability_map import scan
    thesis_stable_model = load_model(load_scene("thesis_stable"))
    over = simulate(thesis_stable_model, 3500.0)
    assert over["levitating"] is False and over["t_end"] > 5.0
    inside = simulate(thesis_stable_model, 1000.0)
    assert inside["levitating"] is True
    scan_t_end = scan(thesis_stable_model, np.array([1000.0]), "tilt", np.array([0.01]),
                      quiet=True).t_end
    assert inside["t_end"] == pytest.approx(scan_t_end, rel=1e-12)


def test_cli_simulate_on_a_scene_without_the_full_model_names_both_ways(capsys):
    """A scene that models only the vertical motion: simulate (default --part full) says to pass
    --part reduced or to add "full" to model.needs; --part reduced runs."""
    from levitron.runtime.cli.main import main
    assert main(["simulate", "reduced_only", "--spin", "1000"]) == 2
    err = capsys.readouterr().err
    assert "--part reduced" in err and 'add "full" to model.needs' in err and len(err.strip().splitlines()) == 1
    assert main(["simulate", "reduced_only", "--spin", "1000", "--part", "reduced", "--t-end", "0.05", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["levitating"] is None      # on the invariant set: untested


def test_linear_context_against_the_generated_jacobian(capsys):
    """simulate's line of linear theory (thesis 3.3.9-3.3.16): inside the interval no growth; outside
    it the e-folding time of a tilt is 1 / the largest real part of the eigenvalues of the
    generated 12-D Jacobian's transverse block at the relative equilibrium (a second route to the
    8-D matrix linear_context uses), to 1e-9; the command prints it with the run's e-foldings."""
    from levitron.runtime.cli.main import main
    from levitron.runtime.physics.routes import eigen_route
    from levitron.runtime.physics.stability import analysis as stability
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.simulate.start import linear_context
    m = load_model(load_scene("thesis_stable"))
    z_s = hover_height(m, m.p)
    _, jac, states = stability.model_callables(m, m.p)
    inside = linear_context(m, m.p, z_s, 1000.0)
    lo, hi = inside["spin_interval"]
    assert inside["inside"] and inside["e_folding_time"] is None and 459 < lo < 460 < 2739 < hi < 2740
    for spin in (0.9 * lo, 1.02 * hi):
        lin = linear_context(m, m.p, z_s, spin)
        x_eq = eigen_route.full_equilibrium_state(states, z_s, m.param("C"), spin)
        gamma = eigen_route.growth_rate(eigen_route.transverse_block(jac(x_eq), states))
        assert not lin["inside"] and lin["e_folding_time"] == pytest.approx(1 / gamma, rel=1e-9)
    assert main(["simulate", "thesis_stable", "--spin", "2800", "--t-end", "2"]) == 0
    out = capsys.readouterr().out
    assert "linear theory: 2800 rad/s lies above the stable interval 459.6-2740 rad/s: a tilt grows by e every" in out
    assert main(["simulate", "thesis_stable", "--spin", "1000", "--t-end", "0.5", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["linear"]["inside"] is True


def test_a_run_that_stops_early_gives_no_verdict():
    """runtime/integrate/verdict.py: a run that ends before t_end for another reason than the top
    leaving its box (here the z-x-z chart started exactly upright, tilt 0, off the axis by 1e-4 m
    so that the launch is not the invariant set: its 1/sin theta is infinite, status nonfinite;
    before the cancellation-free form, derive/zxz_form.py, a tilt of 1e-8 used up the step budget,
    and now completes) says nothing of the top: simulate answers levitating None with the reason,
    not 'no'; simulate_many marks it untested, the same answer; the verdicts of the other statuses."""
    import levitron as lev
    from levitron.runtime.integrate.verdict import no_verdict_reason, stopped_early, verdict
    assert (verdict("completed"), verdict("left_box"), verdict("step_budget"), verdict("nonfinite")) == \
        (True, False, None, None)
    assert stopped_early("step_budget") and not stopped_early("no_hover_height") and not stopped_early("")
    st = lev.load("thesis_stable", {"model.coordinates": "euler-zxz"})
    one = st.simulate(1000.0, tilt=0.0, offset=1e-4, t_end=0.01)
    assert one.details["status"] == "nonfinite" and one.levitating is None
    assert one.details["untested"] == no_verdict_reason("nonfinite", one.details["message"])
    many = st.simulate_many([1000.0, 1000.0], tilt=[0.0, 0.01], offset=[1e-4, 1e-4], t_end=0.01)
    assert many.untested.tolist() == [True, False] and many.status.tolist() == ["nonfinite", "completed"]
    assert (None if many.untested[0] else bool(many.levitating[0])) == one.levitating
