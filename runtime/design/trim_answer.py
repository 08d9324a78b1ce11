"""The answer to "what mass should I set so that most launches by hand float?": `Trim`, one type for
every face (the CLI's `trim --json` is its `as_json()`, `Study.trim()` returns it, its plot reads it).
Computed by runtime/design/trim.py: the launch-odds design over top.mass in the stable band (thesis
3.3.2-3.3.3), beside the spin window of every mass (thesis 3.3.15-3.3.19) and the odds at the widest.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from levitron.runtime.design.launch_design_answer import (LaunchDesign, change_text, odds_text, start_text,
                                                           warning_lines)
from levitron.runtime.ui.answer_lines import as_written, keep_said, worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plain_text import NOTHING_SAID

_SI = Units(si=True)


def trim_lines(r: dict, u: Units, scene=None) -> list[str]:
    """The plain view of a trim's JSON, answer first: the change and what it does to the odds; then
    the band and the widest window; the launches; the plot (`out` where given); the warnings."""
    from levitron.runtime.scan.launch_answer import launches_line
    a, b, w = r["start_launch_odds"], r["launch_odds"], r["widest_window"]
    lo, hi = r["band_mass"]
    iv = w["spin_interval"]
    change = change_text("top.mass", r["mass"], r["advice"], u)
    change += f" (to {u.mass(r['advice'])})" if r["advice"] != r["mass"] else ""
    first = (f"{change}: launch odds {odds_text(a)} -> {odds_text(b)} of {b['n']} launches floating at least "
             f"{u.time(r['success_time'])}" + (f" (as written on the first {a['n']}, paired: enough to decide "
                                                "the difference)" if a.get("paired_with") else ""))
    if r.get("no_change"):
        than = "no more often than" if a.get("paired_with") else "inside the interval of"
        first = (f"no change: the best mass ({change}) floats {odds_text(b)}, {than} the "
                 f"mass as written, {start_text(a)}, of {b['n']} launches floating at least "
                 f"{u.time(r['success_time'])}")
    return [
        first,
        f"the masses that hover: {u.mass(lo)} to {u.mass(hi)}; as written {u.mass(r['mass'])}",
        f"the widest spin window ({u.rate_span(*iv)}) is at {u.mass(w['mass'])}: odds there "
        f"{odds_text(w['launch_odds'])}" if iv else "",
        launches_line(r["design"], u, scene),
        f"plot: {r['out']}" if r.get("out") else "",
        *warning_lines(r), u.note]


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
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, repr=False, compare=False)  # warnings as written

    def __post_init__(self) -> None:
        keep_said(self, warnings=self.warnings)

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
        """Whether the advice is to change nothing (the best mass stays in `advice`, as data). The
        mass as written runs paired with the best on the same fresh draws and stops once McNemar's
        test decides their difference (runtime/design/paired_fresh.py): then the change is real, and
        it is advised where the best floats more often. Where nothing decided it (all n run), the
        search cannot tell the change from its own noise when the best mass's odds lie inside the
        95 % interval of the odds as written."""
        start = self.design.start_launch_odds
        if start.get("paired_with"):
            return self.probability <= start["probability"]
        lo, hi = start["probability_ci95"]
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

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (trim_lines of as_json: the one wording of every face), in `units`
        (default the scene's), worded for `face` (None: the markers kept)."""
        u = units or self.units
        written = {"warnings": (*self.said.get("warnings", ()), *self.design.said.get("warnings", ()))}
        return worded(trim_lines(as_written(self.as_json(), written, self.units), u, self.design.scene), u, face)

    @property
    def message(self) -> str:
        return "; ".join(self.lines())

    def __repr__(self) -> str:
        return text_repr("Trim", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table("Trim", self.lines())
