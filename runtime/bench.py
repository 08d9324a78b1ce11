"""Speed against error (work-precision) for the reduced and the full model (issue 3, DESIGN.md).

The run: the default scene's generated model; the top trimmed into the stable band of the plate
(m = 51.4 g and A, C eight times the thesis's, so that 200 rad/s stabilises it: see
runtime.linear), spinning at 200 rad/s, tilted 0.01 rad, offset 1 mm, lifted 2 % above z_s; 1 s
of levitation. The reduced model (thesis 3.2.12) runs from the same height (a vertical bounce).

error  = max_k |x_k(T) - x_ref,k(T)| / scale_k, the largest deviation of the final state from the
         reference relative to the component's magnitude (lengths z_s, angles 1 rad, linear momenta
         m sqrt(g z_s), angular momenta C * spin; runtime.simulate.state_scales);
x_ref  = C DOP853 at rtol = 1e-14 (atol = 1e-14 * scale), cross-checked against the fixed-step
         8th-order DOP853 formula at h = 1e-5 (the difference is reported as `reference_check`);
wall_s = the minimum over repeats of the integrator call alone (model loading and CasADi
         construction excluded, identically for all backends);
rhs_evals = right-hand-side calls (CasADi's collocation does not expose its count: null).

Backends: "c" (runtime/csrc/integrators.c over the generated C), "casadi" (casadi.integrator over
the generated CasADi function), "scipy" (solve_ivp with the generated C right-hand side called
through ctypes, ~19 us per call; the runtime exposes no lambdified numpy rhs, which would cost about
the same per call).
"""
from __future__ import annotations

import csv
import json
import math
import time
from pathlib import Path

import numpy as np

from runtime.integrate import backend_of, integrate, run_c, time_fn_ns
from runtime.simulate import hover_height, initial_state, state_scales
from runtime.plotting import pyplot, save_figure

ROW_KEYS = ("model", "backend", "integrator", "tol", "error", "wall_s", "rhs_evals")
SPIN, TILT, OFFSET, LIFT, T_END = 200.0, 0.01, 1e-3, 0.02, 1.0


def trimmed_parameters(model) -> np.ndarray:
    names = list(model.manifest["parameters"])
    p = model.p.copy()
    p[names.index("m")] = 0.0514
    p[names.index("A")] *= 8
    p[names.index("C")] *= 8
    return p


def start(model, part_name: str, p: np.ndarray):
    part = model.part(part_name)
    z_s = hover_height(model, p)
    pv = dict(zip(model.manifest["parameters"], p))
    if part_name == "full":
        x0 = initial_state(part, z_s, SPIN, TILT, OFFSET, p)
    else:
        x0 = initial_state(part, z_s, SPIN, 0.0, 0.0, p)
    x0[part.states.index("z")] *= 1 + LIFT
    return part, x0, state_scales(part, z_s, SPIN, pv), z_s


def plan(quick: bool) -> list[tuple[str, str, list[float]]]:
    """(integrator, "tol" or "h", values) from coarse to fine."""
    if quick:
        return [("rk4", "h", [1e-3, 1e-4]), ("dop853", "tol", [1e-6, 1e-10]),
                ("gauss4", "h", [1e-3]), ("euler", "h", [1e-4]),
                ("cvodes", "tol", [1e-6]), ("casadi-rk", "h", [1e-3]),
                ("scipy-dop853", "tol", [1e-6])]
    tols = [1e-4, 1e-6, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
    return [("euler", "h", [1e-3, 1e-4, 1e-5, 1e-6]),
            ("rk4", "h", [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5]),
            ("dop853", "tol", tols + [1e-13]),
            ("gauss4", "h", [1e-2, 3e-3, 1e-3, 3e-4, 1e-4]),
            ("midpoint", "h", [1e-3, 1e-4, 1e-5]),
            ("cvodes", "tol", tols),
            ("casadi-rk", "h", [1e-3, 3e-4, 1e-4]),
            ("casadi-collocation", "h", [1e-2, 3e-3, 1e-3]),
            ("scipy-dop853", "tol", tols)]


def reference(part, x0, p, scale):
    ref = integrate(part, x0, T_END, method="dop853", tol=1e-14, p=p, scale=scale, n_out=1)
    check = run_c(part.model.lib, "dop853-fixed", part.c_function("rhs"), x0, p, T_END, h=1e-4)
    return ref.x_final, float(np.max(np.abs(ref.x_final - check.x_final) / scale))


def bench_model(model, part_name: str, quick: bool = False, repeats: int | None = None) -> dict:
    p = trimmed_parameters(model)
    part, x0, scale, z_s = start(model, part_name, p)
    x_ref, ref_check = reference(part, x0, p, scale)
    repeats = repeats or (1 if quick else 3)
    rows = []
    for method, kind, values in plan(quick):
        for v in values:
            kw = {"tol": v} if kind == "tol" else {"h": v, "tol": None}
            best = None
            for _ in range(repeats if not method.startswith("casadi-coll") else 1):
                r = integrate(part, x0, T_END, method=method, p=p, scale=scale, n_out=1, **kw)
                if best is None or r.wall_s < best.wall_s:
                    best = r
            err = (float(np.max(np.abs(best.x_final - x_ref) / scale))
                   if best.status == "completed" else math.inf)
            rows.append({"model": part_name, "backend": backend_of(method), "integrator": method,
                         "tol": v, "error": err, "wall_s": best.wall_s, "rhs_evals": best.rhs_evals,
                         "step_or_tol": kind, "status": best.status})
    return {"rows": rows, "reference_check": ref_check, "z_s": z_s, "x0": x0.tolist(),
            "states": list(part.states)}


def cheapest(rows, integrator, bound=1e-8):
    ok = [r for r in rows if r["integrator"] == integrator and r["error"] <= bound]
    return min(ok, key=lambda r: r["wall_s"]) if ok else None


def goals(model, full_rows: list[dict], quick: bool) -> dict:
    """The figures of issue 3's goals."""
    p = trimmed_parameters(model)
    part, x0, scale, z_s = start(model, "full", p)
    out = {}
    c = cheapest(full_rows, "dop853")
    s = cheapest(full_rows, "scipy-dop853")
    v = cheapest(full_rows, "cvodes")
    out["error_bound"] = 1e-8
    out["c_dop853"] = c
    out["scipy_dop853"] = s
    out["casadi_cvodes"] = v
    out["speedup_vs_scipy"] = s["wall_s"] / c["wall_s"] if c and s else None
    out["speedup_vs_cvodes"] = v["wall_s"] / c["wall_s"] if c and v else None
    out["speedup_goals_met"] = (None if out["speedup_vs_scipy"] is None or out["speedup_vs_cvodes"] is None
                                else out["speedup_vs_scipy"] >= 100 and out["speedup_vs_cvodes"] >= 2)
    reps = 200_000 if quick else 5_000_000
    ns = min(time_fn_ns(model.lib, part.c_function("rhs"), x0, p, len(x0), reps) for _ in range(3))
    out["full_rhs_ns"] = ns
    out["full_rhs_ops"] = model.manifest["functions"][f"{part.name}_rhs"]["ops"]
    out["full_rhs_goal_met"] = ns <= 150
    # long run: 1e6 steps (quick: 2e4) of gauss4 and RK4 at h = 1e-3, energy monitored in C
    n = 20_000 if quick else 1_000_000
    h = 1e-3
    long = {}
    e_scale = None
    for method in ("gauss4", "rk4"):
        every = max(1, n // 1000)
        r = run_c(model.lib, method, part.c_function("rhs"), x0, p, n * h, h=h,
                  jac=part.c_function("jac") if method == "gauss4" else None,
                  energy=part.c_function("energy"), every=every, max_samples=n // every + 3)
        e_scale = max(abs(r.energy0), float(p[list(model.manifest["parameters"]).index("C")]) * SPIN ** 2 / 2)
        dev = (r.energy - r.energy0) / e_scale
        slope = float(np.polyfit(r.t, dev, 1)[0]) if len(r.t) > 2 else None
        tenths = [float(np.abs(c_).max()) for c_ in np.array_split(np.abs(dev), 10)]
        long[method] = {"steps": r.steps, "status": r.status, "wall_s": r.wall_s,
                        "rhs_evals": r.rhs_evals, "jac_evals": r.jac_evals,
                        "max_rel_energy_error": r.energy_max_dev / e_scale,
                        "rel_energy_drift_slope_per_s": slope, "max_per_tenth": tenths}
    out["long_run"] = {"h": h, "steps": n, "simulated_s": n * h, "energy_scale": e_scale, **long}
    return out


def draw(rows: list[dict], path: Path, title: str) -> Path:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    markers = {"c": "o", "casadi": "s", "scipy": "^"}
    for integ in dict.fromkeys(r["integrator"] for r in rows):
        rs = [r for r in rows if r["integrator"] == integ and math.isfinite(r["error"]) and r["error"] > 0]
        if not rs:
            continue
        ax.loglog([r["wall_s"] for r in rs], [r["error"] for r in rs],
                  marker=markers[rs[0]["backend"]], label=f"{rs[0]['backend']}: {integ}")
    ax.set_xlabel("wall time (s, min of repeats)")
    ax.set_ylabel("error of the final state (relative to component scales)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


def run(model, out_dir: str | Path = "reports", quick: bool = False) -> dict:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    files, rows, per_model = [], [], {}
    for name in ("reduced", "full"):
        if name not in model.parts:
            continue
        res = bench_model(model, name, quick)
        per_model[name] = {k: v for k, v in res.items() if k != "rows"}
        rows += res["rows"]
        stem = out / f"bench_{name}"
        with open(f"{stem}.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(ROW_KEYS) + ["step_or_tol", "status"])
            w.writeheader()
            w.writerows(res["rows"])
        Path(f"{stem}.json").write_text(json.dumps({"model": name, "scene": model.scene.name,
                                                     "setup": __doc__, **res}, indent=1, default=_json))
        draw(res["rows"], Path(f"{stem}.png"),
             f"{model.scene.name}, {name} model: {T_END:g} s at {SPIN:g} rad/s")
        files += [f"{stem}.csv", f"{stem}.json", f"{stem}.png"]
    g = goals(model, [r for r in rows if r["model"] == "full"], quick) if "full" in model.parts else {}
    (out / "bench_goals.json").write_text(json.dumps(g, indent=1, default=_json))
    files.append(str(out / "bench_goals.json"))
    return {"rows": rows, "goals": g, "models": per_model, "files": files, "quick": quick,
            "wall_s": time.perf_counter() - t0}


def _json(o):
    if isinstance(o, float) and not math.isfinite(o):
        return None
    if hasattr(o, "tolist"):
        return o.tolist()
    raise TypeError(type(o))
