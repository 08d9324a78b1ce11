"""Where the level top's linear modes meet, so that the tilted base's narrow gaps are probed.

On a level base the axial symmetry keeps the vertical bounce (z, p_z; frequency sqrt(mu Phi_3 /
m), thesis 3.3.3) apart from the transverse modes, and the transverse modes of opposite sense of
rotation apart from each other: their frequencies may cross inside the stable interval without
harm. A base tilt breaks the symmetry by one unit of angular momentum: it couples a transverse
mode to the bounce at first order in the tilt, and two transverse modes of opposite sense at
second order. Where the coupled modes' Krein signatures differ, a band of instability opens at
the crossing, of width about the coupling; a scan on a grid steps over it. So the crossings are
found on the level system, where they are exact (`level_crossings`), and the tilted system is
probed there and where its own two frequencies come closest nearby (`tilted_probes`). No sympy.
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from scipy.optimize import minimize_scalar

from levitron.runtime.physics.routes.eigen_route import EPS, on_imaginary_axis

CROSSING_GRID = 400     # spins on the level system's log grid where crossings are looked for
MEET_RTOL = 1e-6        # two transverse frequencies this close (relative) at their closest: a meeting
XTOL = 1e-10            # relative spin tolerance of a meeting's refinement


def _frequencies(J: np.ndarray, idx: list[int]) -> np.ndarray:
    """The block's frequencies |Im lambda|, ascending, each pair +-i w once."""
    return np.sort(np.abs(np.linalg.eigvals(J[np.ix_(idx, idx)]).imag))[::2]


def _closest(gap: Callable[[float], float], a: float, b: float) -> tuple[float, float]:
    """The spin in [a, b] where gap(sigma) is smallest (Brent, bounded) and the gap there."""
    r = minimize_scalar(gap, bounds=(a, b), method="bounded", options={"xatol": XTOL * b})
    return float(r.x), float(r.fun)


def level_crossings(jac0: Callable[[float], np.ndarray], vert: list[int], rest: list[int],
                    lo: float, hi: float) -> tuple[list[float], list[float]]:
    """The spins in [lo, hi] where, on the level system jac0(sigma) (the reduced Jacobian at tilt
    0, with (z, p_z) = rows `vert` decoupled from the transverse rows `rest`), a transverse
    frequency equals the bounce's (sign changes on a log grid, bisected to adjacent doubles'
    width), and where two transverse frequencies meet (where the transverse block is stable, the
    ascending frequencies' gap has a local minimum on the grid that Brent brings below MEET_RTOL
    relative; scipy's Brent stops at sqrt(eps) relative). Returns (bounce, transverse)."""
    grid = np.geomspace(lo, hi, CROSSING_GRID)
    jacs = [jac0(s) for s in grid]
    w_z = np.array([_frequencies(J, vert).max() for J in jacs])
    w = np.array([_frequencies(J, rest) for J in jacs])

    def bounce_gap(sigma: float, k: int) -> float:
        J = jac0(sigma)
        return _frequencies(J, rest)[k] - _frequencies(J, vert).max()
    bounce = []
    d = w - w_z[:, None]
    for i, k in zip(*np.nonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0)):
        a, b, fa = grid[i], grid[i + 1], d[i, k]
        while b - a > 4 * EPS * b:
            mid = 0.5 * (a + b)
            a, b = (mid, b) if np.sign(bounce_gap(mid, k)) == np.sign(fa) else (a, mid)
        bounce.append(0.5 * (a + b))
    transverse = []
    sep = np.diff(w, axis=1) / w[:, 1:]

    def calm(i):
        return all(on_imaginary_axis(jacs[j][np.ix_(rest, rest)]).stable for j in (i - 1, i, i + 1))
    for k in range(sep.shape[1]):
        s = sep[:, k]
        for i in np.nonzero((s[1:-1] <= s[:-2]) & (s[1:-1] <= s[2:]))[0] + 1:
            if not calm(i):
                continue
            at, gap = _closest(lambda x, k=k: float(np.diff(_frequencies(jac0(x), rest))[k]),
                               grid[i - 1], grid[i + 1])
            if gap <= MEET_RTOL * w[i, k + 1]:
                transverse.append(at)
    return sorted(bounce), sorted(transverse)


def tilted_probes(jac: Callable[[float], np.ndarray], crossings: list[float],
                  reach: float) -> list[float]:
    """Spins at which to probe the tilted system jac(sigma) near each level crossing: the crossing
    itself and, within reach (relative) of it, the spin where the tilted system's two closest
    frequencies come closest (inside a gap they have merged: the gap's middle is found even when
    the tilt has moved it off the level crossing by more than its width)."""
    out = []
    for c in crossings:
        def closest_pair(x: float) -> float:
            J = jac(x)
            return float(np.diff(np.sort(np.abs(np.linalg.eigvals(J).imag))[::2]).min())
        out += [c, _closest(closest_pair, c * (1 - reach), c * (1 + reach))[0]]
    return out
