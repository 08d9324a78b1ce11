"""The design part of the bench: how long one verified design optimisation takes
(runtime/design/optimize.py: grid of the box by the exact float routes, IPOPT on the exact derivatives of
runtime/physics/stability/differentiable.py, verification at the optimum; thesis 3.3.2-3.3.16).

Cases (the scene SCENE, default thesis_stable; bounds relative to the scene's own values, so any
scene with a spin interval works): spin-range over the top's mass (one key), spin-range over the
mass and the plate's first length key (two keys), and in the full bench mass-window over that
length key; the spin objectives under a stiffness floor of STIFFNESS_FRACTION times the scene's own
stiffness. Per case: keys, objective, value, solver_status, iterations (IPOPT's), grid_points,
wall_s (the whole `design.optimize` call, verification included), goal_s (GOAL_S) and meets_goal.
A case IPOPT cannot solve is a row with its one-line error, not a crash.

    levitron bench [SCENE] --kind design [--quick] [--out DIR] [--set KEY=VALUE ...]

--quick: the one-key case only. Writes DIR/bench_design.json and DIR/bench_design.csv
(default DIR reports/design).
"""
from __future__ import annotations

import csv
import json
import time
from pathlib import Path

from levitron.runtime.errors import UserError
from levitron.runtime.ui.atomic import open_text, write_text

GOAL_S = 2.0                        # the goal: one design optimisation, verification included
# the spin objectives need a stiffness floor (runtime/design/optimize.py): this fraction of the
# scene's own top's stiffness mu Phi_3(z_s) (thesis 3.3.3) at its hover height (thesis_stable's
# 2.56 N/m gives 0.511 N/m; a dimensionless scene's its own number), never a fixed value
STIFFNESS_FRACTION = 0.2
MASS_SPAN = (0.98, 1.0175)          # the top's mass box relative to the scene's (0.0505:0.0524 kg)
LENGTH_SPAN = (0.95, 1.05)          # the plate key's box relative to the scene's
COLUMNS = ("case", "objective", "keys", "value", "solver_status", "iterations", "grid_points",
           "wall_s", "goal_s", "meets_goal", "error")


def _box(scene, key: str, span: tuple[float, float]) -> str:
    from levitron.runtime.design.scene_keys import key_value
    v = key_value(scene.data, key)
    lo, hi = sorted((span[0] * v, span[1] * v))
    return f"{key}={lo:.6g}:{hi:.6g}"


def plate_length_key(scene) -> str:
    """The plate's first positive length-like key: `hole`, else `radius`, else the first positive
    number of the [plate] table (the two-key case varies it with the mass)."""
    plate = scene.data.get("plate", {})
    for k in ("hole", "radius"):
        if isinstance(plate.get(k), (int, float)) and plate[k] > 0:
            return f"plate.{k}"
    for k, v in plate.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool) and v > 0:
            return f"plate.{k}"
    raise UserError(f"scene '{scene.name}': its [plate] has no positive number to vary")


def stiffness_floor(model) -> str:
    """The constraint `stiffness>=K`, K = STIFFNESS_FRACTION times the scene's own stiffness."""
    from levitron.runtime.physics.equilibrium.finder import hover_height, params_of
    k = params_of(model)["mu"] * float(model.onaxis(hover_height(model))[3])
    return f"stiffness>={STIFFNESS_FRACTION * k:.4g}"


def cases(scene, quick: bool, floor: str) -> list[tuple[str, str, list[str], list[str]]]:
    """(case name, objective, --vary boxes, --constrain) of the bench (module docstring); floor:
    stiffness_floor's constraint."""
    mass = _box(scene, "top.mass", MASS_SPAN)
    length = _box(scene, plate_length_key(scene), LENGTH_SPAN)
    out = [("one_key", "spin-range", [mass], [floor])]
    if not quick:
        out += [("two_keys", "spin-range", [mass, length], [floor]),
                ("mass_window", "mass-window", [length], [])]
    return out


def run(model, quick: bool = False) -> dict:
    """The cases of `cases` on the loaded model (its overrides included)."""
    from levitron.runtime.design import optimize as design
    from levitron.runtime.design.constraints import Constraint
    from levitron.runtime.design.scene_keys import Vary
    rows = []
    for name, objective, boxes, cons in cases(model.scene, quick, stiffness_floor(model)):
        row = {"case": name, "objective": objective, "keys": " ".join(boxes),
               "constraints": cons, "goal_s": GOAL_S}
        t1 = time.perf_counter()
        try:
            res = design.optimize(model, [Vary.parse(b) for b in boxes], objective,
                                  [Constraint.parse(c) for c in cons])
        except UserError as e:
            row.update(error=str(e), wall_s=time.perf_counter() - t1, meets_goal=False)
        else:
            row.update(value=res.value, optimum=res.optimum, solver_status=res.solver_status,
                       iterations=res.iterations, grid_points=res.verification["grid_points"],
                       max_relative_gap=res.verification["max_relative_gap"], wall_s=res.wall_s,
                       meets_goal=res.wall_s <= GOAL_S, error="")
        rows.append(row)
    return {"scene": model.scene.name, "quick": quick, "cases": rows}


def write(result: dict, out: Path) -> list[Path]:
    """DIR/bench_design.json and DIR/bench_design.csv (one row a case, COLUMNS)."""
    out.mkdir(parents=True, exist_ok=True)
    js, cs = out / "bench_design.json", out / "bench_design.csv"
    write_text(js, option="«out»", text=json.dumps(result, indent=1) + "\n")
    with open_text(cs, "«out»", newline="") as fh:
        w = csv.DictWriter(fh, COLUMNS, extrasaction="ignore")
        w.writeheader()
        for row in result["cases"]:
            w.writerow({k: row.get(k, "") for k in COLUMNS})
    return [js, cs]


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py): the cases of `run`, written by `write`."""
    result = run(model, quick)
    result["files"] = [str(f) for f in write(result, out)]
    result["headline"] = "; ".join(
        f"{r['case']} {r['wall_s']:.2f} s" + ("" if not r["error"] else " (failed)") for r in result["cases"])
    return result
