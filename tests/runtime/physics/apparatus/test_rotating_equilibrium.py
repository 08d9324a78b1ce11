"""The tilted magnet's steady motion as a relative equilibrium in the frame turning about the
vertical (runtime/physics/apparatus/rotating_equilibrium.py), against independent routes.

- Route "Floquet" by shooting (runtime/physics/apparatus/multipliers.py, CVODES at 1e-12 and the monodromy
  matrix): at three moment tilts on thesis_stable each end of the relative equilibrium's window is
  bracketed by the shooting's verdicts a relative DELTA inside (stable) and outside (unstable), the
  orbit's start there is the relative equilibrium and its multipliers are exp(T lambda).
- The C integrator (dop853 on the generated full_rhs): from the relative equilibrium the top comes
  back after one period with zeta advanced by 2 pi, i.e. it turns rigidly about the vertical.
- At moment tilt 0 the window is the aligned top's eigen route's interval and exp(T lambda) its
  multipliers.
- The route refuses where the rotation about the vertical is no symmetry (a tilted base, a plate
  with four-fold symmetry only) and moment_tilt.py then shoots.
- max_moment_tilt by the relative equilibrium: a window exists there and none 0.5 % above it.
"""
from __future__ import annotations

import math
import types

import numpy as np
import pytest

from levitron.runtime.physics.apparatus import multipliers as fl
from levitron.runtime.physics.apparatus import moment_tilt as fs
from levitron.runtime.physics.apparatus import rotating_equilibrium as req

# The shooting's window ends are bisected to fl.SPIN_RTOL = 1e-7 and the relative equilibrium's to
# req.SPIN_RTOL = 1e-9; the two verdicts differ only in their tolerance on the real parts (the
# shooting's | |mu| - 1 | <= 1e-6, the eigen route's rounding bound), which moves an end where a pair
# of eigenvalues leaves the imaginary axis (|Re lambda| ~ sqrt(distance)) by ~(1e-6 / 2 pi)^2 ~ 3e-14
# relative. So the shooting must give the verdict of the relative equilibrium's window already at
# the shooting's own resolution: DELTA = fl.SPIN_RTOL inside and outside each end.
DELTA = fl.SPIN_RTOL


@pytest.fixture(scope="module")
def model(derived_model):
    return derived_model("thesis_stable", "top.moment_tilt=0.05")


@pytest.fixture(scope="module")
def aligned(model):
    from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis
    return tilted_analysis(model, model.with_params({"moment_tilt": 0.0}))


def z_magnet(model, aligned):
    return aligned.equilibrium["z_level"] + model.pvals().get("moment_offset", 0.0)


def rotating(model, aligned, b, **kw):
    return req.RotatingTop(model, model.with_params({"moment_tilt": b}), z_magnet(model, aligned), **kw)


def windows(rt, aligned):
    return [w for w in rt.windows(fs.probes_for(rt, aligned.spin_interval)) if w[0] > 0]


@pytest.mark.parametrize("b", [0.01, 0.05, 0.15])
def test_the_window_is_the_floquet_shooting_s(model, aligned, b):
    rt = rotating(model, aligned, b)
    got = windows(rt, aligned)
    assert len(got) == 1, got
    lo, hi = got[0]
    assert aligned.spin_interval[0] < lo < hi < aligned.spin_interval[1]    # the tilt narrows it
    ft = fl.FloquetTop(model, model.with_params({"moment_tilt": b}), z_magnet(model, aligned))
    for end, inward in ((lo, 1), (hi, -1)):
        inside = end * (1 + inward * DELTA)
        c = ft.check(inside)
        assert c.stable, (b, end, c.deviation)
        # the orbit's start is the relative equilibrium, the multipliers are exp(T lambda)
        orbit, x = ft.orbit(inside), rt.solve(inside)
        assert np.max(np.abs((orbit.x0 - x) / orbit.scales)) <= 1e-8
        want, mu = rt.check(inside).multipliers, c.multipliers
        for w in want:
            k = int(np.argmin(np.abs(mu - w)))
            assert abs(mu[k] - w) <= 1e-6, (inside, w, mu[k])     # (two meet at the end: ill conditioned)
            mu = np.delete(mu, k)
        assert not ft.stable(end * (1 - inward * DELTA)), (b, end)


def test_the_critical_point_s_residual_is_rounding(model, aligned):
    rt = rotating(model, aligned, 0.05)
    for sigma in (500.0, 1100.0, 2600.0):
        c = rt.check(sigma)
        assert c.residual <= 1e-14 and c.kept <= 1e-14, (sigma, c.residual, c.kept)
        # grad H = -sigma grad L_z: the generated flow is the rotation about the vertical
        f = np.asarray(model.call("full_rhs", c.state, rt.p), float).ravel()
        xi = rt.fn.Jsym @ np.asarray(rt.fn.A(c.state, sigma, rt.p)[1]).ravel()
        s = rt.scales(sigma)
        assert np.max(np.abs((f + sigma * xi) / s)) <= 1e-10 * sigma


def test_the_c_integrator_turns_the_top_rigidly(model, aligned):
    """dop853 from the relative equilibrium at spin sigma: after one period T = 2 pi / sigma every
    state is back and zeta has advanced by 2 pi; half-way the centre of mass is across the circle."""
    from levitron.runtime.integrate.run import integrate
    rt = rotating(model, aligned, 0.05)
    sigma = 1100.0
    x0, s = rt.solve(sigma), rt.scales(sigma)
    T = 2 * math.pi / sigma
    r = integrate(model.part("full"), x0, T, method="dop853", tol=1e-12, p=rt.p, scale=s, n_out=2)
    assert r.status == "completed", r.status
    shift = np.zeros(len(x0))
    shift[rt.states.index("zeta")] = 2 * math.pi
    assert np.max(np.abs((r.X[-1] - x0 - shift) / s)) <= 1e-8
    ix, iy = rt.states.index("x"), rt.states.index("y")
    assert x0[ix] > 1e-8 and abs(r.X[1][ix] + x0[ix]) <= 1e-4 * x0[ix] and abs(r.X[1][iy]) <= 1e-4 * x0[ix]


def test_at_zero_tilt_it_is_the_eigen_route(model, aligned):
    from levitron.runtime.physics.apparatus.tilted_stability import reduced_jacobian
    rt = rotating(model, aligned, 0.0)
    got = windows(rt, aligned)
    assert len(got) == 1 and len(aligned.eigenvalues) == 1
    for a, b in zip(got[0], aligned.eigenvalues[0]):
        assert abs(a - b) <= 2 * req.SPIN_RTOL * b, (a, b)
    lo, hi = aligned.spin_interval
    for sigma in (0.9 * lo, math.sqrt(lo * hi), 1.05 * hi):
        eq = rt.top.hamilton(0.0, sigma)
        J = reduced_jacobian(model.part("full").jac(eq.state, rt.aligned), eq.states)
        want = np.exp(np.linalg.eigvals(J) * 2 * math.pi / sigma)
        mu = rt.check(sigma).multipliers
        for w in want:
            k = int(np.argmin(np.abs(mu - w)))
            assert abs(mu[k] - w) <= 1e-9, (sigma, w, mu[k])
            mu = np.delete(mu, k)
        assert rt.stable(sigma) == (lo < sigma < hi)


def test_floquet_analysis_takes_the_fast_route_where_it_applies(model):
    res = fs.floquet_analysis(model, model.p)
    fq = res.floquet
    assert fq["route"].startswith("Floquet multipliers exp(T lambda) of the relative equilibrium")
    assert set(fq) >= {"route", "windows", "moment_tilt", "multiplier_tolerance", "spin_rtol",
                       "aligned_interval", "probed", "at_middle"}
    assert fq["spin_rtol"] == req.SPIN_RTOL and res.equilibrium["periodic"]
    # the independent check's window at 0.05 rad (459.807-2726.359 rad/s)
    assert res.spin_interval == pytest.approx((459.807, 2726.359), rel=2e-6)
    assert fq["at_middle"]["orbit_residual"] <= 1e-14 and fq["at_middle"]["deviation"] <= 1e-12


def test_a_tilted_base_falls_back_to_shooting(model, aligned):
    p = model.with_params({"base_tilt": 1e-4})
    why = req.refusal(model, p)
    assert why is not None and "base is tilted" in why
    with pytest.raises(ValueError, match="does not apply"):
        req.RotatingTop(model, p, z_magnet(model, aligned))
    ft, route, rtol = fs.steady_top(model, p, z_magnet(model, aligned))
    assert isinstance(ft, fl.FloquetTop) and rtol == fl.SPIN_RTOL
    assert route.startswith(fs.ROUTE) and "does not apply: the base is tilted" in route
    assert req.refusal(model, model.p) is None            # the level base: it applies


def test_a_four_fold_plate_is_refused(model):
    """The symmetry comes from scene/plates/symmetry.py: a square plate is four-fold only."""
    square = {"kind": "rectangle", "side_x": 0.1, "side_y": 0.1, "magnetization": 1.0}
    sides = {"plate_side_x": 0.1, "plate_side_y": 0.1, "plate_magnetization": 1.0}
    stand_in = types.SimpleNamespace(
        has_function=model.has_function, part=model.part,
        pvals=lambda p: {**model.pvals(p), **sides},
        scene=types.SimpleNamespace(data={"plate": square}))
    why = req.refusal(stand_in, model.p)
    assert why is not None and "four-fold" in why
    stand_in.scene.data["plate"] = model.scene.data["plate"]
    assert req.refusal(stand_in, model.p) is None


def test_max_moment_tilt_by_the_relative_equilibrium(model, aligned):
    ticks = []
    got = fs.moment_tolerance(model, model.p, tick=lambda: ticks.append(1))
    b = got["max_moment_tilt"]
    lo, hi = got["bracket"]
    assert lo == b and hi - lo <= fs.RE_TILT_RTOL * hi and "eigenvalues" in got["how"]
    # one tick per existence decided: the doublings from 1e-3 rad and the bisection's steps
    doublings = int(math.log2(hi / 1e-3)) + 1 if hi > 1e-3 else 1
    assert len(ticks) >= doublings + math.floor(math.log2(0.5 / fs.RE_TILT_RTOL))
    # where the window shrinks to a point (measured: 471.9-473.0 rad/s at 0.2395 rad, none at
    # 0.2397), on a grid 0.025 % apart, independently of the tracking: a stable spin at b, none
    # 0.5 % above it
    grid = np.geomspace(aligned.spin_interval[0], 1.04 * aligned.spin_interval[0], 160)
    at = rotating(model, aligned, b)
    assert any(at.stable(s) for s in grid)
    above = rotating(model, aligned, 1.005 * b, fold_rtol=fs.FOLD_RTOL)
    assert not any(above.stable(s) for s in grid)
