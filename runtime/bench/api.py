"""`levitron bench SCENE --kind api`: what the public API adds around the C integration it reports.

A notebook sweep calls `Study.simulate` once per point, so the Python around the integration (the
launch through the Legendre map, thesis eq. 2.3.8; the checks; the summary's invariants and the
trajectory table) is paid on every call. The case is a short run of the scene's own top: at the
geometric mean of its stable spin interval (the work-precision bench's operating point,
runtime/bench/work_precision.py `setup`), the default tilt, RUN_SPIN_PERIODS spin periods, the
default integrator and tolerance: what `simulate` does for a person who passes only a spin and a
run length. Each part of the scene's model is timed (the reduced model with `part="reduced"`).

The figures, per part: the fastest call's wall time, the integration that call reports
(details["wall_s"], the C integrator's own clock), and the overhead: the smallest wall time less
its own integration over all calls. Calls alternate between the parts and go on for at least
SECONDS (quick: QUICK_SECONDS), so that every part sees the machine at its fastest (this VM's core
has 0.1-1 s stretches some 40 % slower). The budget: the overhead under OVERHEAD_BUDGET_S.
Writes api.csv, api.json and api.png.
"""
from __future__ import annotations

import csv
import json
import math
import os
import time
from pathlib import Path

from levitron.runtime.bench.operating_point import setup
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.plotting import canvas, in_style, save_figure
from levitron.runtime.ui.atomic import open_text, write_text

RUN_SPIN_PERIODS = 8          # the short run: 8 spin periods (0.045 s for thesis_stable's top)
OVERHEAD_BUDGET_S = 1e-3      # the goal: a short API simulation within 1 ms of its integration
SECONDS = 4.0
QUICK_SECONDS = 0.2
COLUMNS = ("part", "call", "wall_s", "integration_s", "overhead_s", "budget_s", "within_budget", "calls")


def cases(study, su) -> list[tuple[str, dict]]:
    """(part, Study.simulate's keyword arguments) of each part of the scene's model."""
    t_end = RUN_SPIN_PERIODS * 2 * math.pi / su.spin
    return [(part, {"spin": su.spin, "t_end": t_end, **({"part": "reduced"} if part == "reduced" else {})})
            for part in ("full", "reduced") if part in study.model.parts]


def time_calls(study, runs: list[tuple[str, dict]], seconds: float) -> list[dict]:
    """Each case called in turn for at least `seconds`: the figures of the module docstring."""
    best = {part: {"wall_s": math.inf, "integration_s": None, "overhead_s": math.inf, "calls": 0}
            for part, _ in runs}
    for _, kw in runs:                          # warm: the library, the first call's allocations
        study.simulate(**kw)
    stop = time.perf_counter() + seconds
    while time.perf_counter() < stop:
        for part, kw in runs:
            t0 = time.perf_counter()
            sim = study.simulate(**kw)
            wall = time.perf_counter() - t0
            b = best[part]
            b["calls"] += 1
            b["overhead_s"] = min(b["overhead_s"], wall - sim.wall_s)
            if wall < b["wall_s"]:
                b["wall_s"], b["integration_s"] = wall, sim.wall_s
    return [{"part": part, "call": "Study.simulate(" + ", ".join(f"{k}={v!r}" if isinstance(v, str)
                                                                  else f"{k}={v:.6g}" for k, v in kw.items()) + ")",
             **best[part], "budget_s": OVERHEAD_BUDGET_S,
             "within_budget": best[part]["overhead_s"] < OVERHEAD_BUDGET_S} for part, kw in runs]


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py)."""
    from levitron.study import Study            # the public API is what is measured
    study = Study(model)
    su = setup(model)                           # refuses a scene without a stable interval
    load_before = os.getloadavg()
    rows = time_calls(study, cases(study, su), QUICK_SECONDS if quick else SECONDS)
    load_after = os.getloadavg()
    out.mkdir(parents=True, exist_ok=True)
    with open_text(out / "api.csv", "«out»", newline="") as fh:
        w = csv.DictWriter(fh, COLUMNS)
        w.writeheader()
        w.writerows(rows)
    res = {"scene": model.scene.name, "description": __doc__, "rows": rows,
           "load_average_1_5_15": {"before": load_before, "after": load_after}, "quick": quick}
    write_text(out / "api.json", option="«out»", text=json.dumps(res, indent=1) + "\n")
    png = draw(rows, out / "api.png", f"{model.scene.name}: Study.simulate, {RUN_SPIN_PERIODS} spin periods "
               f"at {Units.of_scene(model.scene).rate(su.spin)} (load {load_before[0]:.1f})")
    res["files"] = [str(out / "api.csv"), str(out / "api.json"), str(png)]
    res["headline"] = "; ".join(
        f"{r['part']}: {r['wall_s'] * 1e3:.3f} ms for {r['integration_s'] * 1e3:.3f} ms of integration, "
        f"overhead {r['overhead_s'] * 1e3:.3f} ms (budget {r['budget_s'] * 1e3:g} ms)" for r in rows) \
        + f"; load {load_before[0]:.2f}"
    return res


@in_style
def draw(rows: list[dict], path: Path, title: str) -> Path:
    """The fastest call of each part: its integration and the rest of its wall time, in ms, with the
    budget (the integration plus OVERHEAD_BUDGET_S)."""
    fig, ax = canvas(figsize=(6.4, 1.6 + 0.6 * len(rows)))
    ys = range(len(rows))
    integ = [r["integration_s"] * 1e3 for r in rows]
    ax.barh(ys, integ, color="tab:blue", label="integration (C)")
    ax.barh(ys, [r["wall_s"] * 1e3 - i for r, i in zip(rows, integ)], left=integ, color="tab:orange",
            label="Python around it")
    ax.scatter([i + r["budget_s"] * 1e3 for r, i in zip(rows, integ)], ys, marker="|", s=400,
               color="tab:red", label="budget")
    ax.set_yticks(list(ys), [r["part"] for r in rows])
    ax.set_xlabel("wall time of the fastest call (ms)")
    ax.set_title(title, fontsize="small")
    # the legend in a strip of fixed height at the figure's foot: anchored at a fraction of the
    # axes' height it overlapped the x label when one bar (one part) made the axes short
    strip = 0.35 / fig.get_figheight()
    fig.legend(*ax.get_legend_handles_labels(), fontsize="x-small", loc="lower center", ncol=3,
               markerscale=0.4, bbox_to_anchor=(0.5, 0.0))
    fig.tight_layout(rect=(0.0, strip, 1.0, 1.0))
    return save_figure(fig, path)
