"""The answer to "over this grid of launches, where does the top stay up?": `Scan`, one type for
every face (`scan --json` is its `as_json()`, `Study.scan` returns it, the report and the figures
read it; docs/contract.md `scan`, thesis fig. 3.8 after Gans et al.). Drawing the map and saving its
points are actions on it: `plot(path, title)`, `save(path)`. runtime/scan/stability_map.py computes it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.integrate.verdict import NO_HOVER, stopped_early
from levitron.runtime.scan.grid import UNITS
from levitron.runtime.ui.human import Units

_SI = Units(si=True)


@dataclass(frozen=True, eq=False, repr=False)
class Scan:
    """A stability map (docs/contract.md `scan`): one nonlinear run per point of spins (rad/s) x
    others (the second axis `axis`: tilt in rad, mass in kg, height as a fraction of z_s);
    levitating (bool) and t_survived (s) of shape (spins, others); status per point (the run's end,
    runtime/integrate/verdict.py; "no_hover_height" where nothing was run); linear: per value of
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
        early: step budget, ...) and cannot_hover (no equilibrium: not run); they sum to points."""
        flat = [st for row in self.status for st in row]
        no_verdict = sum(stopped_early(st) for st in flat)
        cannot = sum(st == NO_HOVER for st in flat)
        up = int(self.levitating.sum())
        return {"levitating": up, "fell": self.points - up - no_verdict - cannot,
                "no_verdict": no_verdict, "cannot_hover": cannot}

    @property
    def success(self) -> bool:
        """scipy-style: every point that could be run ended normally (reached t_end or left the
        box); points without a hover height were not run and do not count."""
        return not any(stopped_early(st) for row in self.status for st in row)

    @property
    def message(self) -> str:
        bad = sorted({st for row in self.status for st in row if stopped_early(st)})
        return (f"levitating at {100 * float(self.levitating.mean()):.3g}% of {self.levitating.size} "
                f"points (spin x {self.axis}, t_end {self.t_end:.4g} {self.units.named('s')} each)"
                + (f"; runs ended by {', '.join(bad)}" if bad else ""))

    def __repr__(self) -> str:
        return (f"Scan(spin {self.spins.size} x {self.axis} {self.others.size}, levitating "
                f"{int(self.levitating.sum())} of {self.levitating.size}, "
                f"t_end={self.t_end:.4g} {self.units.named('s')}, success={self.success})")

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
                              "(runtime/physics/tilted_stability.py)")
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
        (runtime/simulate/trajectory_file.py; a temporary renamed into place)."""
        from levitron.runtime.simulate import trajectory_file
        return str(trajectory_file.write_columns(path, self.table(), flag))

    def plot(self, path=None, title: str | None = None, ax=None):
        """Draw the map (runtime/scan/plot.py, thesis fig. 3.8) into `ax` (an Axes) or a figure of
        its own, written to `path` (.png, .pdf, .svg) only when given one; title: default
        "<scene>: levitating vs spin and <axis>". Returns the matplotlib Figure (the Axes when
        given `ax`)."""
        from levitron.runtime.scan.plot import draw
        if title is None:
            title = f"{self.scene}: levitating vs spin and {self.axis}"
        return draw(self, path, title, self.units, ax=ax)


ScanResult = Scan      # its former name, kept for scripts that import it
