"""The answer to "which scene keys give the widest window of spins (or masses)?": `Design`, one
type for every face (`optimize --maximize spin-range|spin-ratio|mass-window --json` is its
`as_json()`, `Study.optimize` returns it; docs/contract.md `optimize`, thesis 3.3). Writing the
scene at the optimum is an action on it: `write_scene(path)`. runtime/design/optimize.py computes it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from levitron.scene.load import Scene

from levitron.runtime.ui.human import Units

OBJECTIVES = {"spin-range": ("sigma_hi - sigma_lo", "rad/s"),
              "spin-ratio": ("sigma_hi / sigma_lo", "1"),
              "mass-window": ("(m_hi - m_lo) / m_hi", "1")}

@dataclass
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

    @property
    def success(self) -> bool:
        """scipy-style: IPOPT succeeded and the answer passed every check (a failure raises instead)."""
        return True

    @property
    def message(self) -> str:
        """scipy-style: IPOPT's status, then every warning."""
        from levitron.runtime.design.launch_design_answer import knife_edges
        return "; ".join([f"{self.solver_status}: {self.objective} {self.value:.6g} "
                          f"{self.objective_unit}", *knife_edges(self.sharpness), *self.warnings])

    @property
    def objective_unit(self) -> str:
        """The objective's unit: rad/s, 1; rad/time in a dimensionless scene."""
        return Units.of_scene(self.scene).named(OBJECTIVES[self.objective][1])

    def __repr__(self) -> str:
        keys = ", ".join(f"{k}={v:.6g}" for k, v in self.optimum.items())
        return (f"Design({self.objective}={self.value:.6g} {self.objective_unit} at "
                f"{keys}, success={self.success}, warnings={len(self.warnings)})")

    def as_json(self) -> dict:
        """docs/contract.md's `optimize --json` of a design (SI) but for the command's own keys: the
        launch odds the design costs (in air), `written`."""
        return {"objective": self.value, "objective_name": self.objective,
                "at_bound": self.at_bound, "warnings": self.warnings,
                "success": self.success, "message": self.message,
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
