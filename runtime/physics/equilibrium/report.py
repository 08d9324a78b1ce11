"""What the equilibrium finder (runtime/physics/equilibrium/finder.py) finds, thesis 3.3.1-3.3.3: each
vertical equilibrium (`Equilibrium`: z, vertically stable where U'' = mu Phi_3 > 0, its stiffness),
each stretch where the on-axis functions are not finite (`Singularity`), and the whole report
(`EquilibriumReport`: equilibria, z_c, the largest mass, the stable and adiabatic bands), with the
sentences that say why a top cannot hover (`hover_reasons`). The answer of the `equilibrium`
command, `Equilibria`, is built from it (runtime/physics/equilibrium/answer.py). No sympy here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

from levitron.runtime.ui.human import Units
from levitron.runtime.words import si, si_span


@dataclass(frozen=True, repr=False)
class Equilibrium:
    """One vertical equilibrium (thesis 3.3.2): z (m), vertically_stable (mu Phi_3 > 0, 3.3.3),
    stiffness U'' = mu Phi_3 (N/m), marginal (a double root at z_c)."""
    z: float
    vertically_stable: bool
    stiffness: float         # U''(z) = mu Phi_3(z) (thesis 3.3.3)
    marginal: bool = False   # a double root (the mass is the plate's maximum): U'' = 0
    units: Units = field(default=Units(si=True), compare=False)   # how repr shows numbers

    def lines(self, units: Units | None = None) -> list[str]:
        """Its plain view in `units` (default its own): the height, its kind, the stiffness."""
        u = units or self.units
        kind = "marginal" if self.marginal else "stable" if self.vertically_stable else "unstable"
        return [f"z: {u.length(self.z)}", f"vertically {kind}", f"stiffness: {u.value(self.stiffness, 'N/m')}"]

    def __repr__(self) -> str:
        from levitron.runtime.ui.answer_view import text_repr
        return text_repr("Equilibrium", self.lines())

    def _repr_html_(self) -> str:
        from levitron.runtime.ui.answer_view import html_table
        return html_table("Equilibrium", self.lines())

    def as_dict(self) -> dict:
        return {"z": self.z, "vertically_stable": self.vertically_stable,
                "stiffness": self.stiffness, "marginal": self.marginal}


@dataclass(frozen=True)
class Singularity:
    """Where the on-axis functions are not finite: a pole at z (z_end == z), or a stretch
    [z, z_end] of NaN or inf values (z = 0 / z_end = inf when it reaches the end of the search)."""
    z: float
    z_end: float
    kind: str                # "pole" | "nan" | "inf"

    def as_dict(self) -> dict:
        return {"z": self.z, "z_end": self.z_end if math.isfinite(self.z_end) else None,
                "kind": self.kind}


@dataclass
class EquilibriumReport:
    equilibria: list[Equilibrium]
    z_c: float | None
    max_mass: float | None
    singularities: list[Singularity] = field(default_factory=list)
    stable_bands: list = field(default_factory=list)       # runtime.physics.equilibrium.bands.Band
    adiabatic_bands: list = field(default_factory=list)

    @property
    def stable(self) -> list[Equilibrium]:
        return [e for e in self.equilibria if e.vertically_stable]

    @property
    def stable_band(self):
        """The widest stable band (docs/contract.md reports one; all are in stable_bands)."""
        return max(self.stable_bands, key=lambda b: b.z[1] - b.z[0]) if self.stable_bands else None

    @property
    def adiabatic_band(self):
        return max(self.adiabatic_bands, key=lambda b: b.z[1] - b.z[0]) if self.adiabatic_bands else None

    def no_hover_reason(self, m: float) -> str | None:
        """Why a top of mass m has no vertically stable hover height (None if it has one)."""
        if self.stable:
            return None
        sing = ""
        if self.singularities:
            sing = ("; the on-axis functions are singular at " + ", ".join(
                f"z = {si(s.z, 'm')} ({s.kind})" if s.kind == "pole" else
                f"z in {si_span(s.z, s.z_end, 'm')} ({s.kind})" for s in self.singularities))
        marginal = [e for e in self.equilibria if e.marginal]
        if marginal:
            return (f"the top ({si(m, 'kg')}) is exactly as heavy as the plate can hold: a double root "
                    f"at z_c = {si(marginal[0].z, 'm')} with U'' = 0, marginal, not vertically stable "
                    "(thesis 3.3.3); take a lighter top" + sing)
        if self.equilibria:
            return ("no vertically stable equilibrium: at every root of m g + mu Phi_2 = 0 "
                    f"(z = {si(', '.join(f'{e.z:.6g}' for e in self.equilibria), 'm')}) mu Phi_3 <= 0 "
                    "(thesis 3.3.3)" + sing)
        if self.max_mass is not None and self.z_c is not None and m > self.max_mass:
            return (f"the top of mass {si(m, 'kg')} is too heavy for the plate, which holds at most "
                    f"{si(self.max_mass, 'kg')} (at z_c = {si(self.z_c, 'm')})" + sing)
        return (f"m g + mu Phi_2(z) has no root for z > 0: the field cannot hold a top of mass "
                f"{si(m, 'kg')} with this moment" + sing)


def hover_reasons(rep: EquilibriumReport, m: float) -> list[str]:
    """Why a top of mass m cannot be made to levitate over this plate, as SI sentences (the JSON's
    `reason`), each ending in what would help: no vertically stable height; no stable band; or a
    hover height outside the band (thesis 3.3.2-3.3.3), then with the masses that would hover
    inside it. Empty where the top hovers inside a stable band."""
    reasons = [rep.no_hover_reason(m)] if not rep.stable else []
    band = rep.stable_band
    if band is None:
        reasons.append("no height admits a spin rate that stabilises the top (no stable band)")
    else:
        zs = [e.z for e in rep.equilibria if e.vertically_stable]
        if not zs:
            reasons.append(f"a top of mass in {si_span(*band.mass, 'kg')} would hover "
                           f"inside the stable band {si_span(*band.z, 'm')}")
        elif not any(b.z[0] <= z <= b.z[1] for b in rep.stable_bands for z in zs):
            reasons.append(f"this top hovers at z = {si(zs[0], 'm')}, outside the stable band "
                           f"{si_span(*band.z, 'm')}: no spin stabilises it there; a top of "
                           f"mass in {si_span(*band.mass, 'kg')} would hover inside it")
    return reasons
