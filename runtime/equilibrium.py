"""Vertical equilibria, z_c, the largest mass, and the stable band (thesis 3.3.1-3.3.3; DESIGN.md).

On the invariant set (top on the axis, axis vertical, thesis 3.2.1) the potential is
U(z) = m g z + mu Phi_1(z) (thesis 3.3.1), so the equilibria are the roots of
m g + mu Phi_2(z) = 0 (3.3.2) and they are vertically stable where mu Phi_3(z) > 0 (3.3.3).

z_c is where Phi_3 = 0: there the hovering mass m(z) = -mu Phi_2(z)/g is largest (dm/dz = -mu Phi_3/g),
and max_mass = m(z_c) is the heaviest top the plate can hold at all.

The stable band (DESIGN.md): the heights z where a top of mass m(z) hovering there is vertically stable
and linearly stable for some finite spin (exact linear analysis of runtime/linear.py). Beside it the
adiabatic band of Berry and Simon: |B| has a minimum. With B = -grad(phi) and the expansion of
thesis 2.2.7, |B|^2 = Phi_1^2 + r^2 (Phi_2^2/4 - Phi_1 Phi_3/2) + O(r^4) (tests/test_stability_
derivation.py checks this), so the conditions on the axis are
    d^2|B|/dz^2 = sign(Phi_1) Phi_3 > 0   and   Phi_2^2 - 2 Phi_1 Phi_3 > 0,
equivalently (thesis 3.3.14) g31 < 0 and g21^2 + g31 > 0.

All lengths are scaled by a length of the scene (`length_scale`), never fixed: scenes may be
dimensionless. No sympy here.
"""
from __future__ import annotations

import re

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np
from scipy.optimize import brentq

from . import linear

OnAxis = Callable[[float], Sequence[float]]  # z -> [Phi_0, Phi_1, ..., Phi_K], K >= 3

# the plate parameters (Scene.params keys) that are lengths, most characteristic first
LENGTH_KEYS = ("a", "radius", "r_out", "side_x", "side_y", "w", "r_in", "thickness")
_LENGTH_RE = re.compile(r"^plate_(?:p\d+_)*(" + "|".join(LENGTH_KEYS) + r")$")


def length_scale(params: dict) -> float:
    """The plate's size: the largest length among the plate's parameters (compound parts
    included, plate_p<i>_<key>), else 1.0 (a dimensionless scene)."""
    lengths = [float(v) for k, v in params.items() if _LENGTH_RE.match(k) and v is not None and v > 0]
    return max(lengths) if lengths else 1.0


@dataclass(frozen=True)
class Equilibrium:
    z: float
    vertically_stable: bool
    stiffness: float  # U''(z) = mu Phi_3(z) (thesis 3.3.3)


@dataclass
class Band:
    z: tuple[float, float]
    mass: tuple[float, float]

    def as_dict(self) -> dict:
        return {"z": list(self.z), "mass": list(self.mass)}


@dataclass
class EquilibriumReport:
    equilibria: list[Equilibrium]
    z_c: float | None
    max_mass: float | None
    stable_bands: list[Band] = field(default_factory=list)
    adiabatic_bands: list[Band] = field(default_factory=list)

    @property
    def stable_band(self) -> Band | None:
        """The widest stable band (DESIGN.md reports one; all are in stable_bands)."""
        return max(self.stable_bands, key=lambda b: b.z[1] - b.z[0]) if self.stable_bands else None

    @property
    def adiabatic_band(self) -> Band | None:
        return max(self.adiabatic_bands, key=lambda b: b.z[1] - b.z[0]) if self.adiabatic_bands else None


def z_grid(scale: float, lo: float = 1e-4, hi: float = 1e4, per_decade: int = 64) -> np.ndarray:
    """A log grid of heights scale * [lo, hi]: dense enough that no root of a smooth plate function
    is missed unless two roots are closer than ~4% in z."""
    n = int(round(math.log10(hi / lo) * per_decade)) + 1
    return scale * np.logspace(math.log10(lo), math.log10(hi), n)


def _table(onaxis: OnAxis, zs: np.ndarray) -> np.ndarray:
    return np.array([np.asarray(onaxis(float(z)), float)[:4] for z in zs])


def _roots(f: Callable[[float], float], zs: np.ndarray, values: np.ndarray) -> list[float]:
    """All sign changes of f on the grid, refined by brentq to full precision."""
    out = []
    for i in range(len(zs) - 1):
        a, b = values[i], values[i + 1]
        if a == 0:
            out.append(float(zs[i]))
        elif a * b < 0:
            out.append(brentq(f, zs[i], zs[i + 1], xtol=1e-300, rtol=4 * np.finfo(float).eps,
                              maxiter=200))
    return out


def vertical_equilibria(onaxis: OnAxis, m: float, g: float, mu: float, scale: float,
                        table: tuple[np.ndarray, np.ndarray] | None = None) -> list[Equilibrium]:
    """All roots of m g + mu Phi_2(z) = 0 on z > 0 (thesis 3.3.2), marked vertically stable where
    mu Phi_3 > 0 (3.3.3)."""
    zs, T = table if table is not None else (z_grid(scale), None)
    if T is None:
        T = _table(onaxis, zs)
    f = lambda z: m * g + mu * float(onaxis(z)[2])
    out = []
    for z in _roots(f, zs, m * g + mu * T[:, 2]):
        k = mu * float(onaxis(z)[3])
        out.append(Equilibrium(z, k > 0, k))
    return out


def hover_mass(onaxis: OnAxis, g: float, mu: float, z: float) -> float:
    """m(z) = -mu Phi_2(z) / g, the mass that hovers at height z (thesis 3.3.2 solved for m)."""
    return -mu * float(onaxis(z)[2]) / g


def critical_height(onaxis: OnAxis, g: float, mu: float, scale: float,
                    table: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[float | None, float | None]:
    """(z_c, max_mass): the zero of Phi_3 at which m(z) = -mu Phi_2/g is largest, and that mass.

    m(z) has its extrema where dm/dz = -mu Phi_3/g = 0. If m(z) <= 0 everywhere (the field pushes
    the top down, or the moment has the wrong sign) there is no hover at all: (None, None).
    If the largest sampled m lies at an end of the grid with no zero of Phi_3 near it, z_c is None
    and max_mass the supremum seen on the grid.
    """
    zs, T = table if table is not None else (z_grid(scale), _table(onaxis, z_grid(scale)))
    masses = -mu * T[:, 2] / g
    if not np.any(masses > 0):
        return None, None
    cands = [z for z in _roots(lambda z: float(onaxis(z)[3]), zs, T[:, 3])
             if hover_mass(onaxis, g, mu, z) > 0]
    if not cands:
        return None, float(masses.max())
    zc = max(cands, key=lambda z: hover_mass(onaxis, g, mu, z))
    return zc, hover_mass(onaxis, g, mu, zc)


# -------------------------------------------------------------------------- the bands

def spin_stabilisable(phis: Sequence[float], g: float, A: float, C: float, mu: float) -> bool:
    """At a height with on-axis values phis: does the top of mass m(z) = -mu Phi_2/g hovering there
    admit a finite spin with linear stability? Vertical (mu Phi_3 > 0) and transverse (route
    "discriminant" of runtime/linear.py, exact)."""
    m = -mu * phis[2] / g
    if not (m > 0 and mu * phis[3] > 0):
        return False
    c = linear.RayCoefficients.from_physics(phis[1], phis[2], phis[3], m, A, C, mu)
    return any(hi < math.inf for lo, hi in linear.spin_intervals_discriminant(c))


def adiabatic_trap(phis: Sequence[float], g: float, mu: float) -> bool:
    """Berry-Simon: |B| has a minimum on the axis there (see the module docstring), and a top can
    hover there at all (m(z) > 0)."""
    _, p1, p2, p3 = phis[:4]
    return (-mu * p2 / g > 0) and (math.copysign(1.0, p1) * p3 > 0) and (p2 * p2 - 2 * p1 * p3 > 0)


def _bands(pred: Callable[[float], bool], onaxis: OnAxis, zs: np.ndarray, g: float, mu: float,
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
            hi = edge(float(zs[i - 1]), float(zs[i]), True)
            out.append((lo, hi))
            lo = None
    if lo is not None:
        out.append((lo, float(zs[-1])))
    bands = []
    for lo, hi in out:
        # m(z) is monotone on a vertically stable stretch (dm/dz = -mu Phi_3/g < 0), so its range
        # is spanned by the end points
        m_lo, m_hi = hover_mass(onaxis, g, mu, lo), hover_mass(onaxis, g, mu, hi)
        bands.append(Band((lo, hi), (min(m_lo, m_hi), max(m_lo, m_hi))))
    return bands


def analyse(onaxis: OnAxis, m: float, g: float, A: float, C: float, mu: float,
            scale: float) -> EquilibriumReport:
    """Everything of thesis 3.3.1-3.3.3 and the bands (DESIGN.md) for one scene."""
    zs = z_grid(scale)
    T = _table(onaxis, zs)
    eqs = vertical_equilibria(onaxis, m, g, mu, scale, (zs, T))
    z_c, max_mass = critical_height(onaxis, g, mu, scale, (zs, T))
    phis_at = lambda z: [float(v) for v in np.asarray(onaxis(z), float)[:4]]
    # the bands live where m(z) > 0 and mu Phi_3 > 0: restrict the fine work to that stretch
    ok = (-mu * T[:, 2] / g > 0) & (mu * T[:, 3] > 0)
    stable, adiabatic = [], []
    if ok.any():
        i0, i1 = max(int(np.argmax(ok)) - 1, 0), min(len(zs) - int(np.argmax(ok[::-1])), len(zs) - 1)
        fine = np.geomspace(zs[i0], zs[i1], 300)
        if z_c is not None and zs[i0] <= z_c <= zs[i1]:
            # a band opens at z_c (there g31 = 0; thesis 3.3.15) and is typically a few % wide:
            # sample that stretch densely so that a narrow band is not stepped over
            fine = np.union1d(fine, np.geomspace(z_c, min(1.5 * z_c, zs[i1]), 200))
        stable = _bands(lambda z: spin_stabilisable(phis_at(z), g, A, C, mu), onaxis, fine, g, mu)
        adiabatic = _bands(lambda z: adiabatic_trap(phis_at(z), g, mu), onaxis, fine, g, mu)
    return EquilibriumReport(eqs, z_c, max_mass, stable, adiabatic)
