"""The answer to "where does the top hover?": `Equilibria`, one type for every face (the CLI's
`equilibrium --json` is its `as_json()`, `Study.equilibria()` returns it, the report reads it).

Thesis 3.3.1-3.3.3: the vertical equilibria (roots of m g + mu Phi_2(z) = 0, vertically stable
where U'' = mu Phi_3 > 0), z_c (the zero of Phi_3) and the largest mass m(z_c); the stable band of
docs/contract.md (runtime/physics/equilibrium/bands.py) and, beside it, never instead, Berry-Simon's adiabatic one.
"""
from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace

from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.physics.equilibrium.bands import Band
from levitron.runtime.physics.equilibrium.report import Equilibrium, Singularity, hover_reasons
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plain_text import NOTHING_SAID, said
from levitron.runtime.ui.reference import stated
from levitron.runtime.words import render

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
    reasons: why this top cannot levitate and what would help (empty where it can). Its words:
    `lines(units)` (runtime/physics/equilibrium/view.py), which the command line prints and
    message, repr and the notebook reuse."""

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
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, compare=False)   # the reasons as written (markers)

    @classmethod
    def of(cls, model) -> Equilibria:
        """The equilibria of `model`'s top at the scene's parameters (runtime/physics/equilibrium/finder.py)."""
        m = eqm.params_of(model)["m"]
        t0 = time.perf_counter()
        rep = eqm.equilibria_of(model, bands=True)
        wall = time.perf_counter() - t0
        u = Units.of_scene(model.scene)
        reasons = hover_reasons(rep, m)
        return cls(model.scene.name, m, [replace(e, units=u) for e in rep.equilibria], list(rep.singularities),
                   rep.z_c, rep.max_mass,
                   rep.stable_band, list(rep.stable_bands), rep.adiabatic_band, reasons,
                   eqm.scale_of(model), list(eqm.span_of(model) or ()) or None,
                   {"z_stable": stated(model.scene, "z_stable")}, wall,
                   TILTED_NOTE if "base_tilt" in model.param_names else None, u, said(reasons=reasons))

    @classmethod
    def from_json(cls, r: dict, units: Units = _SI) -> Equilibria:
        """The answer again from its as_json() (the command line's plain view reads it so)."""
        def band(b):
            return None if b is None else Band(tuple(b["z"]), tuple(b["mass"]),
                                               tuple(b.get("at_search_end") or (False, False)))
        eqs = [Equilibrium(e["z"], e["vertically_stable"], e["stiffness"], e.get("marginal", False), units)
               for e in r["equilibria"]]
        sing = [Singularity(s["z"], math.inf if s.get("z_end") is None else s["z_end"], s["kind"])
                for s in r.get("singularities") or []]
        return cls(r.get("scene", ""), r["mass"], eqs, sing, r.get("z_c"), r.get("max_mass"),
                   band(r.get("stable_band")), [band(b) for b in r.get("stable_bands") or []],
                   band(r.get("adiabatic_band")), [r["reason"]] if r.get("reason") else [],
                   r.get("length_scale", 1.0), r.get("z_range"), r.get("reference") or {}, r.get("wall_s", 0.0),
                   r.get("note"), units)

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

    # ---- its words, one function for every face (runtime/physics/equilibrium/view.py)
    def lines(self, units: Units | None = None) -> list[str]:
        """The plain view in `units` (default the scene's): what `levitron equilibrium` prints."""
        from levitron.runtime.physics.equilibrium import view as equilibria_view
        return equilibria_view.lines(self, units or self.units)

    def summary(self, units: Units | None = None) -> str:
        """The answer in one sentence: the equilibria, the band, and why not where the top cannot."""
        from levitron.runtime.physics.equilibrium import view
        from levitron.runtime.ui.plain_text import shown
        u = units or self.units
        why = view.reason(self)
        return "; ".join([view.roots(self, u), view.band_line(self, u)] + ([f"reason: {shown(why, u)}"] if why else []))

    @property
    def message(self) -> str:
        return render(self.summary(), "api", self.units)

    def __repr__(self) -> str:
        from levitron.runtime.physics.equilibrium import view
        u = self.units
        return render(text_repr("Equilibria", [view.roots(self, u), view.band_line(self, u).split("   (")[0],
                                               f"success={self.success}"]), "api", u)

    def _repr_html_(self) -> str:
        return render(html_table("Equilibria", self.lines()), "api", self.units)

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
