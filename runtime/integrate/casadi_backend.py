"""CasADi's integrators over a part's CasADi right-hand side (runtime/integrate/run.py; thesis 3.1):
``cvodes`` (SUNDIALS' adaptive Adams-Moulton here), ``rk`` (fixed-step RK4, thesis 3.1.3-3.1.4)
and ``collocation`` (fixed-step Legendre collocation). CasADi has no events, so a run is checked
on its output grid and truncated at the first sample outside the box.
"""
from __future__ import annotations

import time
from typing import Any

import numpy as np

from levitron.runtime.integrate.methods import lookup
from levitron.runtime.integrate.budget import budget_message, fixed_steps
from levitron.runtime.integrate.trajectory import Box, Result


def _truncate_at_box(t, X, box: Box | None):
    """First sample outside the box or non-finite: (k, status) or (None, None)."""
    for k in range(len(t)):
        if not np.all(np.isfinite(X[k])):
            return k, "nonfinite"
        if box is not None and box.excess(X[k]) > 0:
            return k, "left_box"
    return None, None


CVODES_START = 100   # steps allowed on top of the even share in each output interval (the start)


def integrate_casadi(part, method, x0, p, t_end, tol, h, box, n_out, scale, max_steps, quad=None):
    """CasADi's integrators. The budget: CVODES counts its steps per call, one call per output
    time, so cvodes gets max_num_steps = max_steps / n_out + CVODES_START per output interval (an
    interval takes no step where the steps are longer than it: CVODES interpolates; the extra
    steps serve the start from a small first step), at most max_steps + CVODES_START n_out in all;
    the fixed-step plugins run the budgeted steps only, to t = max_steps h. quad: the part's
    scalar function whose integral is the last state of x0 (runtime/integrate/run.py), given to
    the integrator as CasADi's quadrature ("quad"), which, as in C, does not steer the steps."""
    import casadi as ca
    plugin = lookup(method).engine
    F = part.casadi("rhs")
    n = x0.size
    nx = n - (quad is not None)                 # the states; W, the last of x0, is the quadrature
    u = ca.MX.sym("u", nx)
    pp = ca.MX.sym("p", F.size1_in(1), F.size2_in(1))
    S = ca.DM(scale[:nx])
    dae = {"x": u, "p": pp, "ode": F(S * u, pp) / S}   # scaled states: one scalar atol serves all
    if quad is not None:
        dae["quad"] = part.casadi(quad)(S * u, pp)
    opts: dict[str, Any] = {}
    n_steps = 0
    status, message = "completed", "completed: reached t_end"
    t_run = t_end
    if plugin == "cvodes":
        per_call = -(-max_steps // n_out) + CVODES_START
        opts = {"abstol": tol, "reltol": tol, "max_num_steps": per_call,
                "linear_multistep_method": "adams", "nonlinear_solver_iteration": "functional"}
    else:
        # casadi >= 3.6: the finite elements are counted over the whole horizon (at least one per
        # output interval), so N = t_end / h steps of size h
        n_steps = max(n_out, fixed_steps(t_end, h))
        if n_steps > max_steps:
            t_run = t_end * max_steps / n_steps
            n_steps, n_out = max_steps, min(n_out, max_steps)
            status, message = "step_budget", budget_message(max_steps)
        opts = {"number_of_finite_elements": n_steps}
        if plugin == "collocation":
            opts.update({"interpolation_order": 3, "collocation_scheme": "legendre"})
    t_grid = np.linspace(0.0, t_run, n_out + 1)
    integ = ca.integrator("lev_" + plugin, plugin, dae, 0.0, list(t_grid[1:]), opts)
    start = time.perf_counter()
    try:
        out = integ(x0=ca.DM(x0[:nx] / scale[:nx]), p=ca.DM(p))
        U = np.asarray(out["xf"].full()).T * scale[None, :nx]
        if quad is not None:                    # W(t) = W(0) + the quadrature over [0, t]
            U = np.hstack([U, x0[nx] + np.asarray(out["qf"].full()).T])
    except RuntimeError as err:
        U = np.full((n_out, n), np.nan)
        status, message = "solver_error", f"casadi {plugin}: {str(err).splitlines()[0]}"
        if "TOO_MUCH_WORK" in str(err):
            status, message = "step_budget", (f"stopped: the step budget of {max_steps} steps ran out "
                                              f"before t_end (cvodes: more than {per_call} steps "
                                              "in one output interval)")
    wall = time.perf_counter() - start
    X = np.vstack([x0[None, :], U])
    t = t_grid
    stats = integ.stats()
    if plugin == "cvodes":
        rhs_evals = int(stats.get("nfevals", 0)) or None
        steps = int(stats.get("nsteps", 0))
    elif plugin == "rk":
        steps = n_steps
        rhs_evals = 4 * steps                   # casadi's "rk" is the classical RK4
    else:
        steps = n_steps
        rhs_evals = None                        # Newton iterations of casadi's rootfinder: not exposed
    k, why = _truncate_at_box(t, X, box)
    if k is not None:
        keep = max(k, 1) if why == "nonfinite" else k + 1
        t, X = t[:keep], X[:keep]
        if status == "completed" or why == "left_box":
            status = why
            message = ("stopped: the state left the box (checked on the output grid)" if why == "left_box"
                       else "stopped: the solution became non-finite")
    return Result(t=t, X=X, status=status, message=message, rhs_evals=rhs_evals, wall_s=wall,
                  t_final=float(t[-1]), x_final=X[-1].copy(), method=method, backend="casadi",
                  steps=steps, details={"casadi_stats": {k2: v for k2, v in stats.items()
                                                         if isinstance(v, (int, float))}})
