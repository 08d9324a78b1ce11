"""`levitron bench SCENE --kind launch-design`: the wall time of a design by the launch odds.

The design of runtime/design/launch_design.py over the top's mass, in the stable band's masses at
the scene's temperature (as `levitron trim` runs it; a scene without a band is a one-line error),
with FULL["n"] launches an evaluation (the default launch spread, the default success time), on 1
and on FULL["workers"] processes. Per row: workers, n, evaluations, wall_s, the advice, its odds
(fresh seed) and the machine's load average before and after (os.getloadavg: a loaded machine's
figure is slower, and the report says so); the goal GOAL_S (a design by the launch odds: one key, 300 launches, under
60 s on 2 cores). Writes launch_design.json, launch_design.csv and launch_design.png.
"""
from __future__ import annotations

import csv
import json
import os
import time
from pathlib import Path

from levitron.runtime.ui.human import Units
from levitron.runtime.ui.atomic import open_text, write_text
from levitron.runtime.ui.plotting import canvas, in_style, save_figure

GOAL_S = 60.0
FULL = {"n": 300, "workers": (1, 2)}
QUICK = {"n": 6, "workers": (1,), "success_time": 1.0, "t_end": 1.0}
COLUMNS = ("workers", "n", "evaluations", "wall_s", "goal_s", "meets_goal", "advice", "probability",
           "probability_ci95", "load_before", "load_after")


def measure(model, n: int, workers: int, **options) -> dict:
    """One launch-odds design over top.mass in the band, timed whole (pinning, search, fresh seed)."""
    from levitron.runtime.design.launch_design import maximize_launch_odds
    from levitron.runtime.design.scene_keys import Vary
    from levitron.runtime.errors import UserError
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.scan import launch_odds as mc
    band = eqm.equilibria_of(model, bands=True).stable_band
    if band is None:
        raise UserError(f"{model.scene.name}: no stable band, so no mass to design: bench a scene whose top can hover")
    request = mc.Request.of(model.scene.data.get("launch", {}), None, n=n, workers=workers, **options)
    load_before = os.getloadavg()[0]
    t0 = time.perf_counter()
    res = maximize_launch_odds(model, [Vary("top.mass", *band.mass)], request)
    wall = time.perf_counter() - t0
    return {"workers": workers, "n": n, "evaluations": len(res.evaluations), "wall_s": wall,
            "goal_s": GOAL_S, "meets_goal": wall < GOAL_S, "advice": res.optimum["top.mass"],
            "probability": res.probability, "probability_ci95": res.launch_odds["probability_ci95"],
            "load_before": load_before, "load_after": os.getloadavg()[0]}


@in_style
def draw(rows: list[dict], path: Path, scene: str) -> None:
    fig, ax = canvas(figsize=(6, 3.4))
    labels = [f"{r['workers']} worker{'s' if r['workers'] > 1 else ''}\n(load {r['load_before']:.1f})" for r in rows]
    ax.bar(labels, [r["wall_s"] for r in rows], color="C0")
    ax.axhline(GOAL_S, color="C3", ls="--", label=f"goal {GOAL_S:g} s")
    ax.set_ylabel("wall time of one design (s)")
    ax.set_title(f"{scene}: launch-odds design over top.mass, {rows[0]['n']} launches an evaluation, "
                 f"{rows[0]['evaluations']} evaluations", fontsize="small")
    ax.legend(loc="upper right")
    fig.tight_layout()
    save_figure(fig, path, "«out»")


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py): FULL, or QUICK for the tests."""
    o = QUICK if quick else FULL
    extra = {k: o[k] for k in ("success_time", "t_end") if k in o}
    rows = [measure(model, o["n"], w, **extra) for w in o["workers"]]
    out.mkdir(parents=True, exist_ok=True)
    write_text(out / "launch_design.json", option="«out»",
               text=json.dumps({"scene": model.scene.name, "rows": rows}, indent=2) + "\n")
    with open_text(out / "launch_design.csv", "«out»", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    draw(rows, out / "launch_design.png", model.scene.name)
    u = Units.of_scene(model.scene)
    best = min(rows, key=lambda r: r["wall_s"])
    return {"rows": rows, "files": [str(out / f) for f in ("launch_design.json", "launch_design.csv",
                                                           "launch_design.png")],
            "headline": (f"a launch-odds design over top.mass ({best['n']} launches x {best['evaluations']} "
                         f"evaluations) in {best['wall_s']:.3g} s on {best['workers']} worker(s) (goal "
                         f"{GOAL_S:g} s; load {best['load_before']:.2f}): advice {u.mass(best['advice'])}, "
                         f"odds {100 * best['probability']:.3g} %")}
