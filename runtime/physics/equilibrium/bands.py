"""The stable band and the adiabatic band of heights and masses (docs/contract.md `equilibrium`).

The stable band: the heights z where a top of mass m(z) = -mu Phi_2(z)/g hovering there (thesis
3.3.2) is vertically stable (mu Phi_3 > 0, 3.3.3) and linearly stable for some finite spin (the
exact route "discriminant", runtime/physics/routes/ray_algebra.py, thesis 3.3.11-3.3.16).

Beside it the adiabatic band of Berry and Simon: |B| has a minimum. With B = -grad(phi) and the
expansion of thesis 2.2.7, |B|^2 = Phi_1^2 + r^2 (Phi_2^2/4 - Phi_1 Phi_3/2) + O(r^4)
(tests/derive/test_stability_derivation.py checks this), so the conditions on the axis are
    d^2|B|/dz^2 = sign(Phi_1) Phi_3 > 0   and   Phi_2^2 - 2 Phi_1 Phi_3 > 0,
equivalently (thesis 3.3.14) g31 < 0 and g21^2 + g31 > 0.

The heights come from the equilibrium finder's survey (runtime/physics/equilibrium/finder.py); no sympy here.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from levitron.runtime.physics.routes import ray_algebra

OnAxis = Callable[[float], Sequence[float]]


@dataclass
class Band:
    z: tuple[float, float]
    mass: tuple[float, float]
    # whether the low / high edge is the end of the searched heights (a formula's plate.z_range,
    # else z_grid's), not a physical edge: the band may go on where the search does not look
    at_search_end: tuple[bool, bool] = (False, False)

    def as_dict(self) -> dict:
        return {"z": list(self.z), "mass": list(self.mass), "at_search_end": list(self.at_search_end)}


def spin_stabilisable(phis: Sequence[float], g: float, A: float, C: float, mu: float) -> bool:
    """At a height with on-axis values phis: does the top of mass m(z) = -mu Phi_2/g hovering there
    admit a finite spin with linear stability? Vertical (mu Phi_3 > 0, thesis 3.3.3) and transverse
    (route "discriminant", thesis 3.3.11-3.3.16, exact)."""
    if not all(math.isfinite(v) for v in phis[:4]):
        return False
    m = -mu * phis[2] / g
    if not (m > 0 and mu * phis[3] > 0):
        return False
    c = ray_algebra.RayCoefficients.from_physics(phis[1], phis[2], phis[3], m, A, C, mu)
    return ray_algebra.has_bounded_spin_interval(c)


def adiabatic_trap(phis: Sequence[float], g: float, mu: float) -> bool:
    """Berry-Simon: |B| has a minimum on the axis there (see the module docstring), and a top can
    hover there at all (m(z) > 0)."""
    _, p1, p2, p3 = phis[:4]
    return (-mu * p2 / g > 0) and (math.copysign(1.0, p1) * p3 > 0) and (p2 * p2 - 2 * p1 * p3 > 0)


def _bands(pred: Callable[[float], bool], mass: Callable[[float], float], zs: np.ndarray,
           rtol: float = 1e-12) -> list[Band]:
    flags = [pred(float(z)) for z in zs]

    def edge(a: float, b: float, fa: bool) -> float:
        while b - a > rtol * b:
            mid = 0.5 * (a + b)
            if pred(mid) == fa:
                a = mid
            else:
                b = mid
        return 0.5 * (a + b)

    out, lo = [], None
    for i, f in enumerate(flags):
        if f and lo is None:
            lo = float(zs[0]) if i == 0 else edge(float(zs[i - 1]), float(zs[i]), False)
        if not f and lo is not None:
            out.append((lo, edge(float(zs[i - 1]), float(zs[i]), True)))
            lo = None
    if lo is not None:
        out.append((lo, float(zs[-1])))
    # m(z) is monotone on a vertically stable stretch (dm/dz = -mu Phi_3/g < 0), so its range is
    # spanned by the end points
    return [Band((lo, hi), (min(mass(lo), mass(hi)), max(mass(lo), mass(hi)))) for lo, hi in out]


def bands_of(onaxis: OnAxis, zs: Sequence[float], rows: Sequence[Sequence[float]], z_c: float | None,
             g: float, A: float, C: float, mu: float) -> tuple[list[Band], list[Band]]:
    """(stable bands, adiabatic bands) from the finder's knots zs (sorted, finite) with their rows
    [Phi_0..]: the fine work is restricted to the stretch where m(z) > 0 and mu Phi_3 > 0."""
    zs = np.asarray(zs, float)
    T = np.array([np.asarray(r, float)[:4] for r in rows])
    ok = (-mu * T[:, 2] / g > 0) & (mu * T[:, 3] > 0)
    if not ok.any():
        return [], []
    i0, i1 = max(int(np.argmax(ok)) - 1, 0), min(len(zs) - int(np.argmax(ok[::-1])), len(zs) - 1)
    fine = np.geomspace(zs[i0], zs[i1], 300)
    if z_c is not None and zs[i0] <= z_c <= zs[i1]:
        # a band opens at z_c (there g31 = 0; thesis 3.3.15) and is typically a few % wide:
        # sample that stretch densely so that a narrow band is not stepped over
        fine = np.union1d(fine, np.geomspace(z_c, min(1.5 * z_c, zs[i1]), 200))
    phis = lambda z: [float(v) for v in np.asarray(onaxis(z), float)[:4]]
    mass = lambda z: -mu * phis(z)[2] / g
    stable = _bands(lambda z: spin_stabilisable(phis(z), g, A, C, mu), mass, fine)
    adiabatic = _bands(lambda z: adiabatic_trap(phis(z), g, mu), mass, fine)
    return _mark_ends(stable, zs[0], zs[-1]), _mark_ends(adiabatic, zs[0], zs[-1])


def _mark_ends(bands: list[Band], lo: float, hi: float, rtol: float = 1e-9) -> list[Band]:
    """The bands with at_search_end set where an edge is the search's first or last height."""
    return [Band(b.z, b.mass, (b.z[0] <= lo * (1 + rtol), b.z[1] >= hi * (1 - rtol))) for b in bands]


def edge_note(band: dict | Band | None, stated: bool) -> str:
    """What an edge at the search's end is (Band.at_search_end): "" for a band whose edges are
    physical; else which edge, and that it is the formula's stated range (plate.z_range) or the
    height search's own end, not physics."""
    if band is None:
        return ""
    ends = band["at_search_end"] if isinstance(band, dict) else band.at_search_end
    which = [w for w, e in zip(("lower", "upper"), ends) if e]
    if not which:
        return ""
    edge = " and ".join(which) + (" edges are" if len(which) == 2 else " edge is")
    if stated:
        return f"its {edge} the end of the formula's range, plate.z_range: not a physical edge"
    return (f"its {edge} where the height search ends, not a physical edge: an expression plate states "
            "where its formula holds with plate.z_range")

