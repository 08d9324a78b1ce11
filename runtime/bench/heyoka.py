"""heyoka (Taylor's method, compiled by LLVM at run time) as a bench backend: BENCHMARK-ONLY.

heyoka gets the model's own expressions: derive/emit/heyoka.py (the heyoka backend of the emitter)
turns the lowered right-hand side of derive/emit/lower.py, the graph the generated C computes
(Hamilton's equations, thesis 2.3.9-2.3.16 / 3.2.12), into heyoka expressions through
`heyoka.from_sympy`, so both integrate the same equations. That needs sympy, so this path is the
one place where a runtime process loads sympy: runtime/bench/work_precision.py imports it only when heyoka is
installed (the optional extra: pip install '.[bench]'), and nothing else in the runtime does.

Same problem as every other backend: the same parameter vector, initial state and error measure.
heyoka's single tolerance is relative-or-absolute per component, so it integrates the state in the
bench's units, X_k = x_k / scale_k (scale: runtime.simulate.run.state_scales), which is what our
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


def run(sys_, x0: np.ndarray, p: np.ndarray, scale: np.ndarray, t_end: float, tol: float,
        repeats: int, more=lambda k, spent: False) -> dict:
    """One tolerance: compile (timed apart), then the best of `repeats` runs to t_end (and more
    while more(k, spent): runtime/bench/work_precision.py's rule, the same for every backend)."""
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
