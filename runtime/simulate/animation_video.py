"""The launch animation as a video file (.gif through Pillow, a matplotlib dependency; .mp4 through
ffmpeg where installed): the same data as the page (runtime/simulate/animation.py frames), drawn by
matplotlib: the top over its base in the page's view from 20 degrees above the horizon, to scale,
and the spin against time with the lower limit. At most VIDEO_FRAMES frames at VIDEO_FPS, so the
video's pace (said in its title) is its own: a whole flight in air takes VIDEO_FRAMES / VIDEO_FPS s.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from levitron.runtime.ui.human import sig
from levitron.runtime.ui.plotting import canvas, in_style

VIDEO_FRAMES = 240
VIDEO_FPS = 12
ELEVATION = 0.35           # rad, the page's view


def _project(x, y, z):
    return x, z * math.cos(ELEVATION) + y * math.sin(ELEVATION)


def _disc(c, n, r, h):
    """The projected outline of the cylinder (both faces' rims), for a filled polygon: its hull."""
    from scipy.spatial import ConvexHull
    e1 = np.array([1.0, 0.0, 0.0]) - n[0] * n
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    a = np.linspace(0, 2 * math.pi, 36, endpoint=False)
    pts = [c + s * h / 2 * n + r * (np.cos(t) * e1 + np.sin(t) * e2) for s in (-1, 1) for t in a]
    P = np.array([_project(*p) for p in pts])
    return P[ConvexHull(P).vertices]


@in_style
def render(path: Path, data: dict, frames: dict, title: str) -> Path:
    """Write the video to path (its suffix picks the writer); frames: animation.unpack(data). The
    figure is made without pyplot (runtime/ui/plotting.py): nothing to close."""
    from matplotlib import animation
    from matplotlib.patches import Ellipse, Polygon
    t = np.asarray(data["t"])
    idx = np.unique(np.linspace(0, len(t) - 1, min(VIDEO_FRAMES, len(t))).astype(int))
    X, Y, Z, N, M = (frames[k] for k in ("x", "y", "z", "n", "mark"))
    r, h = data["top_r"], max(data["top_h"], 0.2 * data["top_r"])
    ext = max([data["top_r"] * 3] + [max(b.get("r_out", 0), b.get("half_x", 0), b.get("half_y", 0))
                                     for b in data["base"]]) * 1.12
    fig, (ax, bx) = canvas(ncols=2, figsize=(9, 4.2), gridspec_kw={"width_ratios": [1.1, 1]})
    se = math.sin(ELEVATION)
    for b in data["base"]:
        if b["kind"] == "rect":
            corners = [(-b["half_x"], -b["half_y"]), (b["half_x"], -b["half_y"]),
                       (b["half_x"], b["half_y"]), (-b["half_x"], b["half_y"])]
            ax.add_patch(Polygon([_project(cx, cy, 0) for cx, cy in corners], fc="#b9bec8", ec="#666"))
            if b.get("r_in", 0) > 0:
                ax.add_patch(Ellipse((0, 0), 2 * b["r_in"], 2 * b["r_in"] * se, fc="#f4f4f4", ec="#666"))
            continue
        ax.add_patch(Ellipse((0, 0), 2 * b["r_out"], 2 * b["r_out"] * se,
                             fc="none" if b["kind"] == "loop" else "#b9bec8", ec="#666"))
        if b.get("r_in", 0) > 0 and b["kind"] != "loop":
            ax.add_patch(Ellipse((0, 0), 2 * b["r_in"], 2 * b["r_in"] * se, fc="#f4f4f4", ec="#666"))
    zmax = float(max(Z.max(), data["z_s"] or 0)) + 3 * r
    ax.set_xlim(-ext, ext)
    ax.set_ylim(-ext * se - 0.05 * zmax, zmax)
    ax.set_aspect("equal")
    ax.set_axis_off()
    body = ax.add_patch(Polygon(np.zeros((3, 2)), fc="#c0392b", ec="#7b241c"))
    axis_line, = ax.plot([], [], "k-", lw=1.2)
    mark, = ax.plot([], [], "o", mfc="w", mec="k", ms=5)
    bx.plot(t, data["w"], color="#2c6fb7")
    if data["lower"]:
        bx.axhline(data["lower"], color="#c0392b", ls="--", lw=1, label=f"lower limit {sig(data['lower'], 4)} "
                   f"{data['rate_unit']}")
        bx.legend(loc="upper right", fontsize="small")
    cursor = bx.axvline(t[0], color="#c0392b")
    bx.set_xlim(t[0], t[-1])
    bx.set_xlabel(f"t ({data['time_unit']})")
    bx.set_ylabel(f"spin ({data['rate_unit']})")
    pace = (t[-1] - t[0]) / (len(idx) / VIDEO_FPS)
    fig.suptitle(f"{title}\nto scale; {sig(pace, 3)} x real time; the rim mark turns "
                 f"{sig(data['slowdown'], 3)} x slower than the top", fontsize=9)
    fig.tight_layout()

    def frame(i):
        c, n = np.array([X[i], Y[i], Z[i]]), N[i] / np.linalg.norm(N[i])
        body.set_xy(_disc(c, n, r, h))
        L = h / 2 + 1.8 * r
        a0, a1 = _project(*(c - L * n)), _project(*(c + L * n))
        axis_line.set_data([a0[0], a1[0]], [a0[1], a1[1]])
        m = _project(*(c + h / 2 * n + r * M[i]))
        mark.set_data([m[0]], [m[1]])
        cursor.set_xdata([t[i], t[i]])
        return body, axis_line, mark, cursor

    anim = animation.FuncAnimation(fig, frame, frames=idx, blit=False)
    writer = (animation.PillowWriter(fps=VIDEO_FPS) if path.suffix.lower() == ".gif"
              else animation.FFMpegWriter(fps=VIDEO_FPS))
    anim.save(str(path), writer=writer, dpi=80)
    return path
