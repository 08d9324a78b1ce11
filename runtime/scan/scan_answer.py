"""The answer to "over this grid of launches, where does the top stay up?": `Scan`, one type for
every face (`scan --json` is its `as_json()`, `Study.scan` returns it, the report and the figures
read it; docs/contract.md `scan`, thesis fig. 3.8 after Gans et al.). Drawing the map and saving its
points are actions on it: `plot(path, title)`, `save(path)`. runtime/scan/stability_map.py computes it.
Its words are its own: `scan_lines` (of its JSON) is the plain view `levitron scan` prints, its
`lines(units)`, `message`, repr and a notebook's table (`_repr_html_`, with the map).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.integrate.verdict import NO_HOVER, PAST_WINDOW, no_verdict
from levitron.runtime.integrate.verdict import stopped_early as _early
from levitron.runtime.scan.grid import UNITS
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units, duration, sig

_SI = Units(si=True)


def _axis_value(axis: str, v: float, u: Units) -> str:
    if axis == "tilt":
        return u.angle(v)
    if axis == "mass":
        return u.mass(v)
    return f"{sig(v, 3)} z_s"


def runs(flags) -> list[tuple[int, int]]:
    """The maximal runs of consecutive True entries, as (first, last) index pairs."""
    out, start = [], None
    for i, f in enumerate(list(flags) + [False]):
        if f and start is None:
            start = i
        elif not f and start is not None:
            out.append((start, i - 1))
            start = None
    return out


def _stays_up(spins, up, u: Units) -> str:
    """"stays up for spin 671.4-2557 rad/s (...)": every run of levitating spins as it is, several
    where the map has gaps ("200-400 rad/s (...) and 900 rad/s (...)")."""
    parts = [u.rate(spins[a]) if a == b else u.rate_span(spins[a], spins[b]) for a, b in runs(up)]
    return "stays up for spin " + " and ".join(parts)


def stopped_early(status) -> list[str]:
    """The statuses of the runs that stopped early: no verdict (runtime/integrate/verdict.py)."""
    return [s for s in status if _early(s)]


PAST = "past the stable window at t_end"    # a PAST_WINDOW point, in the plain view


def _undecided(stopped: list[str], past: int, ran: int) -> str:
    """"2 of 9 runs stopped early (step_budget); 3 of 9 runs past the stable window at t_end": the
    points of a row without a verdict, by why (runtime/integrate/verdict.py)."""
    why = ", ".join(sorted(set(stopped)))
    return "; ".join(([f"{len(stopped)} of {ran} runs stopped early ({why})"] if stopped else [])
                     + ([f"{past} of {ran} runs {PAST}"] if past else []))


def _row(axis: str, v, spins, up, status, u: Units) -> str:
    """One row of the summary: where it stays up, "cannot hover" where no run was made (no
    equilibrium at that mass or height), "falls at every spin" where every run fell, and the runs
    without a verdict apart (stopped early: step budget, ...; or up at t_end with the spin past its
    stable window): no verdict, never "falls" nor "stays up"."""
    skipped = sum(s == NO_HOVER for s in status)
    if skipped == len(spins):
        return f"  {axis} {_axis_value(axis, v, u)}: cannot hover (no equilibrium: not simulated)"
    stopped = stopped_early(status)
    past = sum(s == PAST_WINDOW for s in status)
    ran = len(spins) - skipped
    head = f"  {axis} {_axis_value(axis, v, u)}: "
    if len(stopped) + past == ran:
        return head + f"no verdict at any spin: {_undecided(stopped, past, ran)}"
    where = (_stays_up(spins, up, u) if any(up) else
             "falls at every spin" + (" that gave a verdict" if stopped or past else ""))
    tail = f"; no verdict: {_undecided(stopped, past, ran)}" if stopped or past else ""
    return head + f"{where} ({sum(up)} of {ran - len(stopped) - past}){tail}"


def _tilted_line(eq: dict | None, u: Units) -> str:
    """Over a tilted base: where the runs start (runtime/scan/stability_map.py tilted_sites)."""
    if not eq:
        return ""
    where = (f"the top's equilibrium there, {u.length(eq['offset'])} off the axis" if eq.get("position")
             else "each top's equilibrium there")
    return f"base tilted by {u.angle(eq['tilt'])}: every run starts at {where}"


def scan_lines(r: dict, u: Units) -> list[str]:
    """Answer first: where it levitates (the runs of spins per row, "cannot hover" apart from
    "falls"), then the linear interval beside."""
    axis = r["axes"][1]
    spins = r["grid"]["spin"]
    status = r.get("status") or [["" for _ in r["grid"][axis]] for _ in spins]
    rows = [_row(axis, v, spins, [bool(r["levitating"][i][j]) for i in range(len(spins))],
                 [status[i][j] for i in range(len(spins))], u)
            for j, v in enumerate(r["grid"][axis])]
    iv = r.get("spin_interval")
    n_stopped = len(stopped_early([s for row in status for s in row]))
    past = r.get("past_window") or {}
    return [
        f"levitating at {sig(100 * r['fraction_levitating'], 3)}% of {r['points']} points "
        f"(spin x {axis}, {u.time(r['t_end'])} each)"
        + (f"; {n_stopped} runs stopped early without a verdict (JSON status)" if n_stopped else "")
        + (f"; {past['points']} runs {PAST}, without a verdict (JSON status {PAST_WINDOW!r})"
           if past.get("points") else ""),
        *rows,
        f"no verdict {PAST}: {past['reason']}" if past.get("reason") else "",
        f"linear spin interval: {u.rate_span(*iv)}" if iv else "linear spin interval: none",
        _tilted_line(r.get("equilibrium"), u),
        f"{duration(r['wall_s'])} of wall time, {r['runner']['kind']} runner",
        u.note,
        f"map: {r['out']}" if r.get("out") else "",
        f"points: {r['saved']}" if r.get("saved") else ""]


@dataclass(frozen=True, eq=False, repr=False)
class Scan:
    """A stability map (docs/contract.md `scan`): one nonlinear run per point of spins (rad/s) x
    others (the second axis `axis`: tilt in rad, mass in kg, height as a fraction of z_s);
    levitating (bool) and t_survived (s) of shape (spins, others); status per point (the run's end,
    runtime/integrate/verdict.py; "no_hover_height" where nothing was run; "past_window" where the
    top was up at t_end with its spin decayed below the window: no verdict, not levitating); linear: per value of
    the other axis the linear picture (runtime/scan/physics.py: spin_interval in rad/s, z_s in m);
    t_end (s) and its basis; wall_s, cpu_s (s), rhs_evals; runner (how the grid was shared out);
    extra: the scene's linear interval (a mass map) and the keys the JSON carries as they are."""

    axis: str
    spins: np.ndarray
    others: np.ndarray
    levitating: np.ndarray
    t_survived: np.ndarray
    status: list
    linear: list                  # per value of the other axis: linear_interval dicts
    t_end: float
    t_end_basis: dict
    wall_s: float
    runner: dict
    rhs_evals: int
    cpu_s: float
    extra: dict = field(default_factory=dict)
    units: Units = field(default=_SI)     # the scene's: how message, repr and the picture show numbers
    scene: str = ""

    # ---- counts
    @property
    def points(self) -> int:
        """The grid's points: spins x values of the other axis."""
        return int(self.levitating.size)

    @property
    def counts(self) -> dict[str, int]:
        """The points by outcome: levitating, fell (a verdict, not up), no_verdict (the run stopped
        early: step budget, ...; or it was up at t_end with its spin past the stable window,
        PAST_WINDOW) and cannot_hover (no equilibrium: not run); they sum to points."""
        flat = [st for row in self.status for st in row]
        undecided = sum(no_verdict(st) for st in flat)
        cannot = sum(st == NO_HOVER for st in flat)
        up = int(self.levitating.sum())
        return {"levitating": up, "fell": self.points - up - undecided - cannot,
                "no_verdict": undecided, "cannot_hover": cannot}

    @property
    def success(self) -> bool:
        """scipy-style: every point that could be run ended normally (reached t_end or left the
        box); points without a hover height were not run and do not count."""
        return not any(_early(st) for row in self.status for st in row)

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (scan_lines of as_json: the one wording of every face), in `units`
        (default the scene's), worded for `face` (None: the markers kept)."""
        u = units or self.units
        return worded(scan_lines(self.as_json(), u), u, face)

    @property
    def message(self) -> str:
        return "; ".join(line.strip() for line in self.lines())

    def __repr__(self) -> str:
        return text_repr("Scan", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table("Stability map", self.lines(), self.plot())

    def agreement(self) -> float | None:
        """Fraction of grid points where 'levitating' equals 'spin inside the linear interval'."""
        pred = np.zeros_like(self.levitating)
        have = False
        for j, lin in enumerate(self.linear):
            iv = lin.get("spin_interval")
            if iv is not None:
                have = True
                pred[:, j] = (self.spins >= iv[0]) & (self.spins <= iv[1])
        if not have:
            return None
        return float(np.mean(pred == self.levitating))

    def as_json(self) -> dict:
        """docs/contract.md's `scan --json` (SI) but for the command's own `out` and `saved`."""
        scene_lin = self.linear[0] if self.axis != "mass" else self.extra.get("scene_linear")
        return {
            "scene": self.scene,
            "axes": ["spin", self.axis],
            "grid": {"spin": self.spins.tolist(), self.axis: self.others.tolist()},
            "units": {"spin": self.units.named(UNITS["spin"]), self.axis: self.units.named(UNITS[self.axis])},
            "spin_hz": (self.spins / (2 * math.pi)).tolist(),
            "levitating": self.levitating.tolist(),
            "t_survived": self.t_survived.tolist(),
            "status": self.status,
            "fraction_levitating": float(self.levitating.mean()),
            "spin_interval": None if scene_lin is None else scene_lin["spin_interval"],
            "linear": {
                "spin_interval": [lin["spin_interval"] for lin in self.linear],
                "z_s": [lin["z_s"] for lin in self.linear],
                "note": ("thesis 3.3 (exact discriminant route)" if "equilibrium" not in self.extra.get("public", {})
                         else "the eigenvalue route at the equilibrium over the tilted base "
                              "(runtime/physics/apparatus/tilted_stability.py)")
                        + f", one entry per value of the {self.axis} axis; null where no spin stabilises",
                "agreement": self.agreement(),
            },
            "t_end": self.t_end,
            "t_end_basis": self.t_end_basis,
            "wall_s": self.wall_s,
            "cpu_s": self.cpu_s,
            "rhs_evals": self.rhs_evals,
            "points": self.points,
            "runner": self.runner,
            **self.extra.get("public", {}),
        }

    # ---- actions
    def table(self) -> dict[str, np.ndarray]:
        """The map as columns, one row per point (spin-major, as the JSON's nested lists): spin
        (rad/s), the other axis, levitating, t_survived (s), status."""
        S, O = np.meshgrid(self.spins, self.others, indexing="ij")
        return {"spin": S.ravel(), self.axis: O.ravel(), "levitating": self.levitating.ravel(),
                "t_survived": self.t_survived.ravel(),
                "status": np.array([st for row in self.status for st in row], dtype=str)}

    def save(self, path, flag: str = "Scan.save") -> str:
        """Write the map's points (`table()`) to a .csv, .npz or .parquet file
        (runtime/simulate/trajectory_file.py; a temporary renamed into place), with the columns'
        units (`column_units()`)."""
        from levitron.runtime.simulate import trajectory_file
        return str(trajectory_file.write_columns(path, self.table(), flag, self.column_units()))

    def plot(self, path=None, title: str | None = None, ax=None):
        """Draw the map (runtime/scan/plot.py, thesis fig. 3.8) into `ax` (an Axes) or a figure of
        its own, written to `path` (.png, .pdf, .svg) only when given one; title: default
        "<scene>: levitating vs spin and <axis>". Returns the matplotlib Figure (the Axes when
        given `ax`)."""
        from levitron.runtime.scan.plot import draw
        if title is None:
            title = f"{self.scene}: levitating vs spin and {self.axis}"
        return draw(self, path, title, self.units, ax=ax)


    # ---- as tables (runtime/ui/frames.py)
    def column_units(self) -> dict[str, str]:
        """{column of `table()`: unit}: spin rad/s, the other axis (runtime/scan/grid.py UNITS: tilt
        rad, mass kg, height a fraction of z_s), levitating "1", t_survived s, status "text" (SI;
        the scene's units in a dimensionless scene), as the saved files name them."""
        from levitron.runtime.ui import frames
        return frames.shown_units({"spin": UNITS["spin"], self.axis: UNITS[self.axis], "levitating": "1",
                                   "t_survived": "s", "status": "text"}, self.units)

    def to_pandas(self):
        """The map in long format, one row a point (`table()`: spin, the other axis, levitating,
        t_survived, status), the units in `df.attrs["units"]` (needs pandas)."""
        from levitron.runtime.ui import frames
        return frames.frame(self.table(), self.column_units(), "Scan.to_pandas()", scene=self.scene,
                            axis=self.axis)

    def to_xarray(self):
        """The map as an xarray Dataset over the dimensions "spin" and the other axis ("tilt",
        "mass" or "height"), their coordinates the grid's values; variables levitating,
        t_survived and status of shape (spins, others); every variable and coordinate has
        `attrs["units"]` (needs xarray)."""
        from levitron.runtime.ui import frames
        u, dims = self.column_units(), ("spin", self.axis)
        status = np.array(self.status, dtype=str).reshape(self.levitating.shape)
        return frames.dataset({"spin": (self.spins, u["spin"]), self.axis: (self.others, u[self.axis])},
                              {"levitating": (dims, self.levitating, u["levitating"]),
                               "t_survived": (dims, self.t_survived, u["t_survived"]),
                               "status": (dims, status, u["status"])},
                              "Scan.to_xarray()", scene=self.scene, t_end=self.t_end)


ScanResult = Scan      # its former name, kept for scripts that import it
