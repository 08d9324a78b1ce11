"""The result of the linear stability analysis (runtime/physics/stability/analysis.py, level base;
runtime/physics/apparatus/tilted_stability.py, tilted base) and what both routes share: the gap between two
routes' intervals and the thesis's approximations at z_c (thesis 3.3.22/3.3.23). No sympy here."""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from levitron.runtime.physics.routes.ray_algebra import thesis_approximations
from levitron.runtime.words import si_unit


@dataclass
class StabilityResult:
    z_s: float | None
    spin_interval: tuple[float, float] | None
    discriminant: list[tuple[float, float]]
    eigenvalues: list[tuple[float, float]] | None
    approximations: dict
    reason: str | None
    routes_agree: bool | None
    timings: dict
    mass: float | None = None        # kg: the top analysed (stability_of's `height`: the one hovering there)
    notes: list = field(default_factory=list)
    # over a tilted base: position, axis (runtime/physics/apparatus/tilted_stability.py)
    equilibrium: dict | None = None
    floquet: dict | None = None      # a moment off the axis: route "Floquet" (runtime/physics/apparatus/moment_tilt.py)

    def as_dict(self) -> dict:
        def pair(iv):
            return None if iv is None else [float(iv[0]), float(iv[1])]

        def first(ivs):
            return pair(ivs[0]) if ivs else None

        si = pair(self.spin_interval)
        hz = None if si is None else [v / (2 * math.pi) for v in si]
        rpm = None if hz is None else [v * 60 for v in hz]
        return {
            "z_s": self.z_s,
            "spin_interval": si,
            "spin_interval_hz": hz,
            "spin_interval_rpm": rpm,
            "routes": {"discriminant": first(self.discriminant),
                       "eigenvalues": first(self.eigenvalues) if self.eigenvalues is not None else None,
                       **({"floquet": pair(self.spin_interval)} if self.floquet is not None else {})},
            "all_intervals": {"discriminant": [pair(v) for v in self.discriminant],
                              "eigenvalues": None if self.eigenvalues is None
                              else [pair(v) for v in self.eigenvalues]},
            "routes_agree": self.routes_agree,
            "approximations": self.approximations,
            "reason": self.reason,
            "timings_s": self.timings,
            **({"equilibrium": self.equilibrium} if self.equilibrium is not None else {}),
            **({"floquet": self.floquet} if self.floquet is not None else {}),
            **({"notes": list(self.notes)} if self.notes else {}),
        }


def relative_gap(a: Sequence[tuple[float, float]], b: Sequence[tuple[float, float]]) -> float:
    """Largest relative difference between matching interval end points (inf if counts differ)."""
    if len(a) != len(b):
        return math.inf
    gap = 0.0
    for (a0, a1), (b0, b1) in zip(a, b):
        for u, v in ((a0, b0), (a1, b1)):
            if u != v:
                gap = max(gap, abs(u - v) / max(abs(u), abs(v)))
    return gap


def approximations_at_z_c(onaxis, z_c, max_mass, g, A, C) -> dict:
    """Thesis 3.3.22/3.3.23 at z_c for the top of mass m(z_c) that hovers there."""
    out = {"sigma1": None, "sigma2": None, "z_c": z_c, "mass_at_z_c": max_mass, "g21": None,
           "note": "thesis eqs. 3.3.22/3.3.23 (printed as squares) at z_c, for the top of mass "
                   f"m(z_c) that hovers there; {si_unit('rad/s')}"}
    if z_c is not None and max_mass is not None and max_mass > 0:
        ph = onaxis(z_c)
        out.update(thesis_approximations(ph[1], ph[2], g, max_mass, A, C))
        for k in ("sigma1", "sigma2"):
            v = out[k]
            out[k + "_hz"] = None if v is None else v / (2 * math.pi)
    return out
