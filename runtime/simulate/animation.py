"""A launch to watch: the top as a disc with its axis and a mark on its rim over the base drawn to
scale, its trace on the horizontal plane, and the spin and the height against time beside it.

    data = frames(trajectory, details, setup, units)      # the subsampled run, JSON-able
    html = fragment(data)                                 # a <div> and its inline script
    write("launch.html", data, title)                     # a whole page (or .gif where Pillow is)

Everything is inline (SVG drawn by a short script, no fetch, no font, no link): the page plays
offline. The run is subsampled to at most MAX_FRAMES frames. Time is scaled so that the precession
is visible (`speed` run seconds per screen second, from the run's own precession period, a 1-2-5
number; the page says so), and the mark on the rim turns `mark_slowdown` times slower than the
top (its true spin, up to hundreds of turns a second, would only flicker). The axis n = R_bs e_z
(thesis 3.2.2 / 2.1.9, runtime/simulate/rotations.py) is drawn as it is, not exaggerated.
"""
from __future__ import annotations

import html
import json
import math
from pathlib import Path

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.simulate.animation_script import SCRIPT
from levitron.runtime.simulate.rotations import ANGLES, rotation_bs
from levitron.runtime.ui.human import Units, sig

MAX_FRAMES = 3000          # the page stays small (about 100 bytes a frame)
SCREEN_FPS = 40            # frames per screen second the run is sampled for
SCREEN_RUN = 40.0          # screen seconds of a run without precession
PRECESSION_ON_SCREEN = 1.0  # screen seconds a turn of the precession takes at least
MARK_TURNS = 0.5           # turns a screen second of the rim mark at the launch
SUFFIXES = (".html", ".htm", ".gif", ".mp4")


def nice_floor(v: float) -> float:
    """The largest 1-2-5 number (..., 0.5, 1, 2, 5, 10, ...) not above v."""
    e = math.floor(math.log10(v))
    for m in (5, 2, 1):
        if m * 10 ** e <= v * (1 + 1e-12):
            return float(m * 10 ** e)
    return float(10 ** e)


def precession_period(t, x, y) -> float | None:
    """The run's mean period of the centre's turning about the vertical axis (from the unwrapped
    azimuth of (x, y)); None when it does not turn."""
    turns = abs(np.unwrap(np.arctan2(y, x))[-1] - np.arctan2(y[0], x[0])) / (2 * math.pi) if len(t) > 1 else 0
    return float((t[-1] - t[0]) / turns) if turns >= 0.5 else None


def axis_of(traj: dict, coords: str, idx) -> np.ndarray:
    """The symmetry axis n = R_bs e_z (body -> space, rotations.py) at the samples idx: (len(idx), 3)."""
    angles = np.column_stack([np.asarray(traj[a], float)[idx] for a in ANGLES[coords]])
    return np.array([rotation_bs(coords, row)[:, 2] for row in angles])


def _short(a, digits: int = 5) -> list:
    return [float(f"{v:.{digits}g}") for v in np.asarray(a, float)]


def frames(traj: dict, details: dict, setup: dict, u: Units) -> dict:
    """The run as the page draws it: frame times, the centre, the axis n and the rim mark's
    direction (turned about n by the slowed spin: module docstring), the spin and the limits, the
    base and the top's disc (runtime/simulate/setup_shape.py)."""
    coords = details.get("coordinates")
    if coords is None or "t" not in traj:
        raise UserError("only a run of the full model can be animated (the reduced model has no tilt): "
                        "drop «part=reduced»")
    t = np.asarray(traj["t"], float)
    x, y, z = (np.asarray(traj[k], float) for k in ("x", "y", "z"))
    C = setup["C"]
    w = np.asarray(traj["L_n"], float) / C
    T_prec = precession_period(t, x, y)
    span = float(t[-1] - t[0]) or 1.0
    # the precession at one turn per PRECESSION_ON_SCREEN screen seconds at least; without one the
    # whole run in SCREEN_RUN screen seconds (the page's speed menu changes either)
    speed = nice_floor(T_prec / PRECESSION_ON_SCREEN if T_prec is not None else span / SCREEN_RUN)
    n_want = min(MAX_FRAMES, max(2, int(span / speed * SCREEN_FPS) + 1))
    idx = np.unique(np.searchsorted(t, np.linspace(t[0], t[-1], n_want)).clip(0, len(t) - 1))
    n = axis_of(traj, coords, idx)
    # the mark: angle about n of the slowed spin, from e1 = e_x projected on the disc's plane
    turned = np.concatenate([[0.0], np.cumsum(0.5 * (w[1:] + w[:-1]) * np.diff(t))])
    w0 = abs(float(w[0])) or 1.0
    slowdown = max(1.0, w0 * speed / (2 * math.pi * MARK_TURNS))
    phi = turned[idx] / slowdown
    fl = details.get("flight") or {}
    iv = fl.get("spin_interval")
    lo = iv[0] if iv else None
    below = np.nonzero(w < lo)[0] if lo is not None else []
    k_len, len_unit = (Units._length_unit(max(setup["scale"], float(np.max(np.abs(z)))))
                       if u.si else (1.0, ""))
    fell = bool(fl.get("fell")) if fl else (details.get("levitating") is False)
    return {
        "t": _short(t[idx]), "pack": pack(x[idx], y[idx], z[idx] - (details.get("z_s") or 0.0), n, phi),
        "w": _short(w[idx], 4), "speed": speed, "slowdown": slowdown, "precession": T_prec,
        "z_s": details.get("z_s"), "lower": lo, "upper": iv[1] if iv else None,
        "t_lower": float(t[below[0]]) if len(below) else None, "t_cross": fl.get("t_cross"),
        "t_fall": float(t[-1]) if fell else None,
        "base": setup["base"], "top_r": setup["top_radius"], "top_h": setup["top_height"],
        "k_len": k_len, "len_unit": len_unit, "si": u.si,
        "time_unit": "s" if u.si else "time units", "rate_unit": "rad/s" if u.si else "rad/time",
        "notes": _notes(speed, slowdown, w0, T_prec, u),
    }


PACK_STEPS = 30000         # the frames' lengths and axis as whole numbers of a quantum: max / PACK_STEPS


def _ints(a: np.ndarray, q: float) -> list[int]:
    return [int(v) for v in np.round(a / q)]


def pack(x, y, dz, n, phi) -> dict:
    """The frames as short JSON: x, y (quantum q_xy), z - z_s (q_z) and the axis' nx, ny (q_n) as
    whole numbers, nz only where the axis points below the horizon somewhere (else
    sqrt(1 - nx^2 - ny^2)), and the rim mark's angle phi about n from e1 = e_x projected on the
    disc's plane (rad, unwrapped, 2 decimals). unpack reverses it; the page's script decodes the same."""
    def quantum(*arrays):
        big = max(float(np.max(np.abs(a))) for a in arrays)
        return big / PACK_STEPS if big > 0 else 1.0
    q_xy, q_z, q_n = quantum(x, y), quantum(dz), 1e-5
    out = {"q_xy": q_xy, "q_z": q_z, "q_n": q_n, "x": _ints(x, q_xy), "y": _ints(y, q_xy),
           "dz": _ints(dz, q_z), "nx": _ints(n[:, 0], q_n), "ny": _ints(n[:, 1], q_n),
           "nz": _ints(n[:, 2], q_n) if np.any(n[:, 2] < 0) else None,
           "phi": [round(float(v), 2) for v in phi]}
    return out


def unpack(data: dict) -> dict:
    """x, y, z (N,), the axis n (N, 3) and the rim mark's direction (N, 3) of the frames."""
    k = data["pack"]
    x, y = np.array(k["x"]) * k["q_xy"], np.array(k["y"]) * k["q_xy"]
    z = (data["z_s"] or 0.0) + np.array(k["dz"]) * k["q_z"]
    nx, ny = np.array(k["nx"]) * k["q_n"], np.array(k["ny"]) * k["q_n"]
    nz = np.array(k["nz"]) * k["q_n"] if k["nz"] is not None else np.sqrt(np.clip(1 - nx ** 2 - ny ** 2, 0, None))
    n = np.column_stack([nx, ny, nz])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    e1 = np.array([1.0, 0.0, 0.0]) - n[:, :1] * n
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(n, e1)
    phi = np.array(k["phi"])
    return {"x": x, "y": y, "z": z, "n": n, "mark": np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2}


def _notes(speed, slowdown, w0, T_prec, u: Units) -> list[str]:
    pace = ("real time" if speed == 1 else
            f"{sig(speed, 3)} times faster than real time" if speed > 1 else
            f"{sig(1 / speed, 3)} times slower than real time")
    per = u.time(speed)
    prec = f" (the top's centre turns once in {u.time(T_prec)})" if T_prec else ""
    head = (f"Time runs {'at ' if speed == 1 else ''}{pace}: one second on the screen is {per} of the run"
            if u.si else f"One second on the screen is {per} of the run")    # a scene's time unit is no clock's
    return [f"{head}{prec}.",
            f"The mark on the rim turns {sig(slowdown, 3)} times slower than the top, whose spin "
            f"at the launch is {u.rate(w0)}: drawn at its true rate it would only flicker.",
            "Base, top and heights are drawn to scale; the trace on the horizontal plane is magnified "
            "(its scale bar says how much)."]


def fragment(data: dict, caption: str = "") -> str:
    """The animation as one <div> (SVG drawn by its inline script, which finds its own div): for
    the report, a page of its own, and a notebook (Simulation._repr_html_)."""
    notes = "".join(f"<li>{html.escape(s)}</li>" for s in data["notes"])
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    cap = f'<p class="note">{html.escape(caption)}</p>' if caption else ""
    return (f'<div class="levitron-animation" style="max-width:60em">{cap}'
            '<svg viewBox="0 0 900 440" width="100%" style="background:#fff;border:1px solid #ddd;'
            'font:12px sans-serif" role="img" aria-label="animation of the launch"></svg>'
            '<div><button type="button">pause</button> speed <select>'
            + "".join(f'<option value="{f}"{" selected" if f == 1 else ""}>x{f}</option>'
                      for f in (0.25, 0.5, 1, 2, 4, 10))
            + '</select> <input type="range" min="0" max="1000" value="0" style="width:50%"> '
            f'<span></span></div><ul class="note">{notes}</ul>'
            f'<script>({SCRIPT})(document.currentScript.parentNode,{payload});</script></div>')


def page(data: dict, title: str) -> str:
    """A whole HTML page holding only the animation."""
    return ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(title)}</title><style>body{{font-family:system-ui,sans-serif;"
            "max-width:62em;margin:1em auto;color:#222}.note{color:#555;font-size:.9em}</style></head>"
            f"<body><h1 style=\"font-size:1.3em\">{html.escape(title)}</h1>{fragment(data)}</body></html>\n")


def check_path(path) -> Path:
    """--animate FILE: .html (always), .gif (Pillow, a matplotlib dependency) or .mp4 (ffmpeg)."""
    p = Path(path)
    if p.suffix.lower() not in SUFFIXES:
        raise UserError(f"«animate» {path}: give a file ending in .html (a page that plays offline), "
                        ".gif or .mp4")
    if p.is_dir():
        raise UserError(f"«animate» {path} is a folder: give a file name in it, e.g. {p / 'launch.html'}")
    if any(q.exists() and not q.is_dir() for q in p.parents):
        raise UserError(f"«animate» {path}: a part of its folder is a file, not a folder: save elsewhere")
    if p.suffix.lower() == ".mp4":
        from matplotlib import animation
        if not animation.writers.is_available("ffmpeg"):
            raise UserError(f"«animate» {path}: an .mp4 needs ffmpeg, which is not installed here; "
                            "write .html or .gif instead (or install ffmpeg)")
    return p


def write(path, data: dict, title: str) -> Path:
    """The animation to path (.html: page; .gif/.mp4: runtime/simulate/animation_video.py),
    written to a temporary beside it and renamed (runtime/ui/atomic.py)."""
    from levitron.runtime.ui.atomic import output
    p = check_path(path)
    with output(p, "«animate»", mkdir=True) as tmp:     # the folder made, as --plot and report --out do
        if p.suffix.lower() in (".html", ".htm"):
            tmp.write_text(page(data, title), encoding="utf-8")
        else:
            from levitron.runtime.simulate.animation_video import render
            render(tmp, data, unpack(data), title)
    return p


