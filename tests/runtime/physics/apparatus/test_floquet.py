"""Route "Floquet" (issue 27): the periodic orbit of a top whose moment is off its axis, its
monodromy's multipliers, the spin window (runtime/physics/apparatus/periodic_orbit.py, multipliers.py,
moment_tilt.py).

Checks against independent routes: at moment tilt 0 the multipliers are exp(T lambda) of the eigen
route's reduced Jacobian, and on the peer's loop trap (scenes/loop_peer.toml) the Floquet window
is the eigen route's to the bisection's width; stability names route Floquet in JSON and plain view.
Against the C integrator (dop853 on the generated full_rhs, a second integrator and a second
implementation of the flow): the orbit closes after one period and stays closed over many, and
beside the window's upper end a perturbation along the largest multiplier's eigenvector grows at
the rate log|mu| / T that Floquet predicts, while inside the window at both ends it does not grow.
The lower end at moment tilt 0.02 is a fold of the forced response: a pair of multipliers meets at
+1 there (their angle shrinks toward the end) and below it the orbit on the branch is gone.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from levitron.runtime.physics.apparatus import multipliers as fl

PEER_TILT = 0.02


@pytest.fixture(scope="module")
def peer(derived_model):
    return derived_model("loop_peer")


@pytest.fixture(scope="module")
def aligned(peer):
    from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis
    return tilted_analysis(peer, peer.with_params({"moment_tilt": 0.0}))


def floquet_top(model, res0, b):
    return fl.FloquetTop(model, model.with_params({"moment_tilt": b}), res0.equilibrium["z_level"])


def test_at_zero_tilt_the_multipliers_are_the_eigen_route_s(peer, aligned):
    from levitron.runtime.physics.apparatus.tilted_stability import reduced_jacobian
    ft = floquet_top(peer, aligned, 0.0)
    lo, hi = aligned.spin_interval
    for sigma in (1.1 * lo, math.sqrt(lo * hi), 0.95 * hi, 0.9 * lo):
        c = ft.check(sigma)
        eq = ft.top.hamilton(0.0, sigma)
        J = reduced_jacobian(peer.part("full").jac(eq.state, ft.aligned), eq.states)
        want = np.exp(np.linalg.eigvals(J) * 2 * math.pi / sigma)
        got = c.multipliers
        # each multiplier has its partner in the other set (matched greedily, nearest first)
        for w in want:
            k = int(np.argmin(np.abs(got - w)))
            assert abs(got[k] - w) <= 1e-8, (sigma, w, got[k])
            got = np.delete(got, k)
        assert c.stable == (lo < sigma < hi)


def test_at_zero_tilt_the_floquet_window_is_the_eigen_route_s(peer, aligned):
    from levitron.runtime.physics.apparatus.moment_tilt import probes_for
    ft = floquet_top(peer, aligned, 0.0)
    windows = fl.spin_windows(ft.stable, probes_for(ft, aligned.spin_interval))
    assert len(windows) == 1 and len(aligned.eigenvalues) == 1
    for got, want in zip(windows[0], aligned.eigenvalues[0]):
        assert abs(got - want) <= 2 * fl.SPIN_RTOL * want, (got, want)


def test_stability_names_the_floquet_route(capsys):
    import json
    from levitron.runtime.cli.main import main
    assert main(["stability", "loop_peer", "--set", f"top.moment_tilt={PEER_TILT}", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["routes"]["floquet"] == out["spin_interval"] and out["routes"]["discriminant"] is None
    assert out["floquet"]["route"].startswith("Floquet") and out["equilibrium"]["periodic"]
    # the plain view of the same answer (one analysis, 100 s, not two)
    from levitron.runtime.cli.commands import stability
    from levitron.runtime.model.scenes import load_scene
    text = stability.human(out, load_scene("loop_peer", [f"top.moment_tilt={PEER_TILT}"]))
    assert "(route Floquet: the moment 0.02 rad (1.15 deg) off the axis" in text
    assert "the steady motion is periodic" in text and "level, aligned apparatus only" in text


SHIFT_STATE = "zeta"


def _c_run(ft, orbit, x0, periods, n_out):
    from levitron.runtime.integrate.run import integrate
    r = integrate(ft.model.part("full"), x0, periods * orbit.period, method="dop853", tol=1e-12,
                  p=ft.p, scale=orbit.scales, n_out=n_out)
    assert r.status == "completed", r.status
    shift = np.zeros(len(x0))
    shift[ft.states.index(SHIFT_STATE)] = 2 * math.pi
    return r, (r.X - orbit.x0 - np.outer(np.round(r.t / orbit.period), shift)) / orbit.scales


@pytest.fixture(scope="module")
def tilted(peer, aligned):
    return floquet_top(peer, aligned, PEER_TILT)


def test_the_orbit_closes_under_the_c_integrator(tilted):
    """dop853 from the shooting's x0: back at x0 (zeta + 2 pi) after one period and after each of 200."""
    orbit = tilted.orbit(141.0)
    _, d = _c_run(tilted, orbit, orbit.x0, 1, 1)
    assert np.max(np.abs(d[-1])) <= 1e-8, np.abs(d[-1]).max()
    r, d = _c_run(tilted, orbit, orbit.x0, 200, 200)
    assert np.allclose(r.t / orbit.period, np.arange(201))
    # the phase along the orbit drifts (neutral), the rest stays: measured 1.1e-9 at tol 1e-12
    f = tilted.shoot.rhs(orbit.x0) / orbit.scales
    f /= np.linalg.norm(f)
    d -= np.outer(d @ f, f)
    assert np.max(np.linalg.norm(d, axis=1)) <= 1e-7


def _growth(ft, sigma, periods=200, eps=1e-7):
    """|perturbation(N T)| / eps by dop853 from the orbit pushed along the eigenvector of the largest
    nontrivial multiplier (the flow direction taken out), and Floquet's |mu|^N."""
    orbit, check = ft.orbit(sigma), ft.check(sigma)
    s = orbit.scales
    M = orbit.monodromy * s[None, :] / s[:, None]
    f = ft.shoot.rhs(orbit.x0) / s
    f /= np.linalg.norm(f)
    w, V = np.linalg.eig(M)
    mu = check.multipliers[int(np.argmax(np.abs(check.multipliers)))]
    v = V[:, int(np.argmin(np.abs(w - mu)))]
    v = np.real(v + v.conj()) if mu.imag != 0 else np.real(v)
    v -= f * (f @ v)
    v /= np.linalg.norm(v)
    _, d = _c_run(ft, orbit, orbit.x0 + eps * v * s, periods, periods)
    d -= np.outer(d @ f, f)
    return float(np.linalg.norm(d[-1]) / eps), float(abs(mu)) ** periods, abs(mu)


@pytest.fixture(scope="module")
def peer_window(tilted, aligned):
    from levitron.runtime.physics.apparatus.moment_tilt import probes_for
    windows = fl.spin_windows(tilted.stable, probes_for(tilted, aligned.spin_interval))
    assert len(windows) == 1
    return windows[0]


def test_beside_the_upper_end_the_simulation_grows_as_floquet_says(tilted, peer_window):
    lo, hi = peer_window
    inside, _, mu_in = _growth(tilted, hi * (1 - 2e-3))
    assert abs(mu_in - 1) <= fl.MULT_TOL and 0.5 <= inside <= 1.5, (inside, mu_in)
    sim, pred, mu = _growth(tilted, hi * (1 + 3e-3))
    assert mu > 1 + 1e-3 and pred > 20
    # 200 periods: the rates log(growth) / N agree to 10 % (measured 0.0187 against 0.0195 per period)
    assert abs(math.log(sim) - math.log(pred)) <= 0.1 * math.log(pred), (sim, pred)


def test_below_the_lower_end_the_simulated_top_is_lost(tilted, peer_window):
    """At moment tilt 0.02 the window's lower end is where the orbit of period 2 pi / sigma stops
    existing on the branch (the period has an extremum along the orbits' family: Newton's Jacobian
    turns singular, no multiplier leaves the circle). Inside, the orbit kept; 0.1 % below, a top
    started where the orbit was just inside flies off within 2000 periods."""
    lo, _ = peer_window
    inside, _, mu = _growth(tilted, lo * (1 + 4e-3))
    assert abs(abs(mu) - 1) <= fl.MULT_TOL and 0.5 <= inside <= 1.5, inside
    with pytest.raises(fl.NoOrbit):
        tilted.orbit(lo * (1 - 1e-3))
    from levitron.runtime.integrate.run import integrate
    edge = tilted.orbit(lo * (1 + 1e-5))
    ir = [tilted.states.index(k) for k in "xyz"]
    for rel, lost in ((1 + 1e-5, False), (1 - 1e-3, True)):
        sigma = lo * rel
        x0 = tilted.rescaled(edge, sigma)
        r = integrate(tilted.model.part("full"), x0, 2000 * 2 * math.pi / sigma, method="dop853",
                      tol=1e-11, p=tilted.p, scale=edge.scales, n_out=2000)
        far = np.max(np.linalg.norm(r.X[:, ir] - x0[ir], axis=1)) / x0[ir[2]]
        assert (far > 1.0) == lost, (rel, far)
