"""The picture of a stability map (thesis fig. 3.8; runtime/scan/scan_answer.py's Scan: its plot action)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plotting import canvas, finish, in_style
from levitron.runtime.scan.grid import UNITS
from levitron.runtime.integrate.verdict import NO_HOVER, PAST_WINDOW, stopped_early


NO_HOVER_COLOUR = "0.75"          # light grey: outside viridis, which runs from purple to yellow
NO_VERDICT_COLOUR = "0.35"        # dark grey: a run that stopped early (step budget, ...)
PAST_WINDOW_COLOUR = "#e8702a"    # orange, outside viridis too: up at t_end, its spin past the window


def _edges(v: np.ndarray) -> np.ndarray:
    if v.size == 1:
        d = abs(v[0]) * 0.05 or 0.5
        return np.array([v[0] - d, v[0] + d])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


@in_style
def draw(res, path: str | Path | None = None, title: str = "", units: Units | None = None, ax=None):
    """The map (thesis fig. 3.8): colour = t_survived / t_end (1 = levitating, marked with dots;
    light grey where the top cannot hover and nothing was run, dark grey where the run stopped early
    without a verdict: step budget, non-finite state, step underflow; orange where the top was up at
    t_end with its spin decayed below the window, past_window: no verdict either)
    over spin (x) and the other axis (y); the linear spin interval as vertical lines (for a mass
    scan, one pair per mass row: it moves with the mass). units: the scene's (runtime/ui/human.py;
    default SI). Into `ax` (an Axes; its colour bar takes room beside it) or a figure of its own,
    written to `path` when given one; the Figure (the Axes when given `ax`)."""
    u = units or Units(si=True)
    given = ax
    frac = (res.t_survived / res.t_end).T
    # masses in g in an SI scene (as everywhere else in the tool), the scene's units otherwise
    ky, y_unit = (1e3, "g") if res.axis == "mass" and u.si else (1.0, None)
    others = res.others * ky
    fig, ax = canvas(given, figsize=(8, 5.5))
    mesh = ax.pcolormesh(_edges(res.spins), _edges(others), frac, cmap="viridis", vmin=0, vmax=1,
                         shading="flat")
    fig.colorbar(mesh, ax=ax, label="t_survived / t_end  (1 = levitating)")
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch
    extra = []
    no_hover = np.array([[st == NO_HOVER for st in row] for row in res.status], bool).T
    if no_hover.any():      # not simulated: its own colour, never the "fell at once" of the colour map
        ax.pcolormesh(_edges(res.spins), _edges(others), np.ma.masked_where(~no_hover, no_hover),
                      cmap=ListedColormap([NO_HOVER_COLOUR]), shading="flat")
        extra.append(Patch(color=NO_HOVER_COLOUR, label="cannot hover (no equilibrium: not simulated)"))
    stopped = np.array([[stopped_early(st) for st in row] for row in res.status], bool).T
    if stopped.any():       # no verdict either way: never the colour map's "fell at once"
        ax.pcolormesh(_edges(res.spins), _edges(others), np.ma.masked_where(~stopped, stopped),
                      cmap=ListedColormap([NO_VERDICT_COLOUR]), shading="flat")
        kinds = ", ".join(sorted({st for row in res.status for st in row if stopped_early(st)}))
        extra.append(Patch(color=NO_VERDICT_COLOUR, label=f"no verdict: the run stopped early ({kinds})"))
    past = np.array([[st == PAST_WINDOW for st in row] for row in res.status], bool).T
    if past.any():          # up at t_end with the spin below the window: the fall came after the run
        ax.pcolormesh(_edges(res.spins), _edges(others), np.ma.masked_where(~past, past),
                      cmap=ListedColormap([PAST_WINDOW_COLOUR]), shading="flat")
        extra.append(Patch(color=PAST_WINDOW_COLOUR, label="no verdict: up at t_end, its spin decayed "
                                                           "below the window (the fall comes later)"))
    S, O = np.meshgrid(res.spins, others, indexing="ij")
    # white dots ringed in black: visible on the dark and on the bright end of the colour map
    ax.plot(S[res.levitating], O[res.levitating], "o", ms=5, mfc="w", mec="k", mew=1.0, ls="none",
            label="levitating" if res.levitating.any() else "levitating: no run")
    los = [li["spin_interval"][0] if li["spin_interval"] else np.nan for li in res.linear]
    his = [li["spin_interval"][1] if li["spin_interval"] else np.nan for li in res.linear]
    if res.axis == "mass":   # the interval moves with the mass: vertical lines per row
        ye = _edges(others)
        label = "linear stability interval (thesis 3.3)"
        for j in range(res.others.size):
            if np.isfinite(los[j]):
                ax.vlines([los[j], his[j]], ye[j], ye[j + 1], colors="r", lw=1.5, label=label)
                label = None
    elif np.isfinite(los[0]):
        ax.axvline(los[0], color="r", lw=1.5, label="linear stability interval (thesis 3.3)")
        ax.axvline(his[0], color="r", lw=1.5)
    ax.grid(False)
    ax.set_xlim(_edges(res.spins)[[0, -1]])
    ax.set_xlabel(u.label("spin", UNITS["spin"]))
    ax.set_ylabel(f"{res.axis} ({y_unit})" if y_unit else u.label(res.axis, UNITS[res.axis]))
    runs = f"{res.spins.size} x {res.others.size} runs of t_end = {u.time(res.t_end)} each"
    ax.set_title(f"{title}\n{runs}" if title else f"stability map: {res.axis} vs spin, {runs}")
    handles, _ = ax.get_legend_handles_labels()
    ax.legend(handles=handles + extra, loc="upper right", fontsize=8, framealpha=0.8)
    if given is None:
        fig.tight_layout()
    return finish(fig, path, "«out»", ax=given)
