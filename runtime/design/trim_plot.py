"""The trim plot: the spin window and the launch odds against the top's mass (runtime/design/trim.py).

Top: the linear spin interval (sigma_lo, sigma_hi) of each mass of the stable band (thesis 3.3),
with the launch spin's spread as a band. Bottom: the launch odds of the design search (common
random numbers, one seed) against mass, and the fresh seed's odds with their 95 % Wilson interval
at the advice, at the scene's mass and at the widest window. Both: the band's edges, the scene's
mass, the advice and the widest window marked. It shows why the widest window misleads.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plotting import canvas, in_style, save_figure


def _odds_bar(ax, x: float, block: dict, color: str, label: str) -> None:
    p = 100 * block["probability"]
    lo, hi = (100 * v for v in block["probability_ci95"])
    ax.errorbar([x], [p], yerr=[[p - lo], [hi - p]], fmt="o", color=color, capsize=3, label=label)


@in_style
def draw(r: dict, path, u: Units, scene: str, option: str = "«out»") -> Path:
    """Draw the trim answer r (Trim.as_json) to path (.png, .pdf, .svg)."""
    scale, unit = (1e3, "g") if u.si else (1.0, u.unit("kg"))
    mlabel = f"top mass ({unit})" if unit else "top mass"
    fig, (top, bottom) = canvas(nrows=2, sharex=True, figsize=(7.5, 6.5))
    rows = [row for row in r["spin_limits"] if row["spin_interval"]]
    m = np.array([row["mass"] for row in rows]) * scale
    top.plot(m, [row["spin_interval"][0] for row in rows], color="C0", label="sigma_lo (lower spin limit)")
    top.plot(m, [row["spin_interval"][1] for row in rows], color="C1", label="sigma_hi (upper spin limit)")
    spin = mc.parse_input("spin", r["inputs"]["spin"]) if "spin" in r["inputs"] else None
    if spin is not None and spin.kind == "normal":
        top.axhspan(spin.a - 2 * spin.b, spin.a + 2 * spin.b, color="C2", alpha=0.12, lw=0,
                    label="launch spin, mean +- 2 sd")
    elif spin is not None and spin.kind == "uniform":
        top.axhspan(spin.a, spin.b, color="C2", alpha=0.12, lw=0, label="launch spin (uniform)")
    top.set_yscale("log")
    top.set_ylabel(u.label("spin", "rad/s"))
    pts = sorted((p["top.mass"], p["probability"]) for p in r["design"]["search"]["points"])
    bottom.plot([a * scale for a, _ in pts], [100 * b for _, b in pts], ".-", color="0.45",
                label=f"search: {r['design']['search']['n']} launches a mass (seed {r['design']['search']['seed']})")
    _odds_bar(bottom, r["advice"] * scale, r["launch_odds"], "C3", "advice (fresh seed, 95 % interval)")
    _odds_bar(bottom, r["mass"] * scale, r["start_launch_odds"], "k", "as written")
    _odds_bar(bottom, r["widest_window"]["mass"] * scale, r["widest_window"]["launch_odds"], "C1",
              "widest spin window")
    bottom.set_ylim(-3, 103)
    bottom.set_ylabel(f"launches that float {sig(r['success_time'], 3)} {u.unit('s')} (%)".replace("  ", " "))
    bottom.set_xlabel(mlabel)
    lo, hi = (v * scale for v in r["band_mass"])
    for ax in (top, bottom):
        ax.axvspan(lo, hi, color="C2", alpha=0.06, lw=0, label="the masses that hover" if ax is top else None)
        ax.axvline(lo, color="C2", lw=0.8, ls=":")
        ax.axvline(hi, color="C2", lw=0.8, ls=":")
        ax.axvline(r["mass"] * scale, color="k", lw=0.8, ls="--")
        ax.axvline(r["advice"] * scale, color="C3", lw=1.2)
        ax.axvline(r["widest_window"]["mass"] * scale, color="C1", lw=0.8, ls="-.")
    top.legend(loc="best", fontsize="small")
    bottom.legend(loc="lower center", fontsize="small")
    span = max(hi, r["mass"] * scale, r["advice"] * scale) - min(lo, r["mass"] * scale)
    bottom.set_xlim(min(lo, r["mass"] * scale) - 0.05 * span, max(hi, r["mass"] * scale) + 0.05 * span)
    top.set_title(f"{scene}: the trim by the launch odds\nred: the advice; dashed: as written; dash-dot: "
                  "the widest spin window; dotted: the band's edges", fontsize="small")
    fig.tight_layout()
    return save_figure(fig, path, option)
