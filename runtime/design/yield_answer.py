"""The answer to "which design makes the most kits of a production run float after their owners
trim them?": `YieldDesign` (`optimize --maximize yield --json` is its as_json(); computed by
runtime/design/yield_design.py on runtime/design/production.py's yield)."""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from levitron.runtime.design.production import Production, washer_text
from levitron.runtime.design.sharpness import sharpness_lines
from levitron.runtime.ui.answer_lines import as_written, keep_said, worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plain_text import NOTHING_SAID


def percent(block: dict) -> str:
    lo, hi = block["probability_ci95"]
    return f"{100 * block['probability']:.3g} % (95 %: {100 * lo:.3g}-{100 * hi:.3g} %)"


def yield_lines(r: dict, u: Units, scene=None) -> list[str]:
    """The plain view of a yield design's JSON: the design, the yield with the owners' washers and
    as shipped, at the design and as written, the washers chosen, the warnings."""
    keys = ", ".join(f"{k} = {u.mass(v) if k == 'top.mass' else f'{v:.6g}'}" for k, v in r["optimum"].items())
    used = {row["added"]: row["kits"] for row in r["washers_used"]}
    return [f"yield design: {keys}",
            f"yield (kits that float a launch after their owners trim them): {percent(r['yield'])}; "
            f"as written {percent(r['start_yield'])}",
            f"as shipped, no washer: {percent(r['as_shipped'])} at the design, {percent(r['start_as_shipped'])} "
            "as written",
            f"washers the owners put on (kits): {washer_text(used, u.mass)}",
            *([f"kits spread in scene keys, each at its own parameters: {keyed}"]
              if (keyed := ", ".join(f"{k} {v}" for k, v in r["production"]["kit"].items() if "." in k)) else []),
            *sharpness_lines(r.get("sharpness"), u, scene, "yield"),
            *(f"warning: {w}" for w in r["warnings"])]


@dataclass(frozen=True, repr=False)
class YieldDesign:
    """The yield optimum (docs/contract.md `optimize --maximize yield`): `optimum` and `start`
    {scene key: value} (SI); `at_optimum` and `at_start` production_yield's answers on fresh kits
    (yield, as_shipped, untrimmable, washers_used, curve); the production run (kit spreads,
    washers, kits, seed); the launch spread (`inputs`) and success time; every point the search
    evaluated, its best yield; wall_s; warnings; `scene` the scene it designed (write_scene)."""
    optimum: dict[str, float]
    start: dict[str, float]
    at_optimum: dict
    at_start: dict
    production: Production
    inputs: dict[str, str]
    success_time: float
    evaluations: list[dict]
    search_yield: float
    wall_s: float
    warnings: list[str] = field(default_factory=list)
    scene: object = field(default=None, compare=False)
    sharpness: dict | None = None       # the yield at +- a tolerance of each key, the ridge (sharpness.py)
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, repr=False, compare=False)  # warnings as written

    def __post_init__(self) -> None:
        keep_said(self, warnings=self.warnings)

    @property
    def probability(self) -> float:
        """The yield at the optimum (fresh kits)."""
        return self.at_optimum["yield"]["probability"]

    @property
    def success(self) -> bool:
        """Kits float at the optimum (a design where none does raises instead)."""
        return self.probability > 0

    @property
    def message(self) -> str:
        return "; ".join(self.lines())

    def __repr__(self) -> str:
        return text_repr("YieldDesign", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table("Yield design", self.lines())

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (yield_lines of as_json: the one wording of every face), in `units`
        (default the scene's), worded for `face` (None: the markers kept)."""
        u = units or self.units
        return worded(yield_lines(as_written(self.as_json(), self.said, self.units), u, self.scene), u, face)

    def as_json(self) -> dict:
        """docs/contract.md's `optimize --maximize yield` object (SI)."""
        p = self.production
        return {"objective": self.probability, "objective_name": "yield", "objective_unit": "1",
                "optimum": self.optimum, "start": self.start,
                "yield": self.at_optimum["yield"], "start_yield": self.at_start["yield"],
                "as_shipped": self.at_optimum["as_shipped"], "start_as_shipped": self.at_start["as_shipped"],
                "untrimmable": self.at_optimum["untrimmable"],
                "washers_used": [{"added": w, "kits": k} for w, k in self.at_optimum["washers_used"].items()],
                "owner_curve": self.at_optimum["curve"],
                "production": {"kit": dict(p.specs), "washers": list(p.washers), "kits": p.kits,
                               "seed": p.seed},
                "search": {"method": "common random numbers on a grid, zoomed; the answer and the start "
                                     "on fresh kits (runtime/design/yield_design.py, production.py)",
                           "evaluations": len(self.evaluations), "best_search_yield": self.search_yield,
                           "points": self.evaluations},
                "inputs": self.inputs, "success_time": self.success_time, "warnings": self.warnings,
                "sharpness": self.sharpness,
                "solver_status": "grid search", "wall_s": self.wall_s}

    def write_scene(self, path) -> str:
        """Write the scene at the optimum to path (.toml; runtime/design/scene_write.py)."""
        from levitron.runtime.design.scene_write import write_design
        return write_design(self.scene, self.optimum, "yield", path)

    @property
    def units(self) -> Units:
        return Units.of_scene(self.scene) if self.scene is not None else Units(si=True)
