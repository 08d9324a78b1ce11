"""The answer to "what mass should I set so that most launches by hand float?": `Trim`, one type for
every face (the CLI's `trim --json` is its `as_json()`, `Study.trim()` returns it, its plot reads it).
Computed by runtime/design/trim.py: the launch-odds design over top.mass in the stable band (thesis
3.3.2-3.3.3), beside the spin window of every mass (thesis 3.3.15-3.3.19) and the odds at the widest.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from levitron.runtime.design.launch_design_answer import LaunchDesign
from levitron.runtime.ui.human import Units, sig

_SI = Units(si=True)


@dataclass(frozen=True, repr=False)
class Trim:
    """The trim (docs/contract.md `trim`): the scene's mass, the masses that hover (the stable band),
    the launch-odds design over them, the spin window of each mass (`limits`: [{mass, z_s,
    spin_interval}]) and the widest window with its launch odds; masses in kg, rates in rad/s (SI,
    or the scene's units); `units`: how repr and message show numbers."""

    mass: float
    band_mass: tuple[float, float]
    design: LaunchDesign = field(repr=False)
    limits: list = field(repr=False, default_factory=list)
    widest: dict = field(repr=False, default_factory=dict)
    warnings: list = field(default_factory=list)
    units: Units = field(default=_SI, repr=False, compare=False)

    @property
    def advice(self) -> float:
        """The mass to set: the launch-odds optimum over the band."""
        return self.design.optimum["top.mass"]

    @property
    def change(self) -> float:
        return self.advice - self.mass

    @property
    def probability(self) -> float:
        """The launch odds at the advice (fresh seed)."""
        return self.design.launch_odds["probability"]

    @property
    def start_probability(self) -> float:
        """The launch odds of the scene's own mass (fresh seed)."""
        return self.design.start_launch_odds["probability"]

    @property
    def no_change(self) -> bool:
        """The best mass's odds lie inside the 95 % interval of the odds as written (both on the
        fresh draws): the search cannot tell the change from its own noise, so the advice is to
        change nothing (the best mass stays in `advice`, as data)."""
        lo, hi = self.design.start_launch_odds["probability_ci95"]
        return lo <= self.probability <= hi

    @property
    def widest_window_mass(self) -> float:
        return self.widest["mass"]

    @property
    def widest_window_probability(self) -> float:
        return self.widest["launch_odds"]["probability"]

    @property
    def success(self) -> bool:
        """The search found launches that float (it raises UserError where none does)."""
        return self.probability > 0

    @property
    def details(self) -> dict:
        """Every key of the JSON (the spin limits of every mass, the design's search)."""
        return self.as_json()

    def as_json(self) -> dict:
        """docs/contract.md's `trim --json` (SI) but for the command's own `scene` and `out`."""
        d = self.design
        return {"mass": self.mass, "advice": self.advice, "change": self.change, "no_change": self.no_change,
                "band_mass": list(self.band_mass), "launch_odds": d.launch_odds,
                "start_launch_odds": d.start_launch_odds, "widest_window": self.widest,
                "spin_limits": self.limits, "inputs": d.inputs, "success_time": d.success_time,
                "t_end": d.t_end, "design": d.as_json(), "warnings": [*self.warnings, *d.warnings]}

    @property
    def message(self) -> str:
        d, u = self.change, self.units
        how = f"take {u.mass(-d)} off" if d < 0 else f"add {u.mass(d)}"
        if self.no_change:
            how = f"no change (the best mass, {how}, floats within the interval of the mass as written)"
        return (f"{how}: launch odds {sig(100 * self.start_probability, 3)}% -> {sig(100 * self.probability, 3)}%"
                f" (the widest spin window, at {u.mass(self.widest_window_mass)}: "
                f"{sig(100 * self.widest_window_probability, 3)}%)")

    def __repr__(self) -> str:
        return f"Trim({self.message})"
