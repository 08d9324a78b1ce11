"""scipy's ODE solvers over a part's numpy-facing right-hand side (runtime/integrate/run.py; thesis 3.1),
stepped one accepted step at a time as solve_ivp does, so that a step budget can stop them.
"""
from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.methods import lookup
from levitron.runtime.integrate.budget import budget_message
from levitron.runtime.integrate.trajectory import Result


def numpy_rhs(part, p: np.ndarray, kind: str = "auto") -> tuple[Callable, str]:
    """The right-hand side scipy calls, and which one it is.

    "numpy": a pure-numpy callable exposed by the part (part.numpy_function("rhs"), the
    lambdified expression); "c": part.rhs(x, p) through ctypes per call; "auto": numpy if
    available, else c."""
    if kind in ("auto", "numpy"):
        getter = getattr(part, "numpy_function", None)
        if getter is not None:
            fn = getter("rhs")
            return (lambda t, x: fn(x, p)), "numpy (lambdified expression)"
        if kind == "numpy":
            raise UserError("this model exposes no numpy right-hand side; use scipy_rhs='c'")
    return (lambda t, x: part.rhs(x, p)), "c (generated C through ctypes, one call per stage)"


class _CallBudget(Exception):
    """Raised by the counting right-hand side once the calls exceed the budget."""


def with_quadrature(f: Callable, part, p: np.ndarray, quad: str | None) -> Callable:
    """f extended by the part's scalar function `quad` for a last state W (runtime/integrate/run.py):
    (t, [x, W]) -> [f(t, x), quad(x)]; f itself without one. Unlike C's and CVODES' quadratures, W
    here enters scipy's error norm (atol tol * its size) and so takes part in choosing the steps."""
    if quad is None:
        return f
    name = f"{part.name}_{quad}"
    return lambda t, y: np.append(f(t, y[:-1]), part.model.call(name, y[:-1], p))


def integrate_scipy(part, method, x0, p, t_end, tol, box, n_out, scale, scipy_rhs, max_steps,
                    quad=None):
    """scipy's solvers stepped one accepted step at a time (solve_ivp's own loop, with its dense
    output and box event), so that the run stops after max_steps steps, or once the right-hand
    side was called more than CALLS_PER_STEP * max_steps times (counted in the wrapper: implicit
    methods may call it many times inside one step)."""
    import scipy.integrate
    from scipy.optimize import brentq
    f, kind = numpy_rhs(part, p, scipy_rhs)
    f = with_quadrature(f, part, p, quad)
    calls = [0]
    call_cap = (16 + 2 * x0.size) * max_steps

    def fun(t, x):
        calls[0] += 1
        if calls[0] > call_cap:
            raise _CallBudget
        return f(t, x)

    t_grid = np.linspace(0.0, t_end, n_out + 1)
    ts, xs = [0.0], [x0.copy()]
    i_out = 1
    status, message = "completed", "completed: reached t_end"
    start = time.perf_counter()
    solver = getattr(scipy.integrate, lookup(method).engine)(fun, 0.0, x0, t_end, rtol=tol, atol=tol * scale)
    steps = 0
    t_final, x_final = 0.0, x0.copy()
    while solver.status == "running":
        if steps >= max_steps:
            status, message = "step_budget", budget_message(max_steps)
            break
        try:
            msg = solver.step()
        except _CallBudget:
            status, message = "step_budget", (budget_message(max_steps) +
                                              f" (more than {call_cap} right-hand side calls)")
            break
        if solver.status == "failed":
            status, message = "step_underflow", f"scipy: {msg}"
            break
        steps += 1
        t_old, t_new = solver.t_old, solver.t
        if not np.all(np.isfinite(solver.y)):
            status, message = "nonfinite", "stopped: the solution became non-finite"
            break
        dense = None                        # built only when needed, as solve_ivp does (DOP853's
        t_stop = t_new                      # interpolant costs three more rhs calls)
        if box is not None and box.excess(solver.y) > 0:
            dense = solver.dense_output()
            t_stop = t_old
            if box.excess(dense(t_old)) <= 0:
                t_stop = brentq(lambda s, d=dense: box.excess(d(s)), t_old, t_new,
                                xtol=4 * np.finfo(float).eps * max(abs(t_new), 1e-300))
                if box.excess(dense(t_stop)) <= 0:      # the root's side inside: step just past it
                    t_stop = float(np.nextafter(t_stop, t_new))
            status, message = "left_box", "stopped: the state left the box"
        while i_out <= n_out and t_grid[i_out] <= t_stop:
            dense = dense or solver.dense_output()
            xs.append(np.asarray(dense(t_grid[i_out]), float))
            ts.append(float(t_grid[i_out]))
            i_out += 1
        t_final, x_final = float(t_stop), (solver.y.copy() if t_stop == t_new else
                                           np.asarray(dense(t_stop), float))
        if status == "left_box":
            break
    wall = time.perf_counter() - start
    if ts[-1] != t_final:
        ts.append(t_final)
        xs.append(x_final)
    return Result(t=np.array(ts), X=np.array(xs), status=status, message=message,
                  rhs_evals=int(solver.nfev), wall_s=wall, t_final=t_final, x_final=x_final, method=method,
                  backend="scipy", steps=steps, details={"rhs": kind, "python_calls": calls[0]})
