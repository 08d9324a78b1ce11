"""`levitron bench SCENE --kind verdict-tolerance`: which integrator tolerance a launch's verdict needs.

A launch Monte Carlo (runtime/scan/launch_odds.py) asks of every run one thing: does the top float
at least the success time? The verdict of a run that stays up, or that falls early, does not
depend on the last digits of the trajectory; a run that falls late (its spin decaying through the
lower end of the window, thesis 3.3.19-3.3.23 with air friction) can move by seconds between two
tight tolerances, and its verdict with it, whatever the tolerance. So the launch odds need a
tolerance only as tight as keeps them well inside their own sampling error.

The study: the same n launches (one seed: the same draws, common random numbers) at every
tolerance of TOLS, against the tightest (REFERENCE) as the truth. Per tolerance: the verdicts that
differ from the reference's, the odds and their difference from the reference's odds, the 95 %
Wilson half-width of the reference's odds, the largest change of a flight time among the launches
that fall in both, and the CPU time of the whole Monte Carlo (serial, this process: the work a
design repeats for every evaluation). A tolerance is ADEQUATE where its odds lie within
SHARE of the Wilson half-width of the reference's (the sampling noise dwarfs the integration's)
and it changes at most MAX_CHANGED of the verdicts; the report names the loosest adequate one.
runtime/scan/launch_odds.py's LAUNCH_TOL is a decade tighter than the loosest tolerance adequate on
every scene of the study (thesis_air and levitron_toy, 1000 launches each: 1e-5 on both, the
loosest tried), a margin for the scenes the study did not try.

Writes verdict_tolerance.csv, verdict_tolerance.json and verdict_tolerance.png (odds and changed
verdicts against the tolerance, the CPU time beside them).
"""
from __future__ import annotations

import csv
import json
import time
from pathlib import Path

import numpy as np

from levitron.runtime.ui.atomic import open_text, write_text
from levitron.runtime.ui.plotting import canvas, in_style, save_figure

REFERENCE = 1e-10
TOLS = (1e-5, 1e-6, 1e-7, 1e-8, 1e-9)
SHARE = 0.25            # adequate: |odds - odds_ref| <= SHARE x the reference's Wilson half-width
MAX_CHANGED = 0.01      # and at most this fraction of the verdicts changed
FULL = {"n": 1000}
QUICK = {"n": 8, "tols": (1e-6,), "success_time": 0.5, "t_end": 0.5}
COLUMNS = ("tol", "n", "probability", "probability_ci95", "odds_change", "half_width_ref", "changed",
           "changed_late_falls", "largest_flight_change", "cpu_s", "speedup", "adequate")


def run_at(model, tol: float, n: int, **options) -> tuple[dict, float]:
    """One serial Monte Carlo of the scene's launch spread at `tol`, with its CPU time (s)."""
    from levitron.runtime.scan import launch_odds as mc
    request = mc.Request.of(model.scene.data.get("launch", {}), None, n=n, tol=tol, workers=1, **options)
    c0 = time.process_time()
    res = request.run(model, quiet=True)
    return res, time.process_time() - c0


def compare(ref: dict, res: dict, cpu_ref: float, cpu: float) -> dict:
    """One row of the study: `res` against the reference Monte Carlo `ref` (same seed, same n)."""
    from levitron.runtime.scan.launch_summary import wilson
    a, b = ref["verdicts"], res["verdicts"]
    t_ref, t = np.array(ref["flight_time"]["values"]), np.array(res["flight_time"]["values"])
    changed = [i for i, (u, v) in enumerate(zip(a, b)) if u != v]
    success_time = ref["success_time"]
    late = [i for i in changed if min(t_ref[i], t[i]) >= 0.5 * success_time]
    falls = np.array([u is False and v is False for u, v in zip(a, b)])
    lo, hi = wilson(ref["successes"], ref["n"] - ref["no_verdict"])
    half = 0.5 * (hi - lo)
    change = res["probability"] - ref["probability"]
    return {"tol": res["tol"], "n": res["n"], "probability": res["probability"],
            "probability_ci95": list(res["probability_ci95"]), "odds_change": change,
            "half_width_ref": half, "changed": len(changed), "changed_late_falls": len(late),
            "largest_flight_change": float(np.max(np.abs(t - t_ref)[falls])) if falls.any() else 0.0,
            "cpu_s": cpu, "speedup": cpu_ref / cpu if cpu > 0 else float("inf"),
            "adequate": bool(abs(change) <= SHARE * half and len(changed) <= MAX_CHANGED * res["n"])}


@in_style
def draw(rows: list[dict], path: Path, scene: str) -> None:
    fig, (ax, bx) = canvas(ncols=2, figsize=(9, 3.6))
    tol = [r["tol"] for r in rows]
    ax.errorbar(tol, [100 * r["probability"] for r in rows],
                yerr=[[100 * (r["probability"] - r["probability_ci95"][0]) for r in rows],
                      [100 * (r["probability_ci95"][1] - r["probability"]) for r in rows]],
                fmt="o-", capsize=3, label="odds (95 % Wilson)")
    ax.set_xscale("log")
    ax.set_xlabel("integrator tolerance")
    ax.set_ylabel("launch odds (%)")
    ax2 = ax.twinx()
    ax2.bar(tol, [r["changed"] for r in rows], width=[0.4 * t for t in tol], color="C3", alpha=0.35,
            label="verdicts changed")
    ax2.set_ylabel("verdicts changed vs the reference", color="C3")
    ax.set_title(f"{scene}: {rows[0]['n']} launches, reference tol {REFERENCE:g}", fontsize="small")
    bx.plot(tol, [r["cpu_s"] for r in rows], "o-")
    bx.set_xscale("log")
    bx.set_xlabel("integrator tolerance")
    bx.set_ylabel("CPU s of the Monte Carlo (serial)")
    for r in rows:
        if r["adequate"]:
            bx.plot(r["tol"], r["cpu_s"], "o", color="C2", ms=9, mfc="none")
    bx.set_title("green rings: adequate (odds within a quarter of the half-width)", fontsize="small")
    fig.tight_layout()
    save_figure(fig, path, "«out»")


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py): FULL, or QUICK for the tests."""
    o = QUICK if quick else FULL
    extra = {k: o[k] for k in ("success_time", "t_end") if k in o}
    ref, cpu_ref = run_at(model, REFERENCE, o["n"], **extra)
    rows = []
    for tol in o.get("tols", TOLS):
        res, cpu = run_at(model, tol, o["n"], **extra)
        rows.append(compare(ref, res, cpu_ref, cpu))
    rows.append({**compare(ref, ref, cpu_ref, cpu_ref), "adequate": True})
    rows.sort(key=lambda r: r["tol"])
    adequate = [r["tol"] for r in rows if r["adequate"]]
    loosest = max(adequate)
    out.mkdir(parents=True, exist_ok=True)
    from levitron.runtime.scan.launch_odds import LAUNCH_TOL
    summary = {"scene": model.scene.name, "n": o["n"], "seed": ref["seed"], "reference_tol": REFERENCE,
               "success_time": ref["success_time"], "share": SHARE, "max_changed": MAX_CHANGED,
               "loosest_adequate": loosest, "launch_tol": LAUNCH_TOL,
               "launch_tol_adequate": LAUNCH_TOL in adequate or LAUNCH_TOL <= min(adequate), "rows": rows}
    write_text(out / "verdict_tolerance.json", option="«out»", text=json.dumps(summary, indent=2) + "\n")
    with open_text(out / "verdict_tolerance.csv", "«out»", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    draw(rows, out / "verdict_tolerance.png", model.scene.name)
    at = {r["tol"]: r for r in rows}
    row = at.get(LAUNCH_TOL)
    return {"rows": rows, "loosest_adequate": loosest,
            "files": [str(out / f) for f in ("verdict_tolerance.json", "verdict_tolerance.csv",
                                             "verdict_tolerance.png")],
            "headline": (f"{o['n']} launches against tol {REFERENCE:g}: the loosest adequate tolerance is "
                         f"{loosest:g}" + ("" if row is None else
                                           f"; at the launch default {LAUNCH_TOL:g} {row['changed']} "
                                           f"verdicts change, the odds by {100 * row['odds_change']:+.2g} "
                                           f"points (half-width {100 * row['half_width_ref']:.2g}), "
                                           f"{row['speedup']:.2g}x faster than the reference"))}
