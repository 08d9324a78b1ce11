"""The launch odds of thesis_air over a base levelled with a bubble level, against the level base
(issue 27; docs/contract.md `launch`, "A base that is not level"): prints the
odds and, given a folder, writes {odds.json, odds.png} there.

    nice .venv/bin/python examples/launch_base_tilt.py [N [FOLDER]]   (default N = 40 launches a spread)

The note's figure: `examples/launch_base_tilt.py 2000 reports/launch_base_tilt` (75 s a run on 2 cores).

Every run takes the same seed, so the launches' own inputs (spin, tilt, offset, ...) are the same
draws in every run (the base's tilt is drawn after them, runtime/scan/launch_odds.py `samples`):
the runs differ only in the base, and the launches that float on the level base but not on the
tilted one are counted pair by pair beside the Wilson intervals.

The levelling spreads: a construction-grade spirit level certifies to about 0.5 mm/m (5e-4 rad);
a base levelled with it along two axes, each left within that sd, is tilted by a vector of rms
sqrt(2) x 5e-4 = 7.1e-4 rad; the launch's base_tilt normal:0,7.1e-4 (its sign flips the downhill
direction, whose azimuth is uniform) has that rms. A level of half that quality (1 mm/m per axis)
gives 1.41e-3 rad. The top is the scene's own; everything else is the launch's defaults.
"""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

import levitron as lev
from levitron.runtime.scan.launch_odds import wilson

SCENE = "thesis_air"
SPREADS = (("level base", 0.0), ("spirit level, 0.5 mm/m per axis", 7.1e-4),
           ("level of 1 mm/m per axis", 1.41e-3))


def main(n: int, out: Path | None) -> None:
    study = lev.load(SCENE, {"plate.tilt": 0.0})
    # the level tolerance of the scene's own top, as `stability --level-tolerance` gives it (the
    # field expansion's order raised until the answer holds to 1 %: runtime/physics/field/truncation.py)
    tol = study.stability(level_tolerance=True).level_tolerance
    runs, tables = [], []
    for label, sd in SPREADS:
        spec = 0.0 if sd == 0 else f"normal:0,{sd!r}"
        r = study.launch(n=n, seed=0, inputs={"base_tilt": spec}, workers=2)
        t = r.launches
        tables.append((label, t))
        lo, hi = r.probability_ci95
        runs.append({"label": label, "base_tilt": spec, "probability": r.probability, "ci95": [lo, hi],
                     "successes": int(r.details["successes"]), "n": r.details["n"] - r.details["no_verdict"],
                     "ranking": [(e["input"], e["effect"], e["noise"]) for e in r.details["ranking"]],
                     "success_time": r.details["success_time"], "outcomes": r.details["outcomes"]})
        print(f"{label}: {100 * r.probability:.1f} % ({100 * lo:.1f}-{100 * hi:.1f} %)", flush=True)
    level = tables[0][1]["floats"]
    for run, (_, t) in zip(runs, tables):
        run["lost_against_level"] = int(np.sum((level == 1) & (t["floats"] == 0)))
        run["gained_against_level"] = int(np.sum((level == 0) & (t["floats"] == 1)))
    tilted = np.concatenate([t["base_tilt"] for _, t in tables[1:]])
    floats = np.concatenate([t["floats"] for _, t in tables[1:]])
    edges = np.linspace(0, 2 * tol["fold_tilt"], 11)
    a = np.abs(tilted)
    by_tilt = []
    for lo_e, hi_e in zip(edges[:-1], edges[1:]):
        sel = (a >= lo_e) & (a < hi_e)
        k, m = int(floats[sel].sum()), int(sel.sum())
        by_tilt.append({"bin": [float(lo_e), float(hi_e)], "n": m, "floats": k,
                        "ci95": list(wilson(k, m)) if m else None})
    if out is None:
        return
    out.mkdir(parents=True, exist_ok=True)
    summary = {"scene": SCENE, "n": n, "seed": 0, "runs": runs, "level_tolerance": tol,
               "success_rate_by_base_tilt": by_tilt,
               "command": f"nice .venv/bin/python examples/launch_base_tilt.py {n} {out}"}
    (out / "odds.json").write_text(json.dumps(summary, indent=1, default=float) + "\n")
    draw(summary, out / "odds.png")


def draw(summary: dict, path: Path) -> None:
    from levitron.runtime.ui.plotting import styled
    with styled():                     # the house style, for this figure only
        _draw(summary, path)


def _draw(summary: dict, path: Path) -> None:
    from levitron.runtime.ui.plotting import canvas, save_figure
    fig, (ax1, ax2) = canvas(ncols=2, figsize=(11, 4.2))
    runs = summary["runs"]
    x = np.arange(len(runs))
    p = np.array([r["probability"] for r in runs]) * 100
    ci = np.array([r["ci95"] for r in runs]) * 100
    ax1.errorbar(x, p, yerr=[p - ci[:, 0], ci[:, 1] - p], fmt="o", capsize=5, color="C0")
    ax1.set_xticks(x, [f"{r['label']}\n{r['base_tilt']}" for r in runs], fontsize="small")
    ax1.set_ylabel(f"launches floating {summary['runs'][0]['success_time']:.0f} s (%)")
    ax1.set_title(f"{summary['scene']}: launch odds, 95 % Wilson intervals (n = {summary['n']} each)",
                  fontsize="medium")
    fold = summary["level_tolerance"]["fold_tilt"]
    bins = [b for b in summary["success_rate_by_base_tilt"] if b["n"]]
    mid = np.array([0.5 * sum(b["bin"]) for b in bins]) * 1e3
    rate = np.array([b["floats"] / b["n"] for b in bins]) * 100
    lo = np.array([b["ci95"][0] for b in bins]) * 100
    hi = np.array([b["ci95"][1] for b in bins]) * 100
    ax2.errorbar(mid, rate, yerr=[rate - lo, hi - rate], fmt="o-", capsize=3, color="C0")
    ax2.axvline(fold * 1e3, color="C3", ls="--",
                label=f"max_base_tilt {fold * 1e3:.3g} mrad ({math.degrees(fold):.3g} deg)")
    ax2.set_xlabel("the launch's base tilt |t| (mrad)")
    ax2.set_ylabel("launches floating (%)")
    ax2.set_title("success rate against the base's tilt (the tilted runs pooled)", fontsize="medium")
    ax2.legend(loc="best", fontsize="small")
    fig.tight_layout()
    save_figure(fig, path)


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 40, Path(sys.argv[2]) if len(sys.argv) > 2 else None)
