"""The answer to "at which scene keys does a launch by hand float most often?": `LaunchDesign`, one
type for every face (`optimize --maximize launch-odds --json` is its `as_json()`, `Study.optimize(
"launch-odds", ...)` returns it, `Trim` carries it). Computed by runtime/design/launch_design.py:
the launch odds of runtime/scan/launch_odds.py searched on common random numbers, the optimum and
the scene as written then judged on fresh draws, with their 95 % Wilson intervals.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from levitron.runtime.design.sharpness import sharpness_lines
from levitron.runtime.ui.answer_lines import as_written, keep_said, worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plain_text import NOTHING_SAID


def knife_edges(block: dict | None) -> list[str]:
    """One sentence for each key of a sharpness block that is a knife edge (the message's; the
    tolerance itself is the block's, in the key's SI unit)."""
    out = []
    for k, r in ((block or {}).get("keys") or {}).items():
        if r["knife_edge"]:
            sides = ["none" if v is None else f"{v:.3g}" for v in (r["at_minus"], r["at_plus"])]
            out.append(f"a knife edge: {k} at +- its tolerance takes the objective from {block['objective']:.3g} "
                       f"to {sides[0]} and {sides[1]}")
    return out


def odds_text(block: dict) -> str:
    """Launch odds with their 95 % Wilson interval: "61.5 % (54.6-68 %)"."""
    lo, hi = block["probability_ci95"]
    if hi == 0:                         # odds_at: a design whose top cannot hover floats never
        return "0 % (it cannot hover)"
    return f"{sig(100 * block['probability'], 3)} % ({sig(100 * lo, 3)}-{sig(100 * hi, 3)} %)"


def start_text(block: dict, whose: str = "the answer's") -> str:
    """The start's odds (odds_text), and where they are paired with the answer's first launches
    (runtime/design/paired_fresh.py start_odds), on how many: "76 % (67-84 %) on the answer's
    first 250 launches, paired"."""
    if not block.get("paired_with"):
        return odds_text(block)
    return f"{odds_text(block)} on {whose} first {block['n']} launches, paired"


def change_text(key: str, start: float, to: float, u: Units) -> str:
    """"take 1.2 g off" / "add 0.3 g" for the top's mass; "set KEY from A to B" for any key; "keep
    KEY at A" where the design is the scene as written."""
    if to == start:
        return f"keep the mass at {u.mass(start)}" if key == "top.mass" else f"keep {key} at {sig(start, 6)}"
    if key == "top.mass":
        d = to - start
        return f"take {u.mass(-d)} off" if d < 0 else f"add {u.mass(d)}"
    return f"set {key} from {sig(start, 6)} to {sig(to, 6)}"


def warning_lines(r: dict) -> list[str]:
    """Every warning of an answer's JSON, one a line (its quantities' markers shown by the face)."""
    return [f"warning: {w}" for w in r.get("warnings") or []]


def launch_odds_lines(r: dict, u: Units, scene=None) -> list[str]:
    """The launch-odds design in plain view: the advice and what it does to the odds."""
    from levitron.runtime.scan.launch_answer import launches_line
    a, b = r["start_launch_odds"], r["launch_odds"]
    advice = "; ".join(change_text(k, r["start"][k], v, u) for k, v in r["optimum"].items())
    search = r["search"]
    return [f"{advice}: odds {sig(100 * a['probability'], 3)} % -> {sig(100 * b['probability'], 3)} %",
            "optimum: " + ", ".join(f"{k} = {u.mass(v) if k == 'top.mass' else sig(v, 6)}"
                                    for k, v in r["optimum"].items())
            + f": {odds_text(b)} of {b['n']} launches float at least {u.time(r['success_time'])} (seed {b['seed']})",
            f"as written: {start_text(a)} (the same seed)",
            launches_line(r, u, scene),
            f"searched: {search['evaluations']} designs of {search.get('launches_per_point', search['n'])} launches "
            f"each on common random numbers (seed {search['seed']}){_judged(search, r['success_time'], u)}, the best "
            f"at {sig(100 * search['best_search_odds'], 3)} % (biased upwards: the best of {search['evaluations']}); "
            f"decided on the fresh seed {b['seed']}"]


def _judged(search: dict, success_time: float, u: Units) -> str:
    """When the search judged its launches, where earlier than the success time: its odds rank the
    designs, the answer's are the ones to read (runtime/design/launch_design.py step 2)."""
    t = search.get("search_time")
    if t is None or t >= success_time * (1 - 1e-12):
        return ""
    return f", judged at {u.time(t)} of the {u.time(success_time)} flight (to rank them, not for their odds)"


def launch_design_lines(r: dict, u: Units, scene=None) -> list[str]:
    """The plain view of a launch-odds design's JSON: the advice, the odds, the launches, the
    search; the design's sharpness; the warnings."""
    return [*launch_odds_lines(r, u, scene), *sharpness_lines(r.get("sharpness"), u, scene),
            *warning_lines(r), u.note]


@dataclass(frozen=True, repr=False)
class LaunchDesign:
    """The launch-odds optimum (docs/contract.md `optimize --maximize launch-odds`): `optimum` and
    `start` {scene key: value} (SI), their odds on fresh draws (`launch_odds`, `start_launch_odds`:
    probability, its 95 % Wilson interval probability_ci95, n, seed,
    successes), the search's best estimate and every point it evaluated, the
    launch spread it ran (`inputs`; `defaulted`: those no flag or [launch] table gave), n, seed,
    success_time and t_end (s), the warnings; `scene` the scene it designed (for write_scene);
    `work` what the search ran: evaluations, stopped_early, duplicates, launches_run and
    launches_full (the launches without paired stopping); `sharpness` the odds on the same fresh
    draws at +- a maker's tolerance of each key, the knife-edge verdicts and, for two or three
    keys, the ridge (runtime/design/sharpness.py; docs/contract.md `optimize`)."""
    optimum: dict[str, float]
    start: dict[str, float]
    launch_odds: dict
    start_launch_odds: dict
    search_odds: float
    evaluations: list[dict]
    inputs: dict[str, str]
    success_time: float
    t_end: float
    seed: int
    n: int
    wall_s: float
    warnings: list[str] = field(default_factory=list)
    defaulted: list[str] = field(default_factory=list)     # the inputs no flag or [launch] table gave
    scene: object = field(default=None, compare=False)
    work: dict = field(default_factory=dict, compare=False)   # runtime/design/paired_odds.py's counts
    sharpness: dict | None = None       # the odds at +- a tolerance of each key, the ridge (sharpness.py)
    paired: dict = field(default_factory=dict, compare=False)   # the optimum's fresh verdicts (not in the JSON)
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, repr=False, compare=False)  # warnings as written

    def __post_init__(self) -> None:
        keep_said(self, warnings=self.warnings)

    @property
    def probability(self) -> float:
        """The launch odds at the optimum (fresh draws)."""
        return self.launch_odds["probability"]

    @property
    def success(self) -> bool:
        """scipy-style: the search ran to its answer (a design no launch floats raises instead)."""
        return True

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (launch_design_lines of as_json: the one wording of every face), in
        `units` (default the scene's), worded for `face` (None: the markers kept)."""
        u = units or self.units
        return worded(launch_design_lines(as_written(self.as_json(), self.said, self.units), u, self.scene), u, face)

    @property
    def message(self) -> str:
        return "; ".join(self.lines())

    def __repr__(self) -> str:
        return text_repr("LaunchDesign", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table("Launch-odds design", self.lines())

    def as_json(self) -> dict:
        """docs/contract.md's `optimize --maximize launch-odds` object (SI)."""
        return {"objective": self.probability, "objective_name": "launch-odds", "objective_unit": "1",
                "optimum": self.optimum, "start": self.start, "launch_odds": self.launch_odds,
                "start_launch_odds": self.start_launch_odds, "warnings": self.warnings,
                "search": {"method": "common random numbers on a grid, zoomed, each point compared launch by "
                                     "launch with the best so far and stopped once clearly worse "
                                     "(runtime/design/launch_design.py, paired_odds.py)",
                           "seed": self.seed, "n": self.n, "evaluations": len(self.evaluations),
                           "best_search_odds": self.search_odds, "points": self.evaluations, **self.work},
                "inputs": self.inputs, "defaulted": self.defaulted, "success_time": self.success_time,
                "t_end": self.t_end, "sharpness": self.sharpness,
                "solver_status": "grid search", "wall_s": self.wall_s}

    # ---- actions
    def write_scene(self, path) -> str:
        """Write the scene at the optimum (re-validated) to path (.toml; runtime/design/scene_write.py),
        its first line naming the design."""
        from levitron.runtime.design.scene_write import write_design
        return write_design(self.scene, self.optimum, "launch-odds", path)

    @property
    def units(self) -> Units:
        return Units.of_scene(self.scene) if self.scene is not None else Units(si=True)
