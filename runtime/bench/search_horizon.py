"""`levitron bench SCENE --kind search-horizon`: when a design's search may judge its launches.

A design by the launch odds (runtime/design/launch_design.py) ranks its points on launches judged
at a search time shorter than the success time: the ranking is all the search needs, and the
answer is decided on fresh launches at the success time. A shorter search time is cheaper (a
launch that stays up costs in proportion to its flight) and harmless as long as the launches that
fall between the search time and the success time are about the same share at every point.

The study: the scene's pinned hand (its [launch] table or the defaults at its written mass) at
MASSES masses across the stable band, n launches each (one seed: common random numbers), every
launch flown to the success time T. Per horizon H of HORIZONS (fractions of T): the odds at every
mass, and the spread across the masses of the late falls, odds(H) - odds(T), the most the ranking at
H can differ from the ranking at T. The design's own search time (launch_design.Pinned.search_time) is
named in the report. Writes search_horizon.json, search_horizon.csv and search_horizon.png.
"""
from __future__ import annotations

import csv
import json
import time
from pathlib import Path

import numpy as np

from levitron.runtime.ui.atomic import open_text, write_text
from levitron.runtime.ui.plotting import canvas, in_style, save_figure

HORIZONS = (1 / 16, 1 / 8, 1 / 4, 1 / 2, 1.0)
MASSES = 7                      # interior points of the stable band
FULL = {"n": 600}
QUICK = {"n": 4, "masses": 2, "success_time": 0.5, "t_end": 0.5}


def _odds_at_horizons(model, mass: float, given: dict, n: int, success_time: float, **extra) -> dict:
    """The first n launches of seed 0 at `mass`, flown to success_time: odds at every horizon."""
    from levitron.runtime.design.paired_odds import variant
    from levitron.runtime.scan import launch_odds as mc
    from levitron.runtime.scan.runners import model_for
    at = model_for(*variant(model.ref, ["top.mass"], (mass,)))
    prep = mc.prepare(at, given, n=n, seed=0, success_time=success_time, workers=1, **extra)
    t = np.array([p["t"] for r in mc.execute(prep, at, range(n), quiet=True) for p in r["points"]])
    return {h: float(np.mean(t >= h * success_time * (1 - 1e-12))) for h in HORIZONS}


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py): FULL, or QUICK for the tests."""
    from levitron.runtime.design.launch_design import Pinned
    from levitron.runtime.design.scene_keys import Vary
    from levitron.runtime.physics.equilibrium.finder import equilibria_of
    from levitron.runtime.scan import launch_odds as mc
    o = QUICK if quick else FULL
    extra = {k: o[k] for k in ("t_end",) if k in o}
    lo, hi = equilibria_of(model, bands=True).stable_band.mass
    request = mc.Request.of(model.scene.data.get("launch", {}), None, n=o["n"], workers=1,
                            success_time=o.get("success_time"), **extra)
    pinned = Pinned.at_start(model, request, [Vary("top.mass", lo, hi)])     # the hand, as a design pins it
    T, given, search = pinned.request.success_time, dict(pinned.request.given), pinned.search_time
    masses = np.linspace(lo, hi, o.get("masses", MASSES) + 2)[1:-1]
    from levitron.runtime.ui import progress
    c0, rows = time.process_time(), []
    with progress.task(f"search horizon: launches at {len(masses)} masses", total=len(masses) * o["n"],
                       log_every=10.0) as tick:
        for m in masses:
            odds = _odds_at_horizons(model, float(m), given, o["n"], T, **extra)
            rows.append({"mass": float(m), **{f"odds_{h:g}": v for h, v in odds.items()}})
            tick(o["n"])
    cpu = time.process_time() - c0
    spread = {}
    for h in HORIZONS:
        late = [r[f"odds_{h:g}"] - r["odds_1"] for r in rows]
        spread[h] = float(max(late) - min(late))
    summary = {"scene": model.scene.name, "n": o["n"], "seed": 0, "success_time": T,
               "search_time": search, "horizons": list(HORIZONS), "late_fall_spread": {f"{h:g}": s for h, s in
                                                                                      spread.items()},
               "rows": rows, "cpu_s": cpu}
    out.mkdir(parents=True, exist_ok=True)
    write_text(out / "search_horizon.json", option="«out»", text=json.dumps(summary, indent=2) + "\n")
    with open_text(out / "search_horizon.csv", "«out»", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    draw(rows, T, search, out / "search_horizon.png", model.scene.name)
    eighth, quarter = spread[1 / 8], spread[1 / 4]
    between = max(abs(r["odds_0.125"] - r["odds_0.25"]) for r in rows)
    return {"rows": rows, "search_time": search,
            "files": [str(out / f) for f in ("search_horizon.json", "search_horizon.csv", "search_horizon.png")],
            "headline": (f"{o['n']} launches at {len(rows)} masses: the late falls' spread across the band is "
                         f"{100 * quarter:.2g} points after T/4 and {100 * eighth:.2g} after T/8; T/8 and T/4 "
                         f"differ by at most {100 * between:.2g} points at any mass; the search judges at "
                         f"{search:.3g} of {T:.3g}")}


@in_style
def draw(rows: list[dict], T: float, search: float, path: Path, scene: str) -> None:
    fig, ax = canvas(figsize=(6, 3.6))
    m = [1e3 * r["mass"] for r in rows]
    for h in HORIZONS:
        ax.plot(m, [100 * r[f"odds_{h:g}"] for r in rows], "o-", label=f"judged at {h * T:.3g}")
    ax.set_xlabel("top's mass (g)")
    ax.set_ylabel("launch odds (%)")
    ax.set_title(f"{scene}: the same launches judged at several times; the search's: {search:.3g}",
                 fontsize="small")
    ax.legend(fontsize="x-small")
    fig.tight_layout()
    save_figure(fig, path, "«out»")
