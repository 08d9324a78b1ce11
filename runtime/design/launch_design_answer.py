"""The answer to "at which scene keys does a launch by hand float most often?": `LaunchDesign`, one
type for every face (`optimize --maximize launch-odds --json` is its `as_json()`, `Study.optimize(
"launch-odds", ...)` returns it, `Trim` carries it). Computed by runtime/design/launch_design.py:
the launch odds of runtime/scan/launch_odds.py searched on common random numbers, the optimum and
the scene as written then judged on fresh draws, with their 95 % Wilson intervals.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from levitron.runtime.ui.human import Units


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

    @property
    def probability(self) -> float:
        """The launch odds at the optimum (fresh draws)."""
        return self.launch_odds["probability"]

    @property
    def success(self) -> bool:
        """scipy-style: the search ran to its answer (a design no launch floats raises instead)."""
        return True

    @property
    def message(self) -> str:
        """scipy-style: the odds at the optimum and at the start, then every warning."""
        lo, hi = self.launch_odds["probability_ci95"]
        return "; ".join([f"launch odds {100 * self.probability:.3g} % (95 %: {100 * lo:.3g}-{100 * hi:.3g} %) "
                          f"at the optimum, {100 * self.start_launch_odds['probability']:.3g} % as written",
                          *knife_edges(self.sharpness), *self.warnings])

    def __repr__(self) -> str:
        keys = ", ".join(f"{k}={v:.6g}" for k, v in self.optimum.items())
        return (f"LaunchDesign(launch-odds={self.probability:.3g} at {keys}, n={self.n}, "
                f"warnings={len(self.warnings)})")

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
        from levitron.runtime.design.scene_keys import with_values
        from levitron.runtime.design.scene_write import shortest, write_scene
        from levitron.runtime.words import render
        note = (f"levitron optimize {self.scene.name} «maximize=launch-odds»: "
                + ", ".join(f"{k} = {v:.6g}" for k, v in self.optimum.items()))
        at = with_values(self.scene, {k: shortest(v) for k, v in self.optimum.items()})
        return str(write_scene(at, path, render(note, "cli")))

    @property
    def units(self) -> Units:
        return Units.of_scene(self.scene) if self.scene is not None else Units(si=True)
