"""The answer to "which scene keys give the widest window of spins (or masses)?": `Design`, one
type for every face (`optimize --maximize spin-range|spin-ratio|mass-window --json` is its
`as_json()`, `Study.optimize` returns it; docs/contract.md `optimize`, thesis 3.3). Writing the
scene at the optimum is an action on it: `write_scene(path)`. runtime/design/optimize.py computes it.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from levitron.scene.load import Scene

from levitron.runtime.design.launch_design_answer import knife_edges, odds_text, start_text, warning_lines
from levitron.runtime.design.sharpness import sharpness_lines
from levitron.runtime.ui.answer_lines import as_written, keep_said, worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plain_text import NOTHING_SAID

OBJECTIVES = {"spin-range": ("sigma_hi - sigma_lo", "rad/s"),
              "spin-ratio": ("sigma_hi / sigma_lo", "1"),
              "mass-window": ("(m_hi - m_lo) / m_hi", "1")}


def cost_lines(r: dict, u: Units) -> list[str]:
    """What another objective's optimum costs in launches (scenes in air or with a [launch] table)."""
    if "launch_odds" not in r:
        return []
    best = r["launch_odds_optimum"]
    where = ", ".join(f"{k} = {u.mass(v) if k == 'top.mass' else sig(v, 6)}" for k, v in best["optimum"].items())
    start = start_text(r["start_launch_odds"], "the launch-odds optimum's")
    return [f"launch odds at this optimum: {odds_text(r['launch_odds'])}; as written {start}; "
            f"the launch-odds optimum ({where}) {odds_text(best['launch_odds'])}"]


def design_lines(r: dict, u: Units, scene=None) -> list[str]:
    """The plain view of a design's JSON, answer first: the optimum; the band and the spin interval
    there; how it was verified; its sharpness; what it costs in launches (where the face added
    them); the warnings; the scene written (`written` where given)."""
    best = ", ".join(f"{k} = {sig(v, 6)}" for k, v in r["optimum"].items())
    iv, band = r.get("spin_interval"), r.get("band")
    ver = r["verification"]
    unit = u.unit(r.get("objective_unit") or "1")      # a ratio: no unit to show
    return [
        f"optimum: {best}: {r['objective_name']} {sig(r['objective'], 6)} {unit}".rstrip(),
        f"stable band {u.length(band['z'][0])} to {u.length(band['z'][1])}, tops of "
        f"{u.mass(band['mass'][0])} to {u.mass(band['mass'][1])}" if band else "",
        (f"{'the scene top' + chr(39) + 's ' if band else ''}spin interval {u.rate_span(*iv)} "
         f"at z_s = {u.length(r['z_s'])}") if iv
        else "the scene's top has no stable spin interval there" if band else "",
        f"the scene itself: {r['objective_name']} {sig(r['scene_objective'], 6)} {unit}".rstrip()
        if r.get("scene_objective") is not None else "",
        f"verified: float route at the optimum, best of {ver['grid_points']} grid points "
        f"{sig(ver['grid_best'], 6) if ver.get('grid_best') is not None else 'none feasible'} {unit}".rstrip(),
        f"solver: {r['solver_status']}, {r['iterations']} iterations",
        *sharpness_lines(r.get("sharpness"), u, scene, r["objective_name"], r.get("objective_unit") or "1"),
        *cost_lines(r, u), *warning_lines(r),
        f"scene written: {r['written']} (check it: «levitron=stability» {r['written']})"
        if r.get("written") else "", u.note]


@dataclass(repr=False)
class Design:
    """A verified design optimum (docs/contract.md `optimize`).

    objective: name; value: objective at the optimum (spin-range in rad/s, spin-ratio
    and mass-window dimensionless); optimum: scene key -> value (the key's unit,
    docs/scenes.md); start: where IPOPT started (the grid's best point); z_s (m), stiffness (N/m),
    spin_interval (rad/s; None where it has none) of the scene's top at the optimum; band (mass-window:
    {"z": [z_lo, z_hi] m, "mass": [m_lo, m_hi] kg}, the float route's); scene: the re-validated
    scene at the optimum; verification: float_route (the objective by the exact float routes),
    grid_best, grid_points, grid_feasible, max_relative_gap (NLP vs float route); sharpness: the
    objective by the float routes at +- a maker's tolerance of each key, the knife-edge verdicts
    and, for two or three keys, the ridge (runtime/design/sharpness.py)."""

    objective: str
    value: float
    optimum: dict[str, float]
    start: dict[str, float]
    start_value: float
    scene_value: float | None
    solver_status: str
    iterations: int
    z_s: float | None
    stiffness: float | None
    spin_interval: tuple[float, float] | None
    band: dict | None
    constraints: list[str]
    verification: dict
    scene: Scene = field(repr=False)
    wall_s: float = 0.0
    at_bound: dict[str, str] = field(default_factory=dict)   # key -> "lower" | "upper" (--vary bound)
    warnings: list[str] = field(default_factory=list)        # plain sentences: at a bound, vanishing stiffness
    sharpness: dict | None = None      # the objective at +- a tolerance of each key, the ridge (sharpness.py)
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, repr=False, compare=False)  # warnings as written

    def __post_init__(self) -> None:
        keep_said(self, warnings=self.warnings)

    @property
    def success(self) -> bool:
        """scipy-style: IPOPT succeeded and the answer passed every check (a failure raises instead)."""
        return True

    @property
    def status_message(self) -> str:
        """scipy-style, the JSON's `message`: IPOPT's status, then every knife edge and warning."""
        return "; ".join([f"{self.solver_status}: {self.objective} {self.value:.6g} "
                          f"{self.objective_unit}", *knife_edges(self.sharpness), *self.warnings])

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (design_lines of as_json: the one wording of every face), in `units`
        (default the scene's), worded for `face` (None: the markers kept)."""
        u = units or Units.of_scene(self.scene)
        return worded(design_lines(as_written(self.as_json(), self.said, u), u, self.scene), u, face)

    @property
    def message(self) -> str:
        return "; ".join(self.lines())

    @property
    def objective_unit(self) -> str:
        """The objective's unit: rad/s, 1; rad/time in a dimensionless scene."""
        return Units.of_scene(self.scene).named(OBJECTIVES[self.objective][1])

    def __repr__(self) -> str:
        return text_repr("Design", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table(f"Design: {self.objective}", self.lines())

    def as_json(self) -> dict:
        """docs/contract.md's `optimize --json` of a design (SI) but for the command's own keys: the
        launch odds the design costs (in air), `written`."""
        return {"objective": self.value, "objective_name": self.objective,
                "at_bound": self.at_bound, "warnings": self.warnings,
                "success": self.success, "message": self.status_message,
                "objective_unit": self.objective_unit,
                "objective_formula": OBJECTIVES[self.objective][0],
                "optimum": self.optimum, "start": self.start, "start_objective": self.start_value,
                "scene_objective": self.scene_value,
                "solver_status": self.solver_status, "iterations": self.iterations,
                "z_s": self.z_s, "stiffness": self.stiffness,
                "spin_interval": None if self.spin_interval is None else list(self.spin_interval),
                "band": self.band, "constraints": self.constraints,
                "verification": self.verification, "sharpness": self.sharpness, "wall_s": self.wall_s,
                "scene": self.scene.name}

    # ---- actions
    def write_scene(self, path) -> str:
        """Write the scene at the optimum (re-validated) to path (.toml; runtime/design/scene_write.py),
        its first line naming the design."""
        from levitron.runtime.design.scene_keys import with_values
        from levitron.runtime.design.scene_write import shortest, write_scene
        from levitron.runtime.words import render
        note = (f"levitron optimize {self.scene.name} «maximize» {self.objective}: "
                + ", ".join(f"{k} = {v:.6g}" for k, v in self.optimum.items()))
        at = with_values(self.scene, {k: shortest(v) for k, v in self.optimum.items()})
        return str(write_scene(at, path, render(note, "cli")))   # the command it names


DesignResult = Design      # its former name, kept for scripts that import it
