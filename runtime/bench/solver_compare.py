"""The thesis's solver comparison (section 3.1.3), run in C through runtime/csrc/integrators.c.

A mass point is held on a circle of radius r0 by the centripetal force F = -m v^2 / r (thesis eq.
3.1.8; csrc/circle.c: a = -(|v|^2/|r|^2) r). Starting at (r0, 0) with speed v0 it should return to
its starting point after every turn, T = 2 pi r0 / v0.

- Figure 3.2: the distance from the starting point after each turn, for Euler (eq. 3.1.2) and
  classical RK4 (eqs. 3.1.3-3.1.4) at the same step.
- Figure 3.3: against the time step, the number of steps before the (kinetic) energy |v|^2/2 has
  drifted by 1 % of its initial value (the C integrator stops at that moment: energy_limit).

Run: python -m levitron.runtime.bench.solver_compare [OUT_DIR] [--quick]; writes solver_compare.json and the two
PNGs (matplotlib, Agg).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from levitron.runtime.integrate.c_backend import CSystem, csrc_library, run_c

from levitron.runtime.ui.plotting import save_figure
from levitron.runtime.ui.atomic import write_text

R0, V0 = 1.0, 1.0
PERIOD = 2 * math.pi * R0 / V0


def circle_system(lib=None) -> CSystem:
    return CSystem(lib or csrc_library(), "lev_circle", ["x", "y", "vx", "vy"], [0.0])


def error_per_turn(method: str, steps_per_turn: int, turns: int, system: CSystem | None = None) -> np.ndarray:
    """Distance |r(kT) - r(0)| after turns k = 1..turns (thesis figure 3.2)."""
    system = system or circle_system()
    x0 = np.array([R0, 0.0, 0.0, V0])
    h = PERIOD / steps_per_turn
    r = run_c(system.lib, method, system.c_function("rhs"), x0, system.p, turns * PERIOD, h=h,
              every=steps_per_turn, max_samples=turns + 3)
    if r.status != "completed":
        raise RuntimeError(f"{method}: {r.message}")
    X = r.X[1:turns + 1]
    return np.hypot(X[:, 0] - R0, X[:, 1])


def steps_to_energy_drift(method: str, h: float, limit: float = 0.01, max_steps: int = 10**7,
                          system: CSystem | None = None) -> tuple[int, bool]:
    """(steps, reached): steps taken until |E - E0| > limit |E0| (thesis figure 3.3); reached is
    False if the step budget max_steps ran out first (the count is then a lower bound)."""
    system = system or circle_system()
    x0 = np.array([R0, 0.0, 0.0, V0])
    r = run_c(system.lib, method, system.c_function("rhs"), x0, system.p, (max_steps + 0.5) * h,
              h=h, energy=system.c_function("energy"), energy_limit=limit, max_steps=max_steps)
    if r.status == "energy_limit":
        return r.steps, True
    if r.status in ("completed", "step_budget"):
        return r.steps, False
    raise RuntimeError(f"{method} at h={h}: {r.message}")


def run(out_dir: str | Path = "reports", quick: bool = False) -> dict:
    """Compute both comparisons, write solver_compare.json and the two figures; return the numbers."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    system = circle_system()
    turns = 20 if quick else 100
    steps_per_turn = 100
    per_turn = {m: error_per_turn(m, steps_per_turn, turns, system) for m in ("euler", "rk4")}
    hs = np.geomspace(1e-3, 0.5, 8 if quick else 16) * PERIOD / (2 * math.pi)
    cap = 10**5 if quick else 10**7
    drift = {m: [steps_to_energy_drift(m, float(h), 0.01, cap, system) for h in hs]
             for m in ("euler", "rk4")}
    result = {
        "problem": "mass point on a circle, F = -m v^2/r (thesis eq. 3.1.8), r0 = 1, v0 = 1",
        "quick": quick,
        "figure_3_2": {"steps_per_turn": steps_per_turn, "turns": list(range(1, turns + 1)),
                       "error": {m: per_turn[m].tolist() for m in per_turn}},
        "figure_3_3": {"energy_limit": 0.01, "step": hs.tolist(), "max_steps": cap,
                       "steps": {m: [n for n, _ in drift[m]] for m in drift},
                       "reached": {m: [ok for _, ok in drift[m]] for m in drift}},
    }
    result["files"] = [str(draw_3_2(result, out / "solver_compare_fig3_2.png")),
                       str(draw_3_3(result, out / "solver_compare_fig3_3.png"))]
    write_text(out / "solver_compare.json", option="«out»", text=json.dumps(result, indent=1))
    result["files"].append(str(out / "solver_compare.json"))
    return result


def draw_3_2(result: dict, path: Path) -> Path:
    from matplotlib.figure import Figure
    f = result["figure_3_2"]
    fig = Figure(figsize=(6, 4))       # matplotlib's own style, as drawn before the house's was set
    ax = fig.subplots()
    for m, color in (("euler", "green"), ("rk4", "red")):
        ax.semilogy(f["turns"], f["error"][m], color=color, label=m.upper() if m == "rk4" else "Euler")
    ax.set_xlabel("turns")
    ax.set_ylabel("distance from the starting point")
    ax.set_title(f"thesis fig. 3.2: error per turn, {f['steps_per_turn']} steps/turn")
    ax.legend()
    fig.tight_layout()
    return save_figure(fig, path)


def draw_3_3(result: dict, path: Path) -> Path:
    from matplotlib.figure import Figure
    f = result["figure_3_3"]
    fig = Figure(figsize=(6, 4))       # matplotlib's own style, as drawn before the house's was set
    ax = fig.subplots()
    for m, color in (("euler", "green"), ("rk4", "red")):
        h = np.array(f["step"])
        n = np.array(f["steps"][m], float)
        ok = np.array(f["reached"][m])
        ax.loglog(h[ok], n[ok], "o-", color=color, label="Euler" if m == "euler" else "RK4")
        if (~ok).any():
            ax.loglog(h[~ok], n[~ok], "^", color=color, mfc="none", label=f"{m}: no 1 % drift within the cap")
    ax.set_xlabel("time step h (T / 2 pi)")
    ax.set_ylabel("steps before 1 % energy drift")
    ax.set_title("thesis fig. 3.3")
    ax.legend()
    fig.tight_layout()
    return save_figure(fig, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", nargs="?", default="reports")
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args(argv)
    res = run(a.out, a.quick)
    print(json.dumps({"files": res["files"]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
