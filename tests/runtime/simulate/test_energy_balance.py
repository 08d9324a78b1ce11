"""The energy balance of a run in air measures the integration (issue 31, D6): the work of friction
W(t) = integral of 2F dt is integrated inside the run as one more state (integrators.h's
lev_system.quad in C; the extended right-hand side in CasADi and scipy; runtime/integrate/run.py's
`quadrature`), so E(t) - E(0) + W(t) = 0 up to the integration's error. It used to be a trapezoid
over the output samples: at --n-out 50 its residual stayed at 8e-9 whatever the tolerance."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.runtime.integrate.run import integrate
from levitron.runtime.physics.equilibrium.finder import hover_height
from levitron.runtime.physics.apparatus.friction import energy_scale
from levitron.runtime.simulate.run import simulate
from levitron.runtime.simulate.start import initial_state, state_scales

STRONG = {"k_spin": 0.5, "k_tilt": 2.0, "k_trans": 1.0}   # a good part of the energy lost in 2 s


def strong_run(air, method, tol=None, h=None, n_out=40, t_end=2.0):
    """A run of thesis_air with STRONG friction and W integrated beside it; (Result, H, H0)."""
    pt = air.part("full")
    p = air.with_params(STRONG)
    pv = air.pvals(p)
    z_s = hover_height(air, p)
    x0 = initial_state(pt, z_s, 1500.0, 0.02, 0.001, p)
    H0 = pt.energy(x0, p)
    size = energy_scale(pv, z_s, 1500.0, H0)
    r = integrate(pt, x0, t_end, method=method, tol=tol, h=h, p=p, n_out=n_out,
                  scale=state_scales(pt, z_s, 1500.0, pv), quadrature=("dissipation", size))
    assert r.status == "completed", (method, r.status, r.message)
    H = air.rows("full_energy", r.X, p)[:, 0]
    return r, H, H0


@pytest.mark.parametrize("method,tol,h,bound", [
    ("dop853", 1e-12, None, 1e-13), ("vern9", 1e-12, None, 1e-13), ("cvodes", 1e-10, None, 1e-10),
    ("scipy-dop853", 1e-11, None, 1e-12), ("rk4", None, 2e-5, 1e-14), ("gauss4", None, 2e-5, 1e-14)])
def test_work_integrated_in_the_run_balances_the_energy_lost(air, method, tol, h, bound):
    """Every backend (C adaptive, C fixed-step, C implicit with the generated Jacobian, CasADi
    CVODES, scipy): W(t) equals the energy lost, E(0) - E(t), to `bound` of the energy lost at
    every sample; the loss is real (a third of the rotational energy and more). Measured: dop853
    7.3e-15, vern9 5.7e-15 (tol 1e-12), cvodes 7.5e-12 (1e-10), scipy-dop853 9.9e-14 (1e-11), rk4
    and gauss4 4.3e-16 at h = 2e-5 s (rk4 1.3e-14 at 4e-5 s: order 4-5)."""
    r, H, H0 = strong_run(air, method, tol, h)
    lost = H0 - H
    assert r.work.shape == H.shape and r.work[0] == 0.0 and r.X.shape[1] == len(air.part("full").states)
    assert lost[-1] > 0.3 * 0.5 * air.pvals()["C"] * 1500.0 ** 2
    assert np.abs(r.work - lost).max() <= bound * lost[-1], np.abs(r.work - lost).max() / lost[-1]
    assert r.work_final == r.work[-1]


@pytest.mark.parametrize("method", ["dop853", "vern9"])
def test_the_quadrature_does_not_steer_the_steps(air, method):
    """In C the work W is left out of the adaptive step's error norm (as CVODES leaves out its
    quadratures): the run with it takes the same steps and gives the same states, bit for bit, as
    the run without it, so the balance measures the integration simulate runs anyway."""
    pt = air.part("full")
    p = air.with_params(STRONG)
    pv = air.pvals(p)
    z_s = hover_height(air, p)
    x0 = initial_state(pt, z_s, 1500.0, 0.02, 0.001, p)
    kw = dict(method=method, tol=1e-10, p=p, n_out=40, scale=state_scales(pt, z_s, 1500.0, pv))
    plain = integrate(pt, x0, 2.0, **kw)
    with_work = integrate(pt, x0, 2.0, quadrature=("dissipation", 1.0), **kw)
    assert plain.work is None and with_work.work is not None
    assert (plain.steps, plain.rejected) == (with_work.steps, with_work.rejected)
    np.testing.assert_array_equal(plain.X, with_work.X)
    np.testing.assert_array_equal(plain.x_final, with_work.x_final)


def test_the_c_quadrature_equals_scipys_with_the_same_extended_system(air):
    """A second route to W: scipy's DOP853 (solve_ivp's method, stepped in Python) over
    [rhs, full_dissipation] against the C DOP853's quadrature, both at tol 1e-12: the same W(t)
    to 1e-11 of the energy lost."""
    rc, _, _ = strong_run(air, "dop853", 1e-12)
    rs, _, _ = strong_run(air, "scipy-dop853", 1e-12)
    assert np.array_equal(rc.t, rs.t)
    assert np.abs(rc.work - rs.work).max() <= 1e-11 * rc.work[-1]


def test_the_residual_falls_with_the_tolerance(air):
    """simulate thesis_air --spin 1000 --t-end 5: the balance's residual falls with --tol
    (measured 4.4e-8, 8.7e-10, 5.1e-12, 2.8e-14 at 1e-6, 1e-8, 1e-10, 1e-12), each below a tenth of
    its tolerance and each at least 10 times below the one before."""
    res = []
    for tol in (1e-6, 1e-8, 1e-10, 1e-12):
        out = simulate(air, spin=1000.0, t_end=5.0, tol=tol, n_out=50, integrator="dop853")
        assert out["status"] == "completed"
        res.append(out["flight"]["energy_balance"])
        assert res[-1] < 0.1 * tol, (tol, res)
        assert out["energy_drift"] == res[-1]
    assert all(b < 0.1 * a for a, b in zip(res, res[1:])), res


def test_the_residual_does_not_depend_on_n_out(air):
    """The grid of --n-out 50 is every 40th point of --n-out 2000's, and the steps are the same
    (the dense output does not steer them): W and E at the common samples are the same numbers
    (to the ulp by which the grids' common times differ), the residual over 2000 samples is at
    most 1.5 times the one over 50, and at 50 samples it is no longer the quadrature's error of
    the samples (8.3e-9 at tol 1e-10 and 1e-12 before; measured now 5.1e-12 and 5.2e-12)."""
    pt = air.part("full")
    p = air.p
    pv = air.pvals(p)
    z_s = hover_height(air, p)
    x0 = initial_state(pt, z_s, 1000.0, 0.005, 0.0, p)
    size = energy_scale(pv, z_s, 1000.0, pt.energy(x0, p))
    runs = [integrate(pt, x0, 5.0, method="dop853", tol=1e-10, p=p, n_out=n,
                      scale=state_scales(pt, z_s, 1000.0, pv), quadrature=("dissipation", size))
            for n in (50, 2000)]
    coarse, fine = runs
    assert coarse.steps == fine.steps
    # linspace's two grids differ by an ulp at some common times, hence 1e-14, not equality
    np.testing.assert_allclose(coarse.t, fine.t[::40], rtol=1e-15, atol=0)
    np.testing.assert_allclose(coarse.work, fine.work[::40], rtol=1e-14, atol=0)
    H = [air.rows("full_energy", r.X, p)[:, 0] for r in runs]
    np.testing.assert_allclose(H[0], H[1][::40], rtol=1e-14, atol=0)
    a = simulate(air, spin=1000.0, t_end=5.0, tol=1e-10, n_out=50, integrator="dop853")
    b = simulate(air, spin=1000.0, t_end=5.0, tol=1e-10, n_out=2000, integrator="dop853")
    ra, rb = a["flight"]["energy_balance"], b["flight"]["energy_balance"]
    assert ra <= rb <= 1.5 * ra and rb < 1e-11, (ra, rb)


def test_a_quadrature_is_refused_by_the_taylor_method(air):
    """Taylor's method runs the generated coefficients of the state only: asked for a quadrature it
    says so (a UserError naming the methods that do), it does not run without one."""
    from levitron.runtime.errors import UserError
    pt = air.part("reduced")
    x0 = np.array([0.1, 0.0, 0.0, 1e-3])
    with pytest.raises(UserError, match="no quadrature"):
        integrate(pt, x0, 0.1, method="taylor", tol=1e-10, quadrature=("energy", 1.0))
