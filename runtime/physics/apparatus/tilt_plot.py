"""The spin interval against the base's tilt, the level tolerance marked.

The interval at each tilt is runtime/physics/apparatus/tilted_stability.py's (the eigenvalues of the
generated Jacobian at the relative equilibrium off the axis); the tilts run from level to the
tolerance `max_base_tilt` (the same module's `level_tolerance`), past which no spin stabilises
the top. Drawn in degrees of tilt and the scene's rate units (runtime/ui/human.py Units).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from levitron.runtime.physics.apparatus.tilted_equilibrium import TiltedTop
from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plotting import canvas, finish, in_style

POINTS = 24


def interval_against_tilt(model, p, tolerance: dict, points: int = POINTS) -> dict:
    """{tilt: [...] rad, low: [...], high: [...] rad/s} from level to max_base_tilt (its last
    point just inside it), one continuation shared by all points."""
    t_max = tolerance["max_base_tilt"]
    tilts = np.linspace(0.0, t_max, points)
    res0 = tilted_analysis(model, model.with_params({"base_tilt": 0.0}, p))
    top = TiltedTop(model, p, res0.equilibrium["z_level"] + model.pvals(p).get("moment_offset", 0.0))
    low, high = [], []
    for t in tilts:
        iv = tilted_analysis(model, model.with_params({"base_tilt": float(t)}, p), top).spin_interval
        low.append(math.nan if iv is None else iv[0])
        high.append(math.nan if iv is None else iv[1])
    return {"tilt": [float(t) for t in tilts], "low": low, "high": high}


@in_style
def draw(model, p, tolerance: dict, path: str | Path | None = None, ax=None):
    """The figure of the module docstring, into `ax` (an Axes) or a figure of its own, written to
    `path` (.png, .pdf or .svg) when given one; the Figure (the Axes when given `ax`)."""
    data = interval_against_tilt(model, p, tolerance)
    u = Units.of_scene(model.scene)
    given = ax
    fig, ax = canvas(given)
    deg = np.degrees(data["tilt"])
    ax.fill_between(deg, data["low"], data["high"], alpha=0.25, lw=0, label="linearly stable")
    ax.plot(deg, data["low"], color="C0")
    ax.plot(deg, data["high"], color="C0")
    t_max = math.degrees(tolerance["max_base_tilt"])
    ax.axvline(t_max, color="C3", ls="--", label=f"level tolerance {sig(t_max, 3)} deg")
    ax.set_xlabel("base tilt (deg)")
    ax.set_ylabel(u.label("spin", "rad/s"))
    ax.set_title(f"{model.scene.name}: the spin interval against the base's tilt")
    ax.legend(loc="best")
    return finish(fig, path, ax=given)
