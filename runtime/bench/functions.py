"""`levitron bench SCENE --kind functions`: nanoseconds per call of every generated function of a
scene (the C of generated/<scene>/model.c, timed by a loop in C, lev_time_fn, the minimum of
REPEATS), beside its operation count (manifest.json): what an integrator step or a map point
costs, and what the compiler makes of the op counts. Writes functions.csv and functions.png."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from levitron.runtime.integrate.c_backend import time_fn_ns
from levitron.runtime.ui.plotting import canvas, save_figure, styled
from levitron.runtime.ui.atomic import open_text

REPEATS = 3


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py)."""
    reps = 20_000 if quick else 1_000_000
    rows = []
    rng = np.random.default_rng(0)
    for name, f in sorted(model.manifest.functions.items()):
        x = 0.1 + 0.01 * rng.standard_normal(f.n_in)          # away from 0 and the axis
        ns = min(time_fn_ns(model.lib, model.c_function(name), x, model.p, f.n_out, reps)
                 for _ in range(REPEATS))
        rows.append({"function": name, "ops": f.ops, "ns": ns, "ns_per_op": ns / max(f.ops, 1)})
    out.mkdir(parents=True, exist_ok=True)
    with open_text(out / "functions.csv", "«out»", newline="") as fh:
        w = csv.DictWriter(fh, ["function", "ops", "ns", "ns_per_op"])
        w.writeheader()
        w.writerows(rows)
    with styled():
        fig, ax = canvas(figsize=(6, 4))
        ax.loglog([r["ops"] for r in rows], [r["ns"] for r in rows], "o")
        for r in rows:
            ax.annotate(r["function"], (r["ops"], r["ns"]), fontsize="x-small")
        ax.set_xlabel("operations (manifest.json)")
        ax.set_ylabel("ns per call (min of repeats)")
        ax.set_title(f"{model.scene.name}: the generated functions", fontsize="medium")
        fig.tight_layout()
        png = save_figure(fig, out / "functions.png")
    rhs = next((r for r in rows if r["function"] == "full_rhs"), rows[0])
    return {"rows": rows, "files": [str(out / "functions.csv"), str(png)],
            "headline": f"{len(rows)} functions; {rhs['function']} {rhs['ns']:.0f} ns a call "
                        f"({rhs['ops']} operations, {rhs['ns_per_op']:.2f} ns each)"}
