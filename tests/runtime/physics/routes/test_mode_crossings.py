"""runtime/physics/routes/mode_crossings.py: the level system's mode crossings are found where they are,
and a gap the coupling opens beside one is probed, on systems whose answers are known in closed
form; on the scenes, the crossings the tilted base's analysis relies on."""
from __future__ import annotations

import math

import numpy as np
import pytest

from levitron.runtime.physics.routes.eigen_route import spin_intervals_eigen
from levitron.runtime.physics.routes.mode_crossings import level_crossings, tilted_probes

W_Z, W_B = 3.0, 10.0


def oscillator(w: float, sign: float = 1.0) -> np.ndarray:
    """(q, p) of H = sign (p^2 + w^2 q^2) / 2: sign -1 is the opposite Krein signature."""
    return np.array([[0.0, sign], [-sign * w * w, 0.0]])


def level(sigma: float) -> np.ndarray:
    """A bounce at W_Z (rows 0-1) beside two transverse modes at sigma and W_B (rows 2-5)."""
    J = np.zeros((6, 6))
    J[:2, :2], J[2:4, 2:4], J[4:, 4:] = oscillator(W_Z), oscillator(sigma), oscillator(W_B, -1.0)
    return J


def coupled(eps: float, w_b: float):
    """The two transverse modes of opposite signature coupled by eps q1 q2:
    (lambda^2 + sigma^2)(lambda^2 + w_b^2) = -eps^2, unstable exactly for |sigma^2 - w_b^2| < 2 eps."""
    def jac(sigma: float) -> np.ndarray:
        J = np.zeros((4, 4))
        J[:2, :2], J[2:, 2:] = oscillator(sigma), oscillator(w_b, -1.0)
        J[1, 2], J[3, 0] = -eps, -eps
        return J
    return jac


def test_the_level_crossings_are_where_the_frequencies_meet():
    bounce, transverse = level_crossings(level, [0, 1], [2, 3, 4, 5], 1.0, 30.0)
    assert bounce == pytest.approx([W_Z], rel=1e-14)
    assert transverse == pytest.approx([W_B], rel=1e-7)


def test_no_meeting_where_the_frequencies_only_come_close():
    """Two modes of the same block that avoid each other (a 1e-4 coupling of the same signature)."""
    def jac(sigma):
        J = level(sigma)
        J[4:, 4:] = oscillator(W_B)
        J[3, 4], J[5, 2] = -1e-2, -1e-2
        return J
    assert level_crossings(jac, [0, 1], [2, 3, 4, 5], 5.0, 30.0)[1] == []


@pytest.mark.parametrize("shift", [0.0, 2e-4])
def test_the_gap_beside_a_crossing_is_found_to_its_closed_form_ends(shift):
    """eps = 1e-3 opens a gap 2e-5 wide (relative) that the log grid steps over; the probes find it,
    also when it lies 10 of its widths off the level crossing at W_B (shift), where probing the
    crossing alone misses it."""
    eps, w_b = 1e-3, W_B * (1 + shift)
    jac = coupled(eps, w_b)
    lo, hi = math.sqrt(w_b ** 2 - 2 * eps), math.sqrt(w_b ** 2 + 2 * eps)
    assert len(spin_intervals_eigen(jac, W_B, [W_B])) == (2 if shift == 0 else 1)
    found = spin_intervals_eigen(jac, W_B, tilted_probes(jac, [W_B], 1e-2))
    assert len(found) == 2
    assert found[0][1] == pytest.approx(lo, rel=1e-10) and found[1][0] == pytest.approx(hi, rel=1e-10)


@pytest.mark.parametrize("scene", ["thesis_stable", "ring_magnet"])
def test_on_the_scenes_the_transverse_modes_do_not_meet_inside_the_level_interval(scene, derived_model):
    """The level top's transverse frequencies (the reduced Jacobian without the bounce) stay apart
    over [lo/2, 2 hi]: only the bounce crossing opens a gap on a tilted base (test_base_tilt.py)."""
    from levitron.runtime.physics.apparatus.friction import without_friction
    from levitron.runtime.physics.apparatus.tilted_equilibrium import FIXED, TiltedTop
    from levitron.runtime.physics.apparatus.tilted_stability import reduced_jacobian, tilted_analysis
    model = derived_model(scene, "plate.tilt=0")
    p = without_friction(model, model.p)
    res = tilted_analysis(model, p)
    lo, hi = res.spin_interval
    eq = TiltedTop(model, p, res.equilibrium["z_level"]).hamilton(0.0, math.sqrt(lo * hi))
    jfast, n = model.fast("full_jac", p), len(eq.states)
    states = [s for s in eq.states if s not in FIXED]
    vert = [states.index("z"), states.index("p_z")]
    bounce, transverse = level_crossings(
        lambda s: reduced_jacobian(jfast(eq.at_spin(s)).reshape(n, n), eq.states),
        vert, [i for i in range(len(states)) if i not in vert], lo / 2, 2 * hi)
    assert transverse == []
    assert scene != "thesis_stable" or any(abs(c - 2727) < 5 for c in bounce), bounce
