"""The picture of a stability map (thesis fig. 3.8; runtime/scan.py's ScanResult)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from runtime.human import sig
from runtime.plotting import pyplot, save_figure, style
from runtime.scan_grid import UNITS


def _edges(v: np.ndarray) -> np.ndarray:
    if v.size == 1:
        d = abs(v[0]) * 0.05 or 0.5
        return np.array([v[0] - d, v[0] + d])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def draw(res, path: str | Path, title: str = "") -> Path:
    """The map (thesis fig. 3.8): colour = t_survived / t_end (1 = levitating, marked with dots)
    over spin (x) and the other axis (y); the linear spin interval as vertical lines (for a mass
    scan, one pair per mass row: it moves with the mass)."""
    plt = pyplot()
    style()
    frac = (res.t_survived / res.t_end).T
    fig, ax = plt.subplots(figsize=(8, 5.5))
    mesh = ax.pcolormesh(_edges(res.spins), _edges(res.others), frac, cmap="viridis", vmin=0, vmax=1,
                         shading="flat")
    fig.colorbar(mesh, ax=ax, label="t_survived / t_end  (1 = levitating)")
    S, O = np.meshgrid(res.spins, res.others, indexing="ij")
    ax.plot(S[res.levitating], O[res.levitating], "w.", ms=4, label="levitating")
    los = [li["spin_interval"][0] if li["spin_interval"] else np.nan for li in res.linear]
    his = [li["spin_interval"][1] if li["spin_interval"] else np.nan for li in res.linear]
    if res.axis == "mass":   # the interval moves with the mass: vertical lines per row
        ye = _edges(res.others)
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
    ax.set_xlabel("spin (rad/s)")
    ax.set_ylabel(f"{res.axis} ({UNITS[res.axis]})")
    runs = f"{res.spins.size} x {res.others.size} runs of t_end = {sig(res.t_end, 3)} s each"
    ax.set_title(f"{title}\n{runs}" if title else f"stability map: {res.axis} vs spin, {runs}")
    ax.legend(loc="upper right", fontsize=8, framealpha=0.8)
    fig.tight_layout()
    return save_figure(fig, path, "--out")
