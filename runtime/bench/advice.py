"""`levitron bench SCENE --kind advice`: how long a person waits for the advice, in CPU and wall time.

The questions a person asks of a scene in air, each run as the command a person types, in a fresh
process with `--json` (no progress drawn), timed whole:

    trim           levitron trim SCENE
    design-mass    levitron optimize SCENE --maximize launch-odds --vary top.mass=LO:HI (the band)
    design-plate   the same over two of the plate's numbers (PLATE_SPAN around the scene's values)
    yield-plate    optimize SCENE --maximize yield over the same box, 300 kits, WASHERS
    tolerance      levitron stability SCENE --set top.moment_tilt=MOMENT_TILT --level-tolerance
    launch         levitron launch SCENE (1000 launches)

Per case: the wall time, the CPU seconds of the whole process tree (the growth of this process's
RUSAGE_CHILDREN over the run: the command and the worker processes it waited for), the machine's
load average before and after (os.getloadavg: another job on the machine shows), and the answer's
headline number (the odds, the advice, max_moment_tilt). GOALS are the speed goals the product set itself (CPU seconds).

LEVITRON_BENCH_CASES=trim,launch runs only the cases named. Before and after: with
LEVITRON_BENCH_CODE=/path/to/another/checkout the commands run that
checkout's code (PYTHONPATH), so the same bench measures an older commit; its advice.json, saved
as advice_before.json in the report folder, is shown beside the new figures in the table and the
plot. Writes advice.json, advice.csv and advice.png.
"""
from __future__ import annotations

import csv
import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

from levitron.runtime.ui.atomic import open_text, write_text
from levitron.runtime.ui.plotting import canvas, in_style, save_figure

GOALS = {"trim": 20.0, "design-mass": 15.0, "design-plate": 60.0, "yield-plate": 120.0, "tolerance": 10.0,
         "launch": 5.0}
WASHERS = (0.004, 0.008, 0.016)   # the yield design's washers, fractions of the top's mass (0.2, 0.4, 0.8 g of 51.5 g)
MOMENT_TILT = 0.05
PLATE_SPAN = 0.01            # the plate keys' box: the scene's value +- this fraction
QUICK_EXTRA = ["--n", "8", "--t-end", "1"]
COLUMNS = ("case", "command", "wall_s", "cpu_s", "goal_cpu_s", "meets_goal", "exit", "headline",
           "load_before", "load_after", "before_cpu_s", "before_wall_s")


def plate_keys(model, k: int = 2) -> list[str]:
    """The first k numbers of the scene's [plate] table that a design may vary (not its kind,
    tilt or temperature coefficient)."""
    plate = model.scene.data.get("plate", {})
    return [f"plate.{key}" for key, v in plate.items()
            if isinstance(v, (int, float)) and not isinstance(v, bool) and v != 0
            and key not in ("tilt", "temperature_coefficient")][:k]


def cases(model, quick: bool) -> dict[str, list[str]]:
    """Each case's command line (module docstring) for this scene."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    name = str(model.scene.path or model.scene.name)
    sets = [a for s in model.scene.overrides for a in ("--set", s)]
    extra = QUICK_EXTRA if quick else []
    out = {"trim": ["trim", name, *sets, *extra]}
    band = eqm.equilibria_of(model, bands=True).stable_band
    if band is not None:
        lo, hi = band.mass
        out["design-mass"] = ["optimize", name, *sets, "--maximize", "launch-odds", "--vary",
                              f"top.mass={lo:.6g}:{hi:.6g}", *extra]
    keys = plate_keys(model)
    if len(keys) == 2:
        from levitron.runtime.design.scene_keys import key_value
        box = []
        for key in keys:
            v = key_value(model.scene.data, key)
            a, b = sorted((v * (1 - PLATE_SPAN), v * (1 + PLATE_SPAN)))
            box += ["--vary", f"{key}={a:.8g}:{b:.8g}"]
        out["design-plate"] = ["optimize", name, *sets, "--maximize", "launch-odds", *box, *extra]
        washers = ",".join(f"{f * model.param('m'):.3g}" for f in WASHERS)
        out["yield-plate"] = ["optimize", name, *sets, "--maximize", "yield", *box, "--washers", washers,
                              *(["--kits", "10"] if quick else []), *extra]
    if not quick:
        out["tolerance"] = ["stability", name, *sets, "--set", f"top.moment_tilt={MOMENT_TILT}",
                            "--level-tolerance"]
    out["launch"] = ["launch", name, *sets, *extra]
    return out


def headline(case: str, answer: dict) -> str:
    """The answer's number a person reads."""
    if case == "tolerance":
        tol = answer.get("level_tolerance") or {}
        return f"max_moment_tilt {tol.get('max_moment_tilt')}, max_base_tilt {tol.get('max_base_tilt')}"
    if case.startswith("yield"):
        return f"optimum {answer.get('optimum')}, yield {(answer.get('yield') or {}).get('probability')}"
    design = answer.get("design", answer)
    odds = design.get("launch_odds", answer.get("launch_odds"))
    if case == "launch":
        return f"odds {answer.get('probability')}"
    return f"optimum {design.get('optimum')}, odds {None if odds is None else odds.get('probability')}"


def measure(case: str, argv: list[str]) -> dict:
    """One command in a fresh process, timed whole (wall, and the CPU of its process tree)."""
    env = dict(os.environ, LEVITRON_PROGRESS="0")
    code = os.environ.get("LEVITRON_BENCH_CODE")
    if code:
        env["PYTHONPATH"] = code
    cmd = [sys.executable, "-m", "levitron.runtime", *argv, "--json"]
    load_before = os.getloadavg()[0]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    # `python -m` puts the working folder first on sys.path: run another checkout from its own folder
    proc = subprocess.run(cmd, capture_output=True, env=env, text=True, check=False, cwd=code or None)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    out, err = proc.stdout, proc.stderr
    try:
        answer = json.loads(out) if out.strip() else {}
        head = headline(case, answer) if proc.returncode == 0 else err.strip().splitlines()[-1:]
    except json.JSONDecodeError:
        head = "(no JSON)"
    return {"case": case, "command": "levitron " + " ".join(argv), "wall_s": wall, "cpu_s": cpu,
            "goal_cpu_s": GOALS.get(case), "meets_goal": cpu <= GOALS.get(case, 0),
            "exit": proc.returncode, "headline": str(head), "load_before": load_before,
            "load_after": os.getloadavg()[0]}


@in_style
def draw(rows: list[dict], path: Path, scene: str) -> None:
    fig, ax = canvas(figsize=(7.5, 3.6))
    x = range(len(rows))
    before = [r.get("before_cpu_s") or 0 for r in rows]
    if any(before):
        ax.bar([i - 0.2 for i in x], before, width=0.4, color="C7", label="CPU s before")
    ax.bar([i + (0.2 if any(before) else 0) for i in x], [r["cpu_s"] for r in rows],
           width=0.4, color="C0", label="CPU s now")
    ax.plot([i + 0.2 for i in x], [r["wall_s"] for r in rows], "o", color="C1", label="wall s now")
    ax.scatter(list(x), [r["goal_cpu_s"] or 0 for r in rows], marker="_", s=600, color="C3", label="goal (CPU s)")
    ax.set_yscale("log")
    ax.set_xticks(list(x), [r["case"] for r in rows])
    ax.set_ylabel("seconds")
    ax.set_title(f"{scene}: the advice a person waits for (load {rows[0]['load_before']:.1f})", fontsize="small")
    ax.legend(fontsize="x-small")
    fig.tight_layout()
    save_figure(fig, path, "«out»")


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py)."""
    only = [c for c in os.environ.get("LEVITRON_BENCH_CASES", "").split(",") if c]
    rows = [measure(case, argv) for case, argv in cases(model, quick).items() if not only or case in only]
    out.mkdir(parents=True, exist_ok=True)
    before_file = out / "advice_before.json"
    if before_file.exists():
        before = {r["case"]: r for r in json.loads(before_file.read_text())["rows"]}
        for r in rows:
            b = before.get(r["case"], {})
            r["before_cpu_s"], r["before_wall_s"] = b.get("cpu_s"), b.get("wall_s")
    write_text(out / "advice.json", option="«out»", text=json.dumps(
        {"scene": model.scene.name, "quick": quick, "code": os.environ.get("LEVITRON_BENCH_CODE"),
         "cores": os.cpu_count(), "rows": rows}, indent=2) + "\n")
    with open_text(out / "advice.csv", "«out»", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    draw(rows, out / "advice.png", model.scene.name)
    return {"rows": rows, "files": [str(out / f) for f in ("advice.json", "advice.csv", "advice.png")],
            "headline": "; ".join(f"{r['case']} {r['cpu_s']:.3g} CPU s ({r['wall_s']:.3g} s wall)"
                                  for r in rows)}
