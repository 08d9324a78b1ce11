"""`levitron bench SCENE --kind startup`: how long a person waits for a one-shot command.

Each command of COMMANDS runs as a fresh process (the installed `levitron` script, or `python -m
runtime` without it), warm: one untimed run first compiles and caches what the command needs, so
the timed runs measure start-up, imports and the answer. The figure is the minimum wall time over
adaptive repeats (runtime/bench/repeat.py), beside the median and the command's budget; the load
average of the machine is recorded with it. Writes startup.csv, startup.json and startup.png.
"""
from __future__ import annotations

import csv
import json
import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

from levitron.runtime.bench.repeat import best_of
from levitron.runtime.ui.plotting import canvas, save_figure, styled
from levitron.runtime.ui.atomic import open_text, write_text

# (label, arguments after `levitron`, budget in s); "{scene}" is the scene
COMMANDS = (
    ("--version", ["--version"], 0.2),
    ("--help", ["--help"], 0.3),
    ("stability", ["stability", "{scene}", "--json"], 0.5),
    ("equilibrium", ["equilibrium", "{scene}", "--json"], 0.5),
)


def launcher() -> list[str]:
    """How a person starts the command: the `levitron` script beside this Python, else -m."""
    script = Path(sys.executable).with_name("levitron")
    if script.exists():
        return [str(script)]
    found = shutil.which("levitron")
    return [found] if found else [sys.executable, "-m", "levitron.runtime"]


def _as_typed(name: str, ref: str) -> str:
    """The scene as a person types it: its name when it is that file of scenes/ (a path to it
    would be timed as an out-of-tree scene), else the path."""
    from levitron.scene.load import SceneError, find_scene_file
    try:
        same = find_scene_file(name).resolve() == Path(ref).resolve()
    except (SceneError, OSError):
        same = False
    return name if same else ref


def time_command(argv: list[str], quick: bool) -> dict:
    """One command, warm: its best and median wall time over adaptive repeats."""
    def once() -> float:
        t0 = time.perf_counter()
        subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        wall = time.perf_counter() - t0
        walls.append(wall)
        return wall

    walls: list[float] = []
    once()                                  # warm: compile and cache, not timed
    walls.clear()
    t = best_of(once, min_runs=2 if quick else 5, patience=1 if quick else 3, rtol=0.03,
                max_runs=3 if quick else 30, budget_s=5.0 if quick else 20.0)
    return {"min_s": t.best, "median_s": statistics.median(walls), "runs": t.runs, "stable": t.stable}


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py)."""
    sets = [a for kv in model.scene.overrides for a in ("--set", kv)]
    scene_ref = _as_typed(model.scene.name, model.ref.scene)
    base = launcher()
    load_before = os.getloadavg()
    rows = []
    for label, template, budget in COMMANDS:
        args = [a.format(scene=scene_ref) for a in template]
        r = time_command(base + args + (sets if "{scene}" in template else []), quick)
        rows.append({"command": label, "argv": " ".join(["levitron", *args]), "budget_s": budget,
                     "within_budget": r["min_s"] < budget, **r})
    load_after = os.getloadavg()
    out.mkdir(parents=True, exist_ok=True)
    with open_text(out / "startup.csv", "«out»", newline="") as fh:
        w = csv.DictWriter(fh, ["command", "min_s", "median_s", "budget_s", "within_budget", "runs",
                                "stable", "argv"])
        w.writeheader()
        w.writerows(rows)
    res = {"scene": model.scene.name, "launcher": " ".join(base), "rows": rows,
           "load_average_1_5_15": {"before": load_before, "after": load_after}, "quick": quick}
    write_text(out / "startup.json", option="«out»", text=json.dumps(res, indent=2) + "\n")
    with styled():
        fig, ax = canvas(figsize=(6, 2.8))
        ys = range(len(rows))
        ax.barh(ys, [r["min_s"] for r in rows], color="tab:blue", label="min of repeats")
        ax.scatter([r["budget_s"] for r in rows], ys, marker="|", s=300, color="tab:red", label="budget")
        ax.set_yticks(list(ys), [r["command"] for r in rows])
        ax.set_xlabel("wall time of a warm one-shot command (s)")
        ax.set_title(f"{model.scene.name}: start-up (load {load_before[0]:.1f})", fontsize="medium")
        ax.legend(fontsize="small")
        fig.tight_layout()
        png = save_figure(fig, out / "startup.png")
    res["files"] = [str(out / "startup.csv"), str(out / "startup.json"), str(png)]
    res["headline"] = "; ".join(f"{r['command']} {r['min_s']:.3f} s (budget {r['budget_s']:g})"
                                for r in rows) + f"; load {load_before[0]:.2f}"
    return res
