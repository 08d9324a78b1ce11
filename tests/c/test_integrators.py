"""The C integrators (runtime/csrc/integrators.c) on model-independent test systems (tests/c/systems.c,
runtime/csrc/circle.c): convergence orders measured by slopes, DOP853 against scipy's, dense output, the box event,
non-finite states, bounded energy of the symplectic method, bad options, concurrency."""
from __future__ import annotations

import itertools
import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.run import Box, CSystem, integrate, run_c

TWO_PI = 2.0 * math.pi


@pytest.fixture(scope="module")
def circle(lib):
    return CSystem(lib, "lev_circle", ["x", "y", "vx", "vy"], [0.0])


@pytest.fixture(scope="module")
def kepler(lib):
    return CSystem(lib, "lev_kepler", ["x", "y", "vx", "vy"], [1.0])


def kepler_x0(e):
    """Periapsis of an orbit of eccentricity e, semi-major axis 1, GM = 1 (period 2 pi)."""
    return np.array([1.0 - e, 0.0, 0.0, math.sqrt((1.0 + e) / (1.0 - e))])


def slope(xs, ys):
    return float(np.polyfit(np.log(xs), np.log(ys), 1)[0])


def final_errors(system, x0, method, steps, turns=1.0):
    x0 = np.asarray(x0, float)
    errs = []
    for n in steps:
        r = integrate(system, x0, TWO_PI * turns, method=method, h=TWO_PI * turns / n)
        assert r.status == "completed" and r.steps == n
        errs.append(np.abs(r.x_final - x0).max())    # the orbit closes after whole turns
    return np.array(errs)


def test_eq_3_1_2_euler_order_1(circle):
    """Thesis eq. 3.1.2 / 3.1.7: Euler's global error is O(h)."""
    steps = [400, 800, 1600, 3200]
    errs = final_errors(circle, [1, 0, 0, 1], "euler", steps)
    assert slope(1.0 / np.array(steps), errs) == pytest.approx(1.0, abs=0.08)


def test_eq_3_1_3_rk4_order_4(circle):
    """Thesis eqs. 3.1.3-3.1.4: classical RK4, local error O(h^5), global O(h^4)."""
    steps = [50, 100, 200, 400]
    errs = final_errors(circle, [1, 0, 0, 1], "rk4", steps)
    assert slope(1.0 / np.array(steps), errs) == pytest.approx(4.0, abs=0.1)


def test_dop853_order_8_on_kepler(kepler):
    """The 8th-order DOP853 formula at a fixed step on a nonlinear problem (Kepler, e = 0.3)."""
    steps = [60, 80, 120, 160]
    errs = final_errors(kepler, kepler_x0(0.3), "dop853-fixed", steps)
    assert errs[-1] > 1e-13                           # still above round-off: the slope is meaningful
    assert slope(1.0 / np.array(steps), errs) == pytest.approx(8.0, abs=0.5)


def test_gauss4_order_4_and_midpoint_order_2(kepler):
    steps = [100, 200, 400]
    e4 = final_errors(kepler, kepler_x0(0.3), "gauss4", steps)
    e2 = final_errors(kepler, kepler_x0(0.3), "midpoint", steps)
    assert slope(1.0 / np.array(steps), e4) == pytest.approx(4.0, abs=0.15)
    assert slope(1.0 / np.array(steps), e2) == pytest.approx(2.0, abs=0.1)


def adaptive_runs(kepler, method, x0, tols):
    """Errors after three closed Kepler orbits and rhs calls of an adaptive method, per tolerance;
    the errors fall strictly as the tolerance tightens."""
    errs, work = [], []
    for tol in tols:
        r = run_c(kepler.lib, method, kepler.c_function("rhs"), x0, kepler.p, 3 * TWO_PI,
                  rtol=tol, atol=tol)
        assert r.status == "completed" and r.t_final == 3 * TWO_PI
        errs.append(np.abs(r.x_final - x0).max())
        work.append(r.rhs_evals)
    assert all(a > b for a, b in itertools.pairwise(errs))
    return errs, work


def test_dop853_adaptive_work_precision_slope(kepler):
    """Adaptive DOP853 on the circular Kepler orbit: the error falls like (rhs calls)^-8 as the
    tolerance tightens, and is proportional to the tolerance (one decade per decade)."""
    tols = [1e-8, 1e-9, 1e-10, 1e-11, 1e-12, 1e-13]
    errs, work = adaptive_runs(kepler, "dop853", kepler_x0(0.0), tols)
    assert slope(work, errs) == pytest.approx(-8.0, abs=0.6)
    assert slope(tols, errs) == pytest.approx(1.0, abs=0.1)


def test_dop853_reproduces_scipy_step_sequence(kepler):
    """Same coefficients, error norm, step control and initial step as scipy's DOP853: the same
    number of right-hand-side calls and the same answer to round-off."""
    from scipy.integrate import solve_ivp
    x0 = kepler_x0(0.6)
    for tol in [1e-6, 1e-10]:
        r = run_c(kepler.lib, "dop853", kepler.c_function("rhs"), x0, kepler.p, 2 * TWO_PI,
                  rtol=tol, atol=tol)
        s = solve_ivp(lambda t, x: kepler.rhs(x), (0, 2 * TWO_PI), x0, method="DOP853",
                      rtol=tol, atol=tol)
        assert r.rhs_evals == s.nfev
        assert np.abs(r.x_final - s.y[:, -1]).max() < 1e-11


def test_dop853_dense_output(osc):
    """Samples at times that are not step ends come from the 7th-degree interpolant: they match
    the exact circle x = cos t, y = sin t to the tolerance."""
    t_out = np.sort(np.random.default_rng(1).uniform(0, 10, 57))
    t_out = np.concatenate([[0.0], t_out, [10.0]])
    r = run_c(osc.lib, "dop853", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 10.0,
              rtol=1e-11, atol=1e-11, t_out=t_out)
    assert r.status == "completed" and r.steps < len(t_out)   # most samples fall inside steps
    np.testing.assert_array_equal(r.t, t_out)
    exact = np.c_[np.cos(t_out), np.sin(t_out), -np.sin(t_out), np.cos(t_out)]
    assert np.abs(r.X - exact).max() < 1e-9


def test_event_stops_at_box_exit_cleanly(lib):
    """A top that flies off: x'' = +x (unstable) from x = 0.1 leaves the box x <= 1 at
    t = acosh(10); the event stops there, nothing is NaN."""
    fly = CSystem(lib, "lev_oscillator", ["x", "y", "vx", "vy"], [-1.0])
    box = Box(iz=0, z_lo=-1.0, z_hi=1.0)
    r = integrate(fly, [0.1, 0, 0, 0], 10.0, method="dop853", tol=1e-11, box=box, n_out=10,
                  scale=[1, 1, 1, 1])
    assert r.status == "left_box"
    assert r.t_final == pytest.approx(math.acosh(10.0), abs=1e-8)
    assert r.x_final[0] == pytest.approx(1.0, abs=1e-9) and r.x_final[0] > 1.0 - 1e-12
    assert np.all(np.isfinite(r.X)) and np.all(np.isfinite(r.x_final))
    assert r.t[-1] == r.t_final and np.all(np.diff(r.t) > 0)
    for m in ["rk4", "gauss4"]:
        rf = integrate(fly, [0.1, 0, 0, 0], 10.0, method=m, h=1e-3, box=box)
        assert rf.status == "left_box" and np.isfinite(rf.x_final).all()
        assert rf.t_final == pytest.approx(math.acosh(10.0), abs=2e-3)


def test_event_radial_box(kepler):
    """The radial limit sqrt(x^2 + y^2) <= r_max stops an eccentric orbit on its way out."""
    box = Box(iz=-1, z_lo=-math.inf, z_hi=math.inf, ix=0, iy=1, r_max=1.2)
    r = integrate(kepler, kepler_x0(0.6), 10.0, method="dop853", tol=1e-10, box=box,
                  scale=[1, 1, 1, 1])
    assert r.status == "left_box"
    assert math.hypot(r.x_final[0], r.x_final[1]) == pytest.approx(1.2, abs=1e-9)
    assert 0 < r.t_final < math.pi              # before the apoapsis at t = pi


def test_nonfinite_state_stops_cleanly(lib):
    """x' = x^2 blows up at t = 1: every method stops with the last finite state, no NaN."""
    b = CSystem(lib, "lev_blowup", ["x"], [0.0])
    r = integrate(b, [1.0], 2.0, method="dop853", tol=1e-10)
    assert r.status in ("nonfinite", "step_underflow")
    assert r.t_final == pytest.approx(1.0, abs=1e-6) and np.isfinite(r.x_final).all()
    for m in ["euler", "rk4", "gauss4"]:
        r = integrate(b, [1.0], 2.0, method=m, h=0.01)
        assert r.status in ("nonfinite", "no_convergence"), m
        assert 0.9 < r.t_final < 1.5 and np.isfinite(r.x_final).all() and np.isfinite(r.X).all()


def test_gauss4_energy_bounded_rk4_drifts(kepler):
    """Over 2e5 steps (1000 orbits, e = 0.6, 200 steps/orbit) the symplectic Gauss-Legendre
    method's energy error stays bounded (the same maximum in every tenth of the run, monitored
    after every step in C), while RK4's grows linearly in time."""
    h = TWO_PI / 200
    n = 200_000
    out = {}
    for m in ["gauss4", "rk4"]:
        r = run_c(kepler.lib, m, kepler.c_function("rhs"), kepler_x0(0.6), kepler.p, n * h, h=h,
                  jac=kepler.c_function("jac"), energy=kepler.c_function("energy"), every=100,
                  max_samples=n // 100 + 3)
        assert r.status == "completed" and r.steps == n
        out[m] = (r.t, np.abs(r.energy - r.energy0), r.energy_max_dev)
    t, dev, maxdev = out["gauss4"]
    tenths = np.array_split(dev, 10)
    assert max(c.max() for c in tenths[5:]) <= 1.05 * max(c.max() for c in tenths[:5])
    assert maxdev < 1e-6
    t, dev, maxdev = out["rk4"]
    tenths = [c.max() for c in np.array_split(dev, 10)]
    assert tenths[-1] > 5 * tenths[0]                # drift, not oscillation
    assert maxdev > 100 * out["gauss4"][2]


def test_gauss4_fixed_point_equals_newton(kepler):
    """Both stage solvers converge to round-off: the same trajectory to ~1e-13."""
    x0 = kepler_x0(0.5)
    a = run_c(kepler.lib, "gauss4", kepler.c_function("rhs"), x0, kepler.p, TWO_PI, h=TWO_PI / 300,
              jac=kepler.c_function("jac"))
    b = run_c(kepler.lib, "gauss4", kepler.c_function("rhs"), x0, kepler.p, TWO_PI, h=TWO_PI / 300)
    assert 1 <= a.jac_evals <= 300 and b.jac_evals == 0
    assert np.abs(a.x_final - b.x_final).max() < 1e-12


def test_sampling_every_kth_step(osc):
    r = integrate(osc, [1, 0, 0, 1], 1.0, method="rk4", h=1e-3, n_out=10)
    np.testing.assert_allclose(r.t, np.linspace(0, 1, 11), atol=1e-12)
    assert r.X.shape == (11, 4) and r.rhs_evals == 4000
    np.testing.assert_allclose(r.X[:, 0], np.cos(r.t), atol=1e-12)


def test_step_budget_status(osc):
    """The budget counts attempted steps (accepted + rejected) and stops the run cleanly."""
    r = run_c(osc.lib, "dop853", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 100.0, rtol=1e-12,
              atol=1e-12, max_steps=5)
    assert r.status == "step_budget" and r.steps + r.rejected == 5 and 0 < r.t_final < 100
    assert "step budget" in r.message
    assert np.isfinite(r.x_final).all()


@pytest.mark.parametrize("kwargs, words", [
    (dict(method="dop853", tol=-1e-8), "tolerance"),
    (dict(method="dop853", tol=0.0), "tolerance"),
    (dict(method="rk4", h=-1e-3), "step"),
    (dict(method="rk4", h=0.0), "step"),
    (dict(method="rk4"), "step"),
    (dict(method="leapfrog", tol=1e-8), "unknown integrator"),
    (dict(method="dop853", tol=1e-8, t_end=0.0), "run length"),
    (dict(method="dop853", tol=1e-8, t_end=-1.0), "run length"),
    (dict(method="dop853", tol=1.0), "too loose"),
    (dict(method="dop853", tol=0.05), "too loose"),
    (dict(method="dop853", tol=1e-17), "below double precision"),
    (dict(method="dop853", tol=1e-8, h=1e-3), "adaptive"),
    (dict(method="dop853", tol=1e-8, n_out=10**9), "n_out"),
    (dict(method="dop853", tol=1e-8, max_steps=0), "max_steps"),
    (dict(method="rk4", h=1e-8, t_end=1.0), "budget"),
])
def test_bad_options_raise_user_error(osc, kwargs, words):
    t_end = kwargs.pop("t_end", 1.0)
    with pytest.raises(UserError, match=words):
        integrate(osc, [1, 0, 0, 1], t_end, **kwargs)


def test_bad_input_status_from_c(osc):
    """The C validates too (e.g. a caller that bypasses integrate())."""
    r = run_c(osc.lib, "rk4", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 1.0, h=-1.0)
    assert r.status == "bad_input"
    for method, kw in (("rk4", dict(h=1e-3)), ("dop853", dict(rtol=1e-8, atol=1e-8))):
        r = run_c(osc.lib, method, osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 1.0, max_steps=0, **kw)
        assert r.status == "bad_input", "no run without a step budget"


def test_concurrent_runs_are_independent(kepler):
    """No global state in C: runs in parallel threads (ctypes drops the GIL) equal serial runs."""
    def run(e):
        r = run_c(kepler.lib, "dop853", kepler.c_function("rhs"), kepler_x0(e), kepler.p,
                  5 * TWO_PI, rtol=1e-10, atol=1e-10)
        return r.x_final, r.rhs_evals
    es = [0.1, 0.3, 0.5, 0.7] * 2
    serial = [run(e) for e in es]
    with ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(run, es))
    for (xs, ns), (xp, np_) in zip(serial, parallel):
        assert ns == np_ and np.array_equal(xs, xp)


def test_casadi_and_scipy_backends_on_the_oscillator(lib):
    """cvodes / casadi-rk / scipy-dop853 through the same `integrate` (a CasADi rhs built here)."""
    import casadi as ca

    class Osc(CSystem):
        def casadi(self, name):
            x, p = ca.SX.sym("x", 4), ca.SX.sym("p", 1)
            return ca.Function("rhs", [x, p], [ca.vertcat(x[2], x[3], -p[0] * x[0], -p[0] * x[1])])

    sys_ = Osc(lib, "lev_oscillator", ["x", "y", "vx", "vy"], [1.0])
    x0 = np.array([1.0, 0, 0, 1])
    for method, kw, bound in [("cvodes", dict(tol=1e-10), 1e-7), ("casadi-rk", dict(h=1e-2), 1e-8),
                              ("casadi-collocation", dict(h=1e-2), 1e-7),
                              ("scipy-dop853", dict(tol=1e-10), 1e-8)]:
        r = integrate(sys_, x0, TWO_PI, method=method, n_out=20, scale=[1, 1, 1, 1], **kw)
        assert r.status == "completed", (method, r.message)
        assert np.abs(r.x_final - x0).max() < bound, method
        assert len(r.t) == 21 and r.t[-1] == pytest.approx(TWO_PI)


@pytest.mark.parametrize("method, engine", [("scipy-dop853", "DOP853"), ("scipy-radau", "Radau"),
                                            ("scipy-lsoda", "LSODA")])
def test_scipy_stepper_equals_solve_ivp(osc, method, engine):
    """The budgeted scipy loop (runtime/integrate/scipy_backend.py) is solve_ivp's: the same samples and the
    same box exit (event root)."""
    from scipy.integrate import solve_ivp
    x0 = np.array([1.0, 0.0, 0.0, 1.0])
    box = Box(iz=1, z_lo=-2.0, z_hi=0.5)          # y = sin t leaves at t = pi / 6

    def leave(t, x):
        return -box.excess(x)
    leave.terminal, leave.direction = True, -1
    for b, events in ((None, None), (box, [leave])):
        r = integrate(osc, x0, 10.0, method=method, tol=1e-9, n_out=20, box=b, scale=[1, 1, 1, 1])
        s = solve_ivp(lambda t, x: osc.rhs(x), (0.0, 10.0), x0, method=engine, rtol=1e-9, atol=1e-9,
                      t_eval=np.linspace(0.0, 10.0, 21), events=events)
        k = len(s.t)
        np.testing.assert_array_equal(r.t[:k], s.t)
        np.testing.assert_array_equal(r.X[:k], s.y.T)
        if b is None:
            assert r.status == "completed" and k == len(r.t)
        else:
            assert r.status == "left_box"
            assert r.t_final == pytest.approx(s.t_events[0][0], rel=1e-14)
            assert r.t_final == pytest.approx(math.pi / 6, rel=1e-7)


def vern9_fixed_errors(kepler, x0, steps):
    """Verner 9(8) held at a fixed step: the tolerance is loose enough that every step is accepted
    and h_max (= the initial step h) caps it, so the run takes exactly n steps of 2 pi / n."""
    errs = []
    for n in steps:
        h = TWO_PI / n
        r = run_c(kepler.lib, "vern9", kepler.c_function("rhs"), x0, kepler.p, TWO_PI,
                  rtol=1e-2, atol=1e-2, h=h, h_max=h * (1 + 1e-12))
        assert r.status == "completed" and r.steps == n and r.rejected == 0
        assert r.rhs_evals == 16 * n + 1                  # 16 per step, and rhs(x0)
        errs.append(np.abs(r.x_final - x0).max())
    return np.array(errs)


def test_vern9_order_9_on_kepler(kepler):
    """Verner's 9(8) pair (its 9th-order solution) on a nonlinear problem with a known solution:
    the Kepler orbit (e = 0.5) closes after one period; the global error falls like h^9. The steps
    keep the error far above round-off (>= 1e-9): with compensated summation the finer steps
    80..160 show the pair's small 9th-order constant (local slopes 9.5-9.6), and without it
    their slope was held near 9 by round-off alone."""
    steps = [30, 40, 50, 60]
    errs = vern9_fixed_errors(kepler, kepler_x0(0.5), steps)
    assert errs[-1] > 1e-9                            # far above round-off
    assert slope(1.0 / np.array(steps), errs) == pytest.approx(9.0, abs=0.5)


def test_vern9_adaptive_tracks_the_tolerance(kepler):
    """Adaptive Verner 9(8) on an eccentric orbit: the error is proportional to the tolerance and
    falls like (rhs calls)^-9."""
    tols = [1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
    errs, work = adaptive_runs(kepler, "vern9", kepler_x0(0.6), tols)
    assert slope(work, errs) == pytest.approx(-9.0, abs=1.2)
    assert slope(tols, errs) == pytest.approx(1.0, abs=0.15)


def test_vern9_dense_output(osc):
    """Samples inside steps come from a Verner step of theta h: they match the exact circle."""
    t_out = np.sort(np.random.default_rng(2).uniform(0, 10, 41))
    t_out = np.concatenate([[0.0], t_out, [10.0]])
    r = run_c(osc.lib, "vern9", osc.c_function("rhs"), [1, 0, 0, 1], osc.p, 10.0,
              rtol=1e-12, atol=1e-12, t_out=t_out)
    assert r.status == "completed" and r.steps < len(t_out)
    np.testing.assert_array_equal(r.t, t_out)
    exact = np.c_[np.cos(t_out), np.sin(t_out), -np.sin(t_out), np.cos(t_out)]
    assert np.abs(r.X - exact).max() < 1e-10


def test_vern9_box_event(lib, kepler):
    """The box event on the dense output: the unstable oscillator leaves x <= 1 at acosh(10);
    the eccentric orbit crosses r = 1.2 before its apoapsis."""
    fly = CSystem(lib, "lev_oscillator", ["x", "y", "vx", "vy"], [-1.0])
    r = integrate(fly, [0.1, 0, 0, 0], 10.0, method="vern9", tol=1e-11,
                  box=Box(iz=0, z_lo=-1.0, z_hi=1.0), n_out=10, scale=[1, 1, 1, 1])
    assert r.status == "left_box"
    assert r.t_final == pytest.approx(math.acosh(10.0), abs=1e-8)
    assert r.x_final[0] == pytest.approx(1.0, abs=1e-9) and np.isfinite(r.X).all()
    assert r.t[-1] == r.t_final and np.all(np.diff(r.t) > 0)
    box = Box(iz=-1, z_lo=-math.inf, z_hi=math.inf, ix=0, iy=1, r_max=1.2)
    r = integrate(kepler, kepler_x0(0.6), 10.0, method="vern9", tol=1e-10, box=box,
                  scale=[1, 1, 1, 1])
    assert r.status == "left_box" and 0 < r.t_final < math.pi
    assert math.hypot(r.x_final[0], r.x_final[1]) == pytest.approx(1.2, abs=1e-9)


def test_compensated_summation_keeps_a_growing_angle_to_round_off(lib):
    """x' = w, the top's spin angle in miniature: every method integrates it exactly, so only the
    rounding of x + increment is left. 10^5 steps carry x from 1 to 1001: summed naively (as numpy's
    sequential cumsum does) the increments lose 7.7e-10, about 6700 ulp; with the compensated
    summation of integrators.c every method ends within 8 ulp of the exact sum (measured: euler,
    rk4, midpoint 0, gauss4 and vern9 1, the DOP853 formula 6-7: its weights sum to 1 only to
    within a few 1e-16, which is its slope's own rounding, not the summation's)."""
    from fractions import Fraction
    drift = CSystem(lib, "lev_drift", ["x"], [1.0 / 3.0])
    w, T, N = 1.0 / 3.0, 3000.0, 100_000
    h = T / N
    exact = float(1 + Fraction(w) * Fraction(h) * N)
    ulp = float(np.spacing(exact))
    naive = float(np.cumsum(np.r_[1.0, np.full(N, h * w)])[-1])
    assert abs(naive - exact) > 1000 * ulp                 # the test can tell the two apart
    runs = {m: run_c(lib, m, drift.c_function("rhs"), [1.0], drift.p, T, h=h)
            for m in ("euler", "rk4", "dop853-fixed", "gauss4", "midpoint")}
    runs.update({m: run_c(lib, m, drift.c_function("rhs"), [1.0], drift.p, T, rtol=1e-12,
                          atol=1e-12, h=h, h_max=h) for m in ("dop853", "vern9")})
    for m, r in runs.items():
        assert r.status == "completed" and r.steps == N, (m, r.status, r.steps)
        assert abs(r.x_final[0] - exact) <= 8 * ulp, (m, (r.x_final[0] - exact) / ulp)


def test_default_scale_takes_a_rounding_s_zero_for_a_zero():
    """A start of 1e-28 beside 0.03 and 1 is a zero: it gets the smallest real size (0.03), not its
    own 1e-28, which asked dop853 for an error of 1e-40 on a periodic orbit's zeta (issue 27)."""
    from levitron.runtime.integrate.run import default_scale
    got = default_scale(np.array([0.03, 1e-28, -1.0, 0.0, 2e-3]))
    assert list(got) == [0.03, 2e-3, 1.0, 2e-3, 2e-3]
    assert list(default_scale(np.zeros(3))) == [1.0, 1.0, 1.0]
