"""The answer to "where does the top hover?": `Equilibria`, one type for every face (the CLI's
`equilibrium --json` is its `as_json()`, `Study.equilibria()` returns it, the report reads it).

Thesis 3.3.1-3.3.3: the vertical equilibria (roots of m g + mu Phi_2(z) = 0, vertically stable
where U'' = mu Phi_3 > 0), z_c (the zero of Phi_3) and the largest mass m(z_c); the stable band of
docs/contract.md (runtime/physics/bands.py) and, beside it, never instead, Berry-Simon's adiabatic one.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field, replace

from levitron.runtime.physics import equilibrium as eqm
from levitron.runtime.physics.bands import Band
from levitron.runtime.physics.equilibrium_report import Equilibrium, Singularity, hover_reasons
from levitron.runtime.ui.human import Units, quantity
from levitron.runtime.ui.reference import stated

ADIABATIC_NOTE = ("Berry-Simon: |B| has a minimum on the axis (sign(Phi_1) Phi_3 > 0 and "
                  "Phi_2^2 > 2 Phi_1 Phi_3); an approximation for fast spin, reported beside "
                  "the exact band, never instead")
TILTED_NOTE = ("plate.tilt: these are the level base's equilibria on the axis (the band "
               "too); over the tilted base the top hovers off the axis: `«levitron=stability»` "
               "gives where, and its spin interval")
_SI = Units(si=True)


def _band(b: Band | None) -> dict | None:
    return None if b is None else b.as_dict()


@dataclass(frozen=True, repr=False)
class Equilibria:
    """The equilibria of the scene's top (thesis 3.3.1-3.3.3): equilibria (z in m, stiffness
    U'' = mu Phi_3 in N/m); z_c (m, zero of Phi_3) and max_mass (kg, m(z_c)), None if the field
    holds no top; stable_band (the widest; all in stable_bands): heights (m) and masses (kg) where
    some spin stabilises a top hovering there (docs/contract.md), None if there is none;
    reasons: why this top cannot levitate and what would help (empty where it can)."""

    scene: str
    mass: float
    equilibria: list[Equilibrium]
    singularities: list[Singularity]
    z_c: float | None
    max_mass: float | None
    stable_band: Band | None
    stable_bands: list[Band]
    adiabatic_band: Band | None
    reasons: list[str]
    length_scale: float
    z_range: list | None
    reference: dict
    wall_s: float
    note: str | None = None
    units: Units = field(default=_SI, compare=False)   # how repr and message show numbers

    @classmethod
    def of(cls, model) -> Equilibria:
        """The equilibria of `model`'s top at the scene's parameters (runtime/physics/equilibrium.py)."""
        m = eqm.params_of(model)["m"]
        t0 = time.perf_counter()
        rep = eqm.equilibria_of(model, bands=True)
        wall = time.perf_counter() - t0
        u = Units.of_scene(model.scene)
        return cls(model.scene.name, m, [replace(e, units=u) for e in rep.equilibria], list(rep.singularities),
                   rep.z_c, rep.max_mass,
                   rep.stable_band, list(rep.stable_bands), rep.adiabatic_band, hover_reasons(rep, m),
                   eqm.scale_of(model), list(eqm.span_of(model) or ()) or None,
                   {"z_stable": stated(model.scene, "z_stable")}, wall,
                   TILTED_NOTE if "base_tilt" in model.param_names else None, u)

    @property
    def reason(self) -> str | None:
        """The reasons in one sentence (the JSON's `reason`), None where the top can levitate."""
        return "; ".join(self.reasons) if self.reasons else None

    @property
    def stable_band_z(self) -> tuple[float, float] | None:
        return None if self.stable_band is None else tuple(self.stable_band.z)

    @property
    def stable_band_mass(self) -> tuple[float, float] | None:
        return None if self.stable_band is None else tuple(self.stable_band.mass)

    @property
    def success(self) -> bool:
        """A vertically stable hover height exists."""
        return any(e.vertically_stable for e in self.equilibria)

    @property
    def message(self) -> str:
        stable = [e.z for e in self.equilibria if e.vertically_stable]
        u = self.units
        head = (f"hovers vertically stable at z = {quantity(u, stable[0], 'm')}" if stable
                else "no vertically stable hover height")
        band = ("no stable band" if self.stable_band_z is None else
                f"stable band z {self.stable_band_z[0]:.6g}-{quantity(u, self.stable_band_z[1], 'm')}, mass "
                f"{self.stable_band_mass[0]:.6g}-{quantity(u, self.stable_band_mass[1], 'kg')}")
        return f"{head}; {band}"

    def __repr__(self) -> str:
        u = self.units
        zs = ", ".join(f"{quantity(u, e.z, 'm')} ({'stable' if e.vertically_stable else 'unstable'})"
                       for e in self.equilibria) or "none"
        band = "None" if self.stable_band_z is None else \
            f"z {self.stable_band_z[0]:.6g}-{quantity(u, self.stable_band_z[1], 'm')}"
        zc = "None" if self.z_c is None else quantity(u, self.z_c, "m")
        return f"Equilibria([{zs}], z_c={zc}, stable_band={band}, success={self.success})"

    def as_json(self) -> dict:
        """docs/contract.md's `equilibrium --json` (SI)."""
        out = {
            "scene": self.scene,
            "mass": self.mass,
            "equilibria": [e.as_dict() for e in self.equilibria],
            "singularities": [s.as_dict() for s in self.singularities],
            "z_c": self.z_c,
            "max_mass": self.max_mass,
            "stable_band": _band(self.stable_band),
            "stable_bands": [b.as_dict() for b in self.stable_bands],
            "adiabatic_band": _band(self.adiabatic_band),
            "adiabatic_note": ADIABATIC_NOTE,
            "reason": self.reason,
            "length_scale": self.length_scale,
            "z_range": self.z_range,
            "reference": self.reference,
            "wall_s": self.wall_s,
        }
        if self.note is not None:
            out["note"] = self.note
        return out
