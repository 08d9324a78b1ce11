"""The answer to "does this launch stay up?": `Simulation`, one type for every face (`simulate
--json` is its `as_json()`, `Study.simulate` returns it, the report reads it; docs/contract.md
`simulate`, thesis 3.1-3.3). Drawing, saving and animating the run are actions on it: `plot(path)`,
`save(path)`, `animate(path)`; a notebook shows the animation (`_repr_html_`).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.integrate.verdict import DOWN, UP
from levitron.runtime.ui.human import Units, quantity

NORMAL_ENDS = (UP, DOWN)    # the runs with a verdict (runtime/integrate/verdict.py): the run itself succeeded
_SI = Units(si=True)


@dataclass(frozen=True, repr=False)
class Simulation:
    """One trajectory from the hover height (docs/contract.md `simulate`): levitating (None for a
    launch on the invariant set, which tests nothing, or a run that stopped early without a verdict,
    runtime/integrate/verdict.py: details["untested"] says why); t_survived (s); max_excursion (m);
    energy_drift (relative; in air the energy balance's residual); rhs_evals; wall_s (s);
    final_state (the model's states, SI); details: every key of `simulate --json` (in air also
    "flight": flight time, fall spin, the adiabatic t_cross); trajectory: the samples as data,
    {column: array}: t (s), the states (SI), energy (J), L_z, L_n (kg m^2/s), tilt (rad) and the
    spin omega_3 = L_n / C (rad/s)."""

    levitating: bool | None
    t_survived: float
    max_excursion: float
    energy_drift: float
    rhs_evals: int
    wall_s: float
    final_state: dict
    details: dict = field(default_factory=dict)
    trajectory: dict = field(default_factory=dict)
    units: Units = field(default=_SI, compare=False)   # how repr, message and plots show numbers
    scene: str = ""
    model: object = field(default=None, compare=False)     # what the drawing of the set-up reads
    p: object = field(default=None, compare=False)

    @classmethod
    def of(cls, out: dict, trajectory: dict, model, p) -> Simulation:
        """The answer from simulate's keys (runtime/simulate/run.py) and its samples."""
        return cls(out["levitating"], float(out["t_survived"]), float(out["max_excursion"]),
                   float(out["energy_drift"]), int(out["rhs_evals"]), float(out["wall_s"]),
                   dict(out["final_state"]), out, trajectory, Units.of_scene(model.scene), model.scene.name,
                   model, p)

    def as_json(self) -> dict:
        """docs/contract.md's `simulate --json` (SI)."""
        return dict(self.details)

    def __getitem__(self, key: str):
        """A key of the JSON answer, as `simulate --json` names it."""
        return self.details[key]

    def __contains__(self, key: str) -> bool:
        return key in self.details

    @functools.cached_property
    def setup(self) -> dict:
        """The set-up as the animation draws it (runtime/simulate/setup_shape.py)."""
        from levitron.runtime.simulate.setup_shape import setup_of
        return setup_of(self.model, self.p)

    # ---- actions
    def save(self, path, flag: str = "Simulation.save") -> str:
        """Write the trajectory to a .csv, .npz or .parquet file (runtime/simulate/trajectory_file.py)."""
        from levitron.runtime.simulate import trajectory_file
        names = list(self.trajectory)
        return str(trajectory_file.write(path, names, np.column_stack([self.trajectory[n] for n in names]),
                                        flag))

    def plot(self, path=None, ax=None, fig=None):
        """Draw height, radial offset and tilt against time (three panels); for a flight in air the
        spin and the height with the linear limits and the adiabatic crossing (two panels;
        runtime/simulate/plot.py). On a figure of its own, on `fig` (a Figure or SubFigure) or into
        `ax` (a list of as many Axes); written to `path` (.png, .pdf, .svg) only when given one.
        Returns the matplotlib Figure (the list of Axes when given `ax`)."""
        from levitron.runtime.simulate.plot import draw, draw_flight
        d, tr = self.details, self.trajectory
        info = dict(d, levitating=d["status"] == UP)      # the run's own end, as its title says it
        dz = tr["z"] - d["z_s"]
        if "flight" in d:
            return draw_flight(tr["t"], dz, tr["spin"], path, info, self.units, self.scene, ax=ax, fig=fig)
        r = np.hypot(tr["x"], tr["y"]) if "x" in tr else np.zeros(len(tr["t"]))
        return draw(tr["t"], dz, r, tr["tilt"], path, info, self.units, self.scene, ax=ax, fig=fig)

    def animation(self, setup: dict | None = None) -> dict:
        """The run as the animation page draws it (runtime/simulate/animation.py frames); setup: the
        set-up's drawing (setup_shape.setup_of) where the caller has it already."""
        from levitron.runtime.simulate import animation
        return animation.frames(self.trajectory, self.details, self.setup if setup is None else setup, self.units)

    def animate(self, path, title: str) -> str:
        """Write the run animated to path: .html (plays offline), .gif or .mp4 (runtime/simulate/animation.py)."""
        from levitron.runtime.simulate import animation
        return str(animation.write(path, self.animation(), title))

    # ---- as the API shows it
    @property
    def status(self) -> str:
        return str(self.details.get("status", "completed" if self.levitating else "unknown"))

    @property
    def success(self) -> bool:
        """The run ended normally: reached t_end, or stopped when the top left the box."""
        return self.status in NORMAL_ENDS

    @property
    def message(self) -> str:
        return str(self.details.get("message") or self.status)

    def _repr_html_(self) -> str:
        """In a notebook: the run animated (runtime/simulate/animation.py: the top over its base to
        scale, its trace, spin and height against time; inline, offline), under its repr."""
        import html

        from levitron.runtime.simulate import animation
        head = f"<pre>{html.escape(repr(self))}</pre>"
        if not self.trajectory or self.model is None or self.details.get("coordinates") is None:
            return head
        return head + animation.fragment(self.animation(), self.message)

    def __repr__(self) -> str:
        u = self.units
        return (f"Simulation(levitating={self.levitating}, t_survived={self.t_survived:.6g} of "
                f"{quantity(u, self.details.get('t_end', float('nan')), 's')}, "
                f"energy_drift={self.energy_drift:.2g}, status={self.status!r}, success={self.success})")
