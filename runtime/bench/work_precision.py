"""Speed against error (work-precision) for the reduced and the full model (docs/contract.md `bench`).

The run is the scene's own: its top (mass, A, C, moment as the scene gives them), hovering at its
own height z_s (the lowest vertically stable root of thesis 3.3.2-3.3.3, runtime/physics/equilibrium/finder.py),
spinning at the geometric mean of its linear stability interval (thesis 3.3, runtime/physics/stability/analysis.py),
perturbed by one small dimensionless amplitude DELTA: tilted DELTA rad, offset DELTA z_s, lifted
2 DELTA z_s. The reduced model (thesis 3.2.12) runs from the same height (a vertical bounce) at the
same spin (zeta is cyclic there, so the spin does not change the motion). A scene whose full model's
top has no stable interval is refused with the reason; a scene with only the reduced model is
benched there, at the interval's spin if its top has one, else at the rate with g1 = 1 (thesis
3.3.10: sigma^2 = mu Phi_1 / (rho^2 A)).

Time scales come from the model at that point: the fastest angular rate w_fast = max(spin, the
vertical bounce sqrt(mu Phi_3 / m), the fastest transverse mode of the 8-D linearisation after
thesis 3.3.5); T_fast = 2 pi / w_fast. Every fixed step is a fraction of T_fast, and a run lasts
SPIN_PERIODS spin periods (DELTA, SPIN_PERIODS and the operating point: runtime/bench/operating_point.py).

error  = max_k |x_k(T) - x_ref,k(T)| / scale_k, the largest deviation of the final state from the
         reference relative to the component's magnitude (lengths z_s, angles 1 rad, linear momenta
         m sqrt(g z_s), angular momenta C * spin; runtime.simulate.run.state_scales);
x_ref  = the fixed-step 8th-order DOP853 formula (C, compensated summation) at h = T_fast /
         REF_STEPS, cross-checked against the same at twice the step (the difference is
         `reference_check`). The fixed formula's error falls like h^8 until round-off, which the
         compensated summation keeps near 1e-16 of the state: the runs at T_fast / 200 .. 1200
         agree to 1e-16 (thesis_stable) and 3e-14 (ring_magnet). The adaptive DOP853 at
         tol 1e-14, the reference before, is off by 2e-13, which hid every error below it.
         Where the part has Taylor coefficients (the reduced model) the reference is also held
         against a second method, taylor at tol 1e-15 (`reference_vs_taylor`, per component):
         they agree to 2e-15 or better in z and p_z (5 scenes), and differ by up to 6-7 ulp on
         the spin angle zeta (1.7e-13 rad at 201 rad), which advances linearly there and which
         taylor gives as the correctly rounded c1 T: the DOP853 formula rounds its weighted
         slope with that bias at every step (weights up to 5.8 of alternating sign), and every
         dop853 run shares it, so errors below about 2e-13 on zeta are the reference's;
wall_s = the minimum over adaptive repeats (runtime/bench/repeat.py: at least 2 runs, then until
         REPEAT["patience"] runs in a row lower the minimum by less than REPEAT["rtol"], at most
         MAX_REPEATS runs or REPEAT["budget_s"] seconds; one run in --quick and for CasADi's
         collocation) of the integrator call alone (model loading, argument conversion and CasADi
         construction excluded, identically for all backends);
rhs_evals = right-hand-side calls (CasADi's collocation does not expose its count: null).

Backends: "c" (runtime/csrc/integrators.c over the generated C), "casadi" (casadi.integrator over
the generated CasADi function), "scipy" (solve_ivp with the generated C right-hand side called
through ctypes, ~19 us per call; the runtime exposes no lambdified numpy rhs, which would cost about
the same per call), "heyoka" (integrator "taylor": Taylor's method compiled by LLVM at run time,
on the same lowered expressions, runtime/bench/heyoka.py; its compile time is the row's
`compile_s`, not in wall_s; only when heyoka is installed: pip install '.[bench]'; not in --quick).

cheapest_by_bound: for each error bound 1e-5 .. 1e-13 and each backend, the run with the least
wall_s whose error is within the bound (bench_cheapest_<model>.csv).
"""
from __future__ import annotations

import csv
import json
import math
import time
from pathlib import Path

import numpy as np

from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.ui import progress
from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import Units
from levitron.runtime.integrate.run import backend_of, integrate, run_c, time_fn_ns
from levitron.runtime.integrate.methods import lookup
from levitron.runtime.ui.plotting import save_figure
from levitron.runtime.bench.repeat import best_of
from levitron.runtime.ui.atomic import open_text, write_text
from levitron.runtime.bench.per_call import per_call, write_per_call
from levitron.runtime.bench.operating_point import Setup, setup, start

ROW_KEYS = ("model", "backend", "integrator", "tol", "error", "wall_s", "rhs_evals")
EXTRA_KEYS = ("step_or_tol", "status", "steps", "compile_s", "compile_cached")
BOUNDS = tuple(10.0 ** -k for k in range(5, 14))      # the error bounds of cheapest_by_bound
BACKENDS = ("c", "heyoka", "casadi", "scipy")
REF_STEPS = 600         # the reference: h = T_fast / REF_STEPS; its check: twice that step
MAX_REPEATS = 100
REPEAT = {"min_runs": 2, "patience": 2, "rtol": 0.03, "max_runs": MAX_REPEATS, "budget_s": 1.0}
ONCE = {"min_runs": 1, "patience": 0, "max_runs": 1}


def plan(quick: bool, part=None) -> list[tuple[str, str, list[float]]]:
    """(integrator, "tol" or "h", values) from coarse to fine, read from the integrator table
    (runtime/integrate/methods.py: each entry's sweep and quick_sweep); "h" values are fractions of
    T_fast. The quick plan runs C integrators first, as the full one does. taylor only where the
    part has Taylor coefficients (the reduced model, derive/emit/taylor.py)."""
    from levitron.runtime.integrate.methods import TABLE
    has_taylor = part is not None and part.taylor_function() is not None
    rows = [(m.name, "h" if m.fixed_step else "tol", list(m.quick_sweep if quick else m.sweep))
            for m in TABLE if has_taylor or not m.needs_taylor]
    return [r for r in rows if r[2]]


def reference(part, x0, su: Setup, scale):
    """x_ref and reference_check (module docstring)."""
    ref, check = (run_c(part.model.lib, "dop853-fixed", part.c_function("rhs"), x0, su.p, su.t_end,
                        h=su.t_fast / steps) for steps in (REF_STEPS, REF_STEPS // 2))
    for r in (ref, check):
        if r.status != "completed":
            raise UserError(f"bench: the reference run of scene '{part.model.scene.name}' ended "
                            f"'{r.status}': {r.message}")
    return ref.x_final, float(np.max(np.abs(ref.x_final - check.x_final) / scale))


def bench_model(model, part_name: str, quick: bool = False, repeats: int | None = None,
                su: Setup | None = None) -> dict:
    su = su or setup(model)
    part, x0, scale = start(model, part_name, su)
    x_ref, ref_check = reference(part, x0, su, scale)
    vs_taylor = None
    if part.taylor_function() is not None:
        r = integrate(part, x0, su.t_end, method="taylor", tol=1e-15, p=su.p, scale=scale, n_out=1)
        vs_taylor = (np.abs(r.x_final - x_ref) / scale).tolist() if r.status == "completed" else None
    repeat = ONCE if (quick or repeats == 1) else REPEAT
    rows = []
    runs = [(method, kind, v) for method, kind, values in plan(quick, part) for v in values]
    for method, kind, v in progress.track(runs, f"bench {model.scene.name} ({part_name})"):
        value = v * su.t_fast if kind == "h" else v
        kw = {"tol": value} if kind == "tol" else {"h": value, "tol": None}
        kept: list = []

        def once(method=method, kw=kw, kept=kept) -> float:
            r = integrate(part, x0, su.t_end, method=method, p=su.p, scale=scale, n_out=1,
                          time_scale=su.t_fast, **kw)
            if not kept or r.wall_s < kept[0].wall_s:
                kept[:] = [r]
            return r.wall_s

        best_of(once, **(ONCE if method.startswith("casadi-coll") else repeat))
        best = kept[0]
        err = (float(np.max(np.abs(best.x_final - x_ref) / scale))
               if best.status == "completed" else math.inf)
        rows.append({"model": part_name, "backend": backend_of(method), "integrator": method,
                     "tol": value, "error": err, "wall_s": best.wall_s, "rhs_evals": best.rhs_evals,
                     "step_or_tol": kind, "status": best.status})
    heyoka = heyoka_rows(model, part_name, x0, su, scale, x_ref, repeat) if not quick else []
    rows += heyoka or []
    calls = per_call(model, part_name, x0, su, scale, rows, quick)
    return {"rows": rows, "reference_check": ref_check, "reference_vs_taylor": vs_taylor,
            "setup": su.as_dict(), "z_s": su.z_s,
            "x0": x0.tolist(), "states": list(part.states),
            "heyoka": ("not run in the quick mode (it compiles for seconds per tolerance)" if quick
                       else "not installed: pip install '.[bench]'" if heyoka is None
                       else "installed"),
            "cheapest_by_bound": cheapest_by_bound(rows), "per_call": calls}


HEYOKA_TOLS = tuple(10.0 ** (-k / 2) for k in range(8, 31))     # 1e-4 .. 1e-15, half decades


def heyoka_rows(model, part_name: str, x0, su: Setup, scale, x_ref, repeat: dict | int = REPEAT,
                tols=HEYOKA_TOLS) -> list | None:
    """heyoka's Taylor integrator on the same problem (runtime/bench/heyoka.py), repeated as every
    other backend (`repeat`: best_of's options, or 1 for one run); None when heyoka is absent."""
    repeat = ONCE if repeat == 1 else repeat
    from levitron.runtime.bench import heyoka as bench_heyoka
    if not bench_heyoka.available():
        return None
    from levitron.derive.emit.heyoka import lowered_rhs, system
    built: list = []

    def make_sys():             # sympy: seconds; only when the cache lacks a tolerance
        if not built:
            built.append(system(lowered_rhs(model.scene, part_name), scale))
        return built[0]

    rows = []
    for tol in tols:
        key = bench_heyoka.cache_key(**bench_heyoka.expressions_key(model, part_name), part=part_name,
                                     scale=[float(v).hex() for v in scale], tol=float(tol).hex())
        r = bench_heyoka.run(make_sys, x0, su.p, scale, su.t_end, tol, repeat, key=key)
        err = (float(np.max(np.abs(r["x_final"] - x_ref) / scale))
               if r["status"] == "completed" else math.inf)
        rows.append({"model": part_name, "backend": "heyoka", "integrator": "taylor", "tol": tol,
                     "error": err, "wall_s": r["wall_s"], "rhs_evals": None, "step_or_tol": "tol",
                     "status": r["status"], "steps": r["steps"], "compile_s": r["compile_s"],
                     "compile_cached": r["compile_cached"]})
    return rows


def cheapest_by_bound(rows: list[dict]) -> list[dict]:
    """For each error bound and backend, the cheapest run within it (module docstring)."""
    out = []
    for bound in BOUNDS:
        row = {"bound": bound}
        for b in BACKENDS:
            ok = [r for r in rows if r["backend"] == b and r["error"] <= bound]
            best = min(ok, key=lambda r: r["wall_s"]) if ok else None
            row[b] = None if best is None else {k: best[k] for k in ("integrator", "tol", "error", "wall_s")}
        out.append(row)
    return out


def write_cheapest(table: list[dict], path: Path) -> None:
    with open_text(path, "«out»", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["bound"] + [f"{b}_{k}" for b in BACKENDS for k in ("integrator", "wall_s", "error")])
        for row in table:
            cells = [row["bound"]]
            for b in BACKENDS:
                c = row[b]
                cells += ["", "", ""] if c is None else [c["integrator"], c["wall_s"], c["error"]]
            w.writerow(cells)


def cheapest(rows, integrator, bound=1e-8):
    ok = [r for r in rows if r["integrator"] == integrator and r["error"] <= bound]
    return min(ok, key=lambda r: r["wall_s"]) if ok else None


def goals(model, full_rows: list[dict], quick: bool, su: Setup | None = None) -> dict:
    """The figures of the bench's goals (bench_goals.json)."""
    su = su or setup(model)
    p = su.p
    part, x0, _ = start(model, "full", su)
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
    out["full_rhs_ops"] = model.function(f"{part.name}_rhs").ops
    out["full_rhs_goal_met"] = ns <= 150
    out["rhs"] = rhs_costs(model, su, reps)
    # long run: 1e6 steps (quick: 2e4) of gauss4 and RK4 at h = T_fast / 30, energy monitored in C
    n = 20_000 if quick else 1_000_000
    h = su.t_fast / 30
    long = {}
    e_scale = None
    for method in ("gauss4", "rk4"):
        every = max(1, n // 1000)
        r = run_c(model.lib, method, part.c_function("rhs"), x0, p, n * h, h=h,
                  jac=part.c_function("jac") if lookup(method).needs_jacobian else None,
                  energy=part.c_function("energy"), every=every, max_samples=n // every + 3)
        e_scale = max(abs(r.energy0), eqm.params_of(model, p)["C"] * su.spin ** 2 / 2)
        dev = (r.energy - r.energy0) / e_scale
        slope = float(np.polyfit(r.t, dev, 1)[0]) if len(r.t) > 2 else None
        tenths = max_per_tenth(dev)
        long[method] = {"steps": r.steps, "status": r.status, "wall_s": r.wall_s,
                        "rhs_evals": r.rhs_evals, "jac_evals": r.jac_evals,
                        "max_rel_energy_error": r.energy_max_dev / e_scale,
                        "rel_energy_drift_slope_per_s": slope, "max_per_tenth": tenths}
    out["long_run"] = {"h": h, "steps": n, "simulated_s": n * h, "energy_scale": e_scale, **long}
    return out


def max_per_tenth(dev) -> list[float]:
    """The largest |dev| in each tenth of the samples (fewer parts when a run that ended early,
    e.g. a top that left its box, left fewer than ten samples; none for none)."""
    return [float(np.abs(c_).max()) for c_ in np.array_split(np.asarray(dev, float), 10) if c_.size]


def rhs_costs(model, su: Setup, reps: int) -> dict:
    """ns per call (best of 3 loops in C) and operation count of every part's rhs, at the bench's
    initial state."""
    out = {}
    for name in ("reduced", "full"):
        if name in model.parts:
            part, x0, _ = start(model, name, su)
            ns = min(time_fn_ns(model.lib, part.c_function("rhs"), x0, su.p, len(x0), reps)
                     for _ in range(3))
            out[name] = {"ns": ns, "ops": model.function(f"{name}_rhs").ops}
    return out


def draw(rows: list[dict], path: Path, title: str) -> Path:
    from matplotlib.figure import Figure
    fig = Figure(figsize=(7.5, 5.5))     # matplotlib's own style, as drawn before the house's was set
    ax = fig.subplots()
    markers = {"c": "o", "casadi": "s", "scipy": "^", "heyoka": "D"}
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


def bench(model, out: Path, quick: bool) -> dict:
    """The bench protocol (runtime/bench/kinds.py): `run` into `out`."""
    return run(model, out, quick)


def run(model, out_dir: str | Path = "reports", quick: bool = False) -> dict:
    t0 = time.perf_counter()
    su = setup(model)                    # refuses a scene without a stable interval: nothing written
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files, rows, per_model = [], [], {}
    units = Units.of_scene(model.scene)
    for name in ("reduced", "full"):
        if name not in model.parts:
            continue
        res = bench_model(model, name, quick, su=su)
        per_model[name] = {k: v for k, v in res.items() if k != "rows"}
        rows += res["rows"]
        stem = out / f"bench_{name}"
        with open_text(f"{stem}.csv", "«out»", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(ROW_KEYS) + list(EXTRA_KEYS), restval="")
            w.writeheader()
            w.writerows(res["rows"])
        write_text(f"{stem}.json", option="«out»", text=json.dumps({"model": name, "scene": model.scene.name,
                                                     "description": __doc__, **res}, indent=1, default=_json))
        draw(res["rows"], Path(f"{stem}.png"),
             f"{model.scene.name}, {name} model: {units.time(su.t_end)} at {units.rate(su.spin)}")
        write_cheapest(res["cheapest_by_bound"], out / f"bench_cheapest_{name}.csv")
        write_per_call(res["per_call"], out / f"bench_per_call_{name}.csv")
        files += [f"{stem}.csv", f"{stem}.json", f"{stem}.png", str(out / f"bench_cheapest_{name}.csv"),
                  str(out / f"bench_per_call_{name}.csv")]
    g = goals(model, [r for r in rows if r["model"] == "full"], quick, su) if "full" in model.parts else {}
    write_text(out / "bench_goals.json", option="«out»", text=json.dumps(g, indent=1, default=_json))
    files.append(str(out / "bench_goals.json"))
    return {"rows": rows, "goals": g, "models": per_model, "setup": su.as_dict(), "files": files,
            "quick": quick,
            "wall_s": time.perf_counter() - t0}


def _json(o):
    if isinstance(o, float) and not math.isfinite(o):
        return None
    if hasattr(o, "tolist"):
        return o.tolist()
    raise TypeError(type(o))
