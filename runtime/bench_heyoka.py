"""heyoka (Taylor's method, compiled by LLVM at run time) as a bench backend: BENCHMARK-ONLY.

This is the one runtime module that imports sympy and derive: it hands heyoka the model's own
expressions (the lowered right-hand side of derive/emit/lower.py, the graph the generated C
computes: Hamilton's equations, thesis 2.3.9-2.3.16 / 3.2.12) through `heyoka.from_sympy`, so both
integrate the same equations. runtime/bench.py imports it only when heyoka is installed (the
optional extra: pip install '.[bench]'); nothing else in the runtime imports it.

Same problem as every other backend: the same parameter vector, initial state and error measure.
heyoka's single tolerance is relative-or-absolute per component, so it integrates the state in the
bench's units, X_k = x_k / scale_k (scale: runtime.simulate.state_scales), which is what our
rtol = tol, atol_k = tol * scale_k mean; the final state is scaled back. Its compilation (one per
tolerance: the Taylor order follows from it) is timed apart (`compile_s`) and not in `wall_s`.
"""
from __future__ import annotations

import importlib.util
import time

import numpy as np


def available() -> bool:
    """Whether heyoka is installed (the bench says so when it is not)."""
    return importlib.util.find_spec("heyoka") is not None


def lowered_rhs(scene, part_name: str):
    """The lowered `<part>_rhs` of the scene (derive's spec -> derive/emit/lower.py)."""
    from derive.build import field_order
    from derive.emit.lower import lower
    from derive.geometry import build_plate
    from derive.spec import build_spec
    order, _ = field_order(scene)
    spec = build_spec(scene.name, build_plate(scene.data["plate"]), order, scene.coordinates,
                      scene.needs)
    fn = next(f for f in spec.functions if f.name == f"{part_name}_rhs")
    return lower(fn, spec)


def system(low, scale: np.ndarray):
    """heyoka's [(X_k, dX_k/dt)] in scaled states X_k = x_k / scale_k, parameters as par[i]."""
    import heyoka as hy
    import sympy as sp
    n = low.n_in
    X = hy.make_vars(*[f"X{i}" for i in range(n)])
    env = {v: X[i] * float(scale[i]) for i, v in low.inputs}
    env.update({v: hy.par[i] for i, v in low.params})
    for s, fn, a in low.trig:
        env[s] = (hy.sin if fn == "sin" else hy.cos)(env[a])
    for s, e in low.body:
        env[s] = hy.from_sympy(e, env)
    rhs = [hy.from_sympy(sp.sympify(e), env) / float(scale[i]) if e != 0 else hy.expression(0.0)
           for i, e in enumerate(low.outputs)]
    return list(zip(X, rhs))


def run(sys_, x0: np.ndarray, p: np.ndarray, scale: np.ndarray, t_end: float, tol: float,
        repeats: int, more=lambda k, spent: False) -> dict:
    """One tolerance: compile (timed apart), then the best of `repeats` runs to t_end (and more
    while more(k, spent): runtime/bench.py's rule, the same for every backend)."""
    import heyoka as hy
    X0 = np.asarray(x0, float) / scale
    t0 = time.perf_counter()
    ta = hy.taylor_adaptive(sys_, X0.copy(), tol=tol, pars=list(map(float, p)))
    compile_s = time.perf_counter() - t0
    best, steps, outcome, k, spent = np.inf, None, None, 0, 0.0
    while k < repeats or more(k, spent):
        ta.state[:] = X0
        ta.time = 0.0
        t0 = time.perf_counter()
        res = ta.propagate_until(float(t_end))
        wall = time.perf_counter() - t0
        k, spent = k + 1, spent + wall
        if wall < best:
            best, steps, outcome = wall, int(res[3]), res[0]
    ok = outcome == hy.taylor_outcome.time_limit
    return {"x_final": ta.state * scale, "wall_s": best, "steps": steps, "compile_s": compile_s,
            "order": int(ta.order), "status": "completed" if ok else str(outcome)}
