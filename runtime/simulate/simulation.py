"""The answer to "does this launch stay up?": `Simulation`, one type for every face (`simulate
--json` is its `as_json()`, `Study.simulate` returns it, the report reads it; docs/contract.md
`simulate`, thesis 3.1-3.3). Drawing, saving and animating the run are actions on it: `plot(path)`,
`save(path)`, `animate(path)`; a notebook shows the animation (`_repr_html_`).
"""
from __future__ import annotations

import functools
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.integrate.verdict import DOWN, UP
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plain_text import NOTHING_SAID, said
from levitron.runtime.words import render

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
    spin omega_3 = L_n / C (rad/s). Its words: `lines(units)` (runtime/simulate/simulation_view.py),
    which the command line prints and message, repr and the notebook reuse."""

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
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, compare=False)    # its sentences as written

    @classmethod
    def of(cls, out: dict, trajectory: dict, model, p) -> Simulation:
        """The answer from simulate's keys (runtime/simulate/run.py) and its samples."""
        return cls(out["levitating"], float(out["t_survived"]), float(out["max_excursion"]),
                   float(out["energy_drift"]), int(out["rhs_evals"]), float(out["wall_s"]),
                   dict(out["final_state"]), out, trajectory, Units.of_scene(model.scene), model.scene.name,
                   model, p, said(**{k: out[k] for k in ("note", "message", "untested") if out.get(k)}))

    @classmethod
    def from_json(cls, r: dict, units: Units = _SI) -> Simulation:
        """The answer again from its as_json() (the command line's plain view reads it so; its
        trajectory is not in the JSON)."""
        return cls(r["levitating"], r["t_survived"], r["max_excursion"], r["energy_drift"], r["rhs_evals"],
                   r.get("wall_s", 0.0), dict(r.get("final_state") or {}), r, {}, units, r.get("scene", ""))

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
        """Write the trajectory to a .csv, .npz or .parquet file (runtime/simulate/trajectory_file.py),
        its columns' units with it (`column_units()`)."""
        from levitron.runtime.simulate import trajectory_file
        names = list(self.trajectory)
        return str(trajectory_file.write(path, names, np.column_stack([self.trajectory[n] for n in names]),
                                        flag, self.column_units()))

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

    # ---- as tables (runtime/ui/frames.py)
    def column_units(self) -> dict[str, str]:
        """{column of `trajectory`: unit}: t in s, the states (m, rad, kg m/s, kg m^2/s), energy in J,
        L_z and L_n in kg m^2/s, tilt in rad, spin in rad/s (SI; the scene's units in a
        dimensionless scene), as the saved files name them."""
        from levitron.runtime.ui import frames
        return frames.shown_units({n: frames.trajectory_unit(n) for n in self.trajectory}, self.units)

    def to_pandas(self):
        """The trajectory as a pandas DataFrame, one row a sample: the columns of `trajectory` (t,
        the states, energy, L_z, L_n, tilt, spin), their units in `df.attrs["units"]` (needs pandas)."""
        from levitron.runtime.ui import frames
        return frames.frame(self.trajectory, self.column_units(), "Simulation.to_pandas()", scene=self.scene)

    def to_xarray(self):
        """The trajectory as an xarray Dataset over the dimension "t" (its coordinate, s): one
        variable a column, each with `attrs["units"]` (needs xarray)."""
        from levitron.runtime.ui import frames
        u = self.column_units()
        data = {n: (("t",), v, u[n]) for n, v in self.trajectory.items() if n != "t"}
        return frames.dataset({"t": (self.trajectory.get("t", []), u.get("t", "s"))}, data,
                              "Simulation.to_xarray()", scene=self.scene, status=self.status)

    # ---- as the API shows it
    @property
    def status(self) -> str:
        return str(self.details.get("status", "completed" if self.levitating else "unknown"))

    @property
    def success(self) -> bool:
        """The run ended normally: reached t_end, or stopped when the top left the box."""
        return self.status in NORMAL_ENDS

    # ---- its words, one function for every face (runtime/simulate/simulation_view.py)
    def _said(self) -> dict:
        """The run's keys, its sentences as written where the API worded them for its face."""
        from levitron.runtime.ui.plain_text import kept
        return {**self.details, **{k: kept(self.details.get(k), w, self.units) for k, w in self.said.items()}}

    def lines(self, units: Units | None = None, scene=None) -> list[str]:
        """The plain view in `units` (default the scene's): what `levitron simulate` prints (scene:
        for the plate's symmetry, default the model's)."""
        from levitron.runtime.simulate import simulation_view
        if scene is None and self.model is not None:
            scene = self.model.scene
        return simulation_view.lines(self._said(), units or self.units, scene)

    def summary(self, units: Units | None = None) -> str:
        """The answer in one sentence: does the top stay up, for how long."""
        from levitron.runtime.simulate import simulation_view
        return simulation_view.summary(self._said(), units or self.units)

    @property
    def message(self) -> str:
        return render(self.summary(), "api", self.units)

    def _repr_html_(self) -> str:
        """In a notebook: a table of its plain view, and the run animated (runtime/simulate/animation.py:
        the top over its base to scale, its trace, spin and height against time; inline, offline)."""
        from levitron.runtime.simulate import animation
        head = render(html_table("Simulation", self.lines()), "api", self.units)
        if not self.trajectory or self.model is None or self.details.get("coordinates") is None:
            return head
        return head + animation.fragment(self.animation(), self.message)

    def __repr__(self) -> str:
        return render(text_repr("Simulation", [self.summary(), f"energy_drift={self.energy_drift:.2g}",
                                               f"status={self.status!r}", f"success={self.success}"]),
                      "api", self.units)
