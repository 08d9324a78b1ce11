"""The picture of the launch odds (runtime/scan/launch_answer.py's LaunchOdds: its plot action, which
`launch --out` and the report draw): the flight times of the Monte Carlo's launches (docs/contract.md
`launch`)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plotting import canvas, finish, in_style


@in_style
def histogram(odds: dict, path: Path | None, u: Units, scene: str, ax=None):
    """The flight times of the odds' launches, axis fitted to them, the censored runs (still up at
    the run's end) as a bar of their own, labelled; into `ax` (an Axes) or a figure of its own,
    written to `path` when given one; the Figure (the Axes when given `ax`)."""
    given = ax
    tu = "s" if u.si else "time units"
    t = np.asarray(odds["flight_time"]["values"], float)
    t_end = odds["t_end"]
    up = t >= t_end * (1 - 1e-12)
    fig, ax = canvas(given, figsize=(7, 3.6))
    width = t_end / 40
    if np.any(~up):
        ax.hist(t[~up], bins=np.arange(0, t_end + width, width), color="C0", label="fell")
    if np.any(up):
        ax.bar([t_end + width], [int(up.sum())], width=width, color="C2",
               label=f"still floating at the run's end ({int(up.sum())})")
        ax.annotate(f"{int(up.sum())} still up", (t_end + width, int(up.sum())), ha="center", va="bottom",
                    fontsize=8)
    ax.axvline(odds["success_time"], color="C3", ls="--", label=f"success time {sig(odds['success_time'], 4)} {tu}")
    ax.set_xlim(0, t_end + 2 * width)
    ax.set_xlabel(f"flight time ({tu})")
    ax.set_ylabel("launches")
    lo, hi = odds["probability_ci95"]
    ax.set_title(f"{scene}: {sig(100 * odds['probability'], 3)} % of {odds['n']} launches float "
                 f"(95 % interval {sig(100 * lo, 3)}-{sig(100 * hi, 3)} %)", fontsize="medium")
    ax.legend(loc="upper left", fontsize="small")
    if given is None:
        fig.tight_layout()
    return finish(fig, path, ax=given)
