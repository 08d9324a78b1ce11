"""The linear picture beside a stability map (runtime/scan/stability_map.py): the linear spin interval per value
of the second axis (thesis 3.3, exact discriminant route) and the slow period that sets the default
run length (thesis 3.3.3, 3.3.5).
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from levitron.runtime.physics.stability.analysis import stability_of
from levitron.runtime.simulate.start import slow_period  # noqa: F401 (the map's default run length)


def linear_interval(model, mass: float | None = None) -> dict:
    """The linear spin interval (thesis 3.3, exact discriminant route) and z_s, for the scene's top
    or one of another mass (the eigenvalue route, a cross-check, is not run: the map reports the
    exact route's interval only)."""
    m = model.param("m") if mass is None else float(mass)
    res = stability_of(model, m, eigen=False)
    iv = res.spin_interval
    return {"mass": m, "z_s": res.z_s, "spin_interval": None if iv is None else [float(iv[0]), float(iv[1])],
            "reason": res.reason}


def reference_spin(interval: Sequence[float] | None, spins: np.ndarray) -> float:
    """A spin to measure the slow period at: the geometric mean of the linear interval, else of
    the scanned spin range (else its largest |value|)."""
    if interval is not None:
        return math.sqrt(interval[0] * interval[1])
    lo, hi = float(np.abs(spins).min()), float(np.abs(spins).max())
    if lo > 0:
        return math.sqrt(lo * hi)
    return hi if hi > 0 else 1.0


def spins_around(interval: Sequence[float], n: int) -> np.ndarray:
    """n spins for a sketch of a map around a linear interval [lo, hi]: 0.5 lo to 1.25 hi, so that
    both ends and the falls beyond them show; where the interval is narrower than three steps of
    that grid (no point or one would fall inside it), lo - (hi - lo) to hi + (hi - lo) instead, so
    that the map resolves it."""
    lo, hi = float(interval[0]), float(interval[1])
    wide = np.linspace(0.5 * lo, 1.25 * hi, n)
    if hi - lo >= 3 * (wide[1] - wide[0]):
        return wide
    w = hi - lo
    return np.linspace(max(lo - w, 0.0), hi + w, n)
