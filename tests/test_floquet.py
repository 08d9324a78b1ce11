"""Route "Floquet" (issue 27): the periodic orbit of a top whose moment is off its axis, its
monodromy's multipliers, the spin window (runtime/physics/periodic_orbit.py, floquet.py,
floquet_stability.py).

Checks against independent routes: at moment tilt 0 the multipliers are exp(T lambda) of the eigen
route's reduced Jacobian, and on the peer's loop trap (scenes/loop_peer.toml) the Floquet window
is the eigen route's to the bisection's width; stability names route Floquet in JSON and plain view.
(The checks against the C integrator, dop853 on the orbit and beside the window's ends, are not
here yet: the dop853 run on loop_peer with a moment tilt stopped at t = 2.7e-4 s, see the report.)
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from levitron.runtime.physics import floquet as fl

PEER_TILT = 0.02


@pytest.fixture(scope="module")
def peer(derived_model):
    return derived_model("loop_peer")


@pytest.fixture(scope="module")
def aligned(peer):
    from levitron.runtime.physics.tilted_stability import tilted_analysis
    return tilted_analysis(peer, peer.with_params({"moment_tilt": 0.0}))


def floquet_top(model, res0, b):
    return fl.FloquetTop(model, model.with_params({"moment_tilt": b}), res0.equilibrium["z_level"])


def test_at_zero_tilt_the_multipliers_are_the_eigen_route_s(peer, aligned):
    from levitron.runtime.physics.tilted_stability import reduced_jacobian
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
    from levitron.runtime.physics.floquet_stability import probes_for
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
    assert main(["stability", "loop_peer", "--set", f"top.moment_tilt={PEER_TILT}"]) == 0
    text = capsys.readouterr().out
    assert "(route Floquet: the moment 0.02 rad (1.15 deg) off the axis" in text
    assert "the steady motion is periodic" in text and "level, aligned apparatus only" in text
