"""Integrate a model part: C integrators, CasADi integrators and scipy's solve_ivp (thesis 3.1).

The C integrators (runtime/csrc/integrators.c) run the whole trajectory inside C over the
generated right-hand side, with no Python call per step:

- ``euler``        explicit Euler, fixed step h                        (thesis eq. 3.1.2)
- ``rk4``          classical Runge-Kutta 4, fixed step h               (thesis eqs. 3.1.3-3.1.4)
- ``dop853``       Dormand-Prince 8(5,3), adaptive (rtol = tol, atol = tol * scale), dense output,
                   box event
- ``gauss4``       2-stage Gauss-Legendre, order 4, symplectic, fixed step h, stage equations solved
                   to round-off by simplified Newton with the generated Jacobian
- ``midpoint``     implicit midpoint (1-stage Gauss), order 2, symplectic, fixed step h
- ``dop853-fixed`` the 8th-order DOP853 formula at a fixed step (used by the order tests)

CasADi (through ``part.casadi("rhs")``): ``cvodes`` (adaptive BDF/Adams of SUNDIALS, here
Adams-Moulton for the non-stiff levitron), ``casadi-rk`` (CasADi's fixed-step RK4) and
``casadi-collocation`` (CasADi's fixed-step Legendre collocation).
scipy: ``scipy-dop853``, ``scipy-rk45``, ``scipy-radau``, ``scipy-bdf``, ``scipy-lsoda``, scipy's
OdeSolver classes stepped as ``solve_ivp`` does, with the part's numpy-facing right-hand side (one
Python call per stage). runtime/integrators_table.py is the one list of these names and their facts.

Every run has a step budget (runtime/step_budget.py) and stops with status "step_budget" once it is
used up: in C a counter compare per step, in CasADi CVODES' max_num_steps, in scipy a count of steps
and of right-hand side calls.

Tolerances are made dimension-aware by a per-component ``scale`` (state magnitudes): every
adaptive backend controls |local error_k| <= tol * (scale_k + |x_k|). The box (``Box``) stops a
C or scipy run at the first exit (dense-output bisection in C, event root in scipy); CasADi has no
events, so a CasADi run is checked on its output grid and truncated at the first sample outside.
"""
from __future__ import annotations

import ctypes
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from runtime.cbuild import DEFAULT_FLAGS, compile_shared
from runtime.errors import UserError
from runtime.integrators_table import lookup
from runtime.step_budget import (
    MAX_STEPS_CAP,
    budget_message,
    check_options,
    default_budget,
    fixed_steps,
)

STATUS = {0: "completed", 1: "left_box", 2: "nonfinite", 3: "step_underflow", 4: "step_budget",
          5: "no_convergence", 6: "bad_input", 7: "energy_limit"}

CSRC = Path(__file__).resolve().parent / "csrc"


def backend_of(method: str) -> str:
    """The backend name of DESIGN.md's bench rows: "c", "casadi" or "scipy"."""
    return lookup(method).backend


@dataclass(frozen=True)
class Box:
    """The region the state must stay in: z_lo <= x[iz] <= z_hi and hypot(x[ix], x[iy]) <= r_max.

    Indices of absent coordinates are -1 (the reduced model has no x, y)."""
    iz: int
    z_lo: float
    z_hi: float
    ix: int = -1
    iy: int = -1
    r_max: float = math.inf

    def excess(self, x: np.ndarray) -> float:
        """> 0 iff x is outside (the largest violated margin); the same test as the C code."""
        g = -math.inf
        if self.iz >= 0:
            g = max(g, x[self.iz] - self.z_hi, self.z_lo - x[self.iz])
        if math.isfinite(self.r_max) and (self.ix >= 0 or self.iy >= 0):
            r = math.hypot(x[self.ix] if self.ix >= 0 else 0.0, x[self.iy] if self.iy >= 0 else 0.0)
            g = max(g, r - self.r_max)
        return g


@dataclass
class Result:
    """One trajectory. X[i] is the state at t[i]; x_final at t_final is the last (finite) state."""
    t: np.ndarray
    X: np.ndarray
    status: str
    message: str
    rhs_evals: int | None
    wall_s: float
    t_final: float
    x_final: np.ndarray
    method: str = ""
    backend: str = ""
    steps: int = 0
    rejected: int = 0
    jac_evals: int = 0
    iterations: int = 0
    energy: np.ndarray | None = None
    energy0: float | None = None
    energy_max_dev: float | None = None
    details: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return self.status == "completed"


# ---------------------------------------------------------------- ctypes layer

class _System(ctypes.Structure):
    _fields_ = [("n", ctypes.c_int), ("rhs", ctypes.c_void_p), ("jac", ctypes.c_void_p),
                ("energy", ctypes.c_void_p), ("p", ctypes.POINTER(ctypes.c_double))]


class _Options(ctypes.Structure):
    _fields_ = [("t0", ctypes.c_double), ("t_end", ctypes.c_double), ("h", ctypes.c_double),
                ("rtol", ctypes.c_double), ("atol", ctypes.c_double),
                ("atol_v", ctypes.POINTER(ctypes.c_double)), ("h_max", ctypes.c_double),
                ("max_steps", ctypes.c_long), ("box_on", ctypes.c_int), ("ix", ctypes.c_int),
                ("iy", ctypes.c_int), ("iz", ctypes.c_int), ("z_lo", ctypes.c_double),
                ("z_hi", ctypes.c_double), ("r_max", ctypes.c_double),
                ("t_out", ctypes.POINTER(ctypes.c_double)), ("n_out", ctypes.c_long),
                ("every", ctypes.c_long), ("max_samples", ctypes.c_long), ("max_iter", ctypes.c_int),
                ("energy_limit", ctypes.c_double)]


class _Stats(ctypes.Structure):
    _fields_ = [("status", ctypes.c_int), ("steps", ctypes.c_long), ("rejected", ctypes.c_long),
                ("rhs_evals", ctypes.c_long), ("jac_evals", ctypes.c_long),
                ("energy_evals", ctypes.c_long), ("iterations", ctypes.c_long),
                ("n_samples", ctypes.c_long), ("dropped", ctypes.c_long),
                ("t_final", ctypes.c_double), ("h_last", ctypes.c_double),
                ("energy0", ctypes.c_double), ("energy_max_dev", ctypes.c_double)]


_DP = ctypes.POINTER(ctypes.c_double)


_STRUCTS = (("lev_sizeof_system", _System), ("lev_sizeof_options", _Options),
            ("lev_sizeof_stats", _Stats))


def _bind(lib: ctypes.CDLL) -> ctypes.CDLL:
    """Declare the signatures of the integrator entry points (idempotent) and check that the
    ctypes mirrors of the C structs have the sizes the library reports."""
    f = lib.lev_integrate
    if f.argtypes is None:
        for fn_name, struct in _STRUCTS:
            fn = getattr(lib, fn_name)
            fn.argtypes, fn.restype = [], ctypes.c_size_t
            if fn() != ctypes.sizeof(struct):
                raise RuntimeError(f"runtime/integrate.py's {struct.__name__} has "
                                   f"{ctypes.sizeof(struct)} bytes, the C library's {fn()}: "
                                   "update the ctypes mirror of runtime/csrc/integrators.h")
        lib.lev_method_id.argtypes, lib.lev_method_id.restype = [ctypes.c_char_p], ctypes.c_int
        lib.lev_method_name.argtypes, lib.lev_method_name.restype = [ctypes.c_int], ctypes.c_char_p
        lib.lev_method_fixed_step.argtypes = [ctypes.c_int]
        lib.lev_method_fixed_step.restype = ctypes.c_int
        f.argtypes = [ctypes.c_int, ctypes.POINTER(_System), ctypes.POINTER(_Options), _DP,
                      ctypes.c_void_p, _DP, _DP, _DP, ctypes.POINTER(_Stats)]
        f.restype = ctypes.c_int
        lib.lev_work_bytes.argtypes = [ctypes.c_int, ctypes.c_int]
        lib.lev_work_bytes.restype = ctypes.c_size_t
        lib.lev_status_message.argtypes = [ctypes.c_int]
        lib.lev_status_message.restype = ctypes.c_char_p
        lib.lev_time_fn.argtypes = [ctypes.c_void_p, _DP, _DP, ctypes.c_int, ctypes.c_long]
        lib.lev_time_fn.restype = ctypes.c_double
    return lib


def fn_address(fn: Any) -> int | None:
    """The address of a C function given as a ctypes function pointer, an int, or None."""
    if fn is None:
        return None
    if isinstance(fn, int):
        return fn
    return ctypes.cast(fn, ctypes.c_void_p).value


def csrc_library() -> ctypes.CDLL:
    """The hand-written C of runtime/csrc alone (integrators + the test systems of circle.c)."""
    flags = DEFAULT_FLAGS + ("-Werror",)
    return _bind(ctypes.CDLL(str(compile_shared(sorted(CSRC.glob("*.c")), flags=flags))))


def _f64(a) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64))


def _ptr(a: np.ndarray | None):
    return None if a is None else a.ctypes.data_as(_DP)


def time_fn_ns(lib: ctypes.CDLL, fn: Any, x: np.ndarray, p: np.ndarray, n_out: int,
               reps: int = 1_000_000) -> float:
    """Nanoseconds per call of a generated function, timed by a loop in C (lev_time_fn)."""
    _bind(lib)
    x, p = _f64(x), _f64(p)
    return float(lib.lev_time_fn(fn_address(fn), _ptr(x), _ptr(p), int(n_out), int(reps)))


def run_c(lib: ctypes.CDLL, method: str, rhs: Any, x0, p, t_end: float, *, t0: float = 0.0,
          h: float = 0.0, rtol: float = 0.0, atol: float | Sequence[float] = 0.0,
          jac: Any = None, energy: Any = None, box: Box | None = None,
          t_out: Sequence[float] | None = None, every: int = 0, max_samples: int | None = None,
          max_steps: int | None = None, h_max: float = 0.0, max_iter: int = 0,
          energy_limit: float = 0.0) -> Result:
    """Run one C integrator (no validation beyond the C's own; see ``integrate``).

    Samples: at the times ``t_out`` (DOP853 dense output), else every ``every``-th step plus the
    first and the last state. Energy, when given, is monitored after every step in C; with
    ``energy_limit`` > 0 the run stops once |H - H0| > energy_limit |H0| (status "energy_limit").
    max_steps: the step budget (attempted steps; status "step_budget"); None: the number of fixed
    steps, or runtime.step_budget.MAX_STEPS_CAP for DOP853."""
    _bind(lib)
    code = lookup(method).c_id
    if code is None:
        raise UserError(f"integrator {method!r} is not a C integrator")
    if max_steps is None:
        max_steps = (default_budget(method, t_end, h) if lookup(method).fixed_step and h > 0
                     else MAX_STEPS_CAP)
    x = _f64(x0).copy()
    n = x.size
    p = _f64(p if p is not None else [0.0])
    tout = None if t_out is None else _f64(t_out)
    if max_samples is None:
        max_samples = (tout.size + 2) if tout is not None else 2
    out_t = np.zeros(max_samples)
    out_x = np.zeros((max_samples, n))
    out_e = np.zeros(max_samples) if energy is not None else None
    atol_v = None
    if np.ndim(atol) > 0:
        atol_v = _f64(atol)
        atol = 0.0
    work = np.zeros(int(lib.lev_work_bytes(code, n)) // 8 + 2)
    sysd = _System(n, fn_address(rhs), fn_address(jac), fn_address(energy), _ptr(p))
    b = box or Box(-1, -math.inf, math.inf)
    opt = _Options(t0, t0 + t_end, h, rtol, float(atol), _ptr(atol_v), h_max, max_steps,
                   1 if box is not None else 0, b.ix, b.iy, b.iz, b.z_lo, b.z_hi, b.r_max,
                   _ptr(tout), 0 if tout is None else tout.size, every, max_samples, max_iter,
                   energy_limit)
    st = _Stats()
    start = time.perf_counter()
    status = lib.lev_integrate(code, ctypes.byref(sysd), ctypes.byref(opt), _ptr(x),
                               work.ctypes.data_as(ctypes.c_void_p), _ptr(out_t), _ptr(out_x),
                               _ptr(out_e), ctypes.byref(st))
    wall = time.perf_counter() - start
    k = st.n_samples
    name = STATUS.get(status, str(status))
    message = lib.lev_status_message(status).decode()
    if name == "step_budget":
        message = budget_message(max_steps, float(st.t_final))
    return Result(t=out_t[:k].copy(), X=out_x[:k].copy(), status=name, message=message, rhs_evals=int(st.rhs_evals),
                  wall_s=wall, t_final=float(st.t_final), x_final=x, method=method, backend="c",
                  steps=int(st.steps), rejected=int(st.rejected), jac_evals=int(st.jac_evals),
                  iterations=int(st.iterations),
                  energy=None if out_e is None else out_e[:k].copy(),
                  energy0=float(st.energy0) if energy is not None else None,
                  energy_max_dev=float(st.energy_max_dev) if energy is not None else None,
                  details={"h_last": float(st.h_last), "dropped_samples": int(st.dropped)})


# ---------------------------------------------------------------- the part-level entry point

def _lib_of(part) -> ctypes.CDLL:
    lib = getattr(part, "lib", None)
    if lib is None and getattr(part, "model", None) is not None:
        lib = part.model.lib
    if lib is None:
        raise TypeError("the part exposes no compiled library (part.lib or part.model.lib)")
    return _bind(lib)


def _has_function(part, name: str) -> bool:
    try:
        return part.c_function(name) is not None
    except (AttributeError, KeyError, LookupError):
        return False


def default_scale(x0: np.ndarray) -> np.ndarray:
    """Per-component magnitudes when the caller gives none: |x0_k|, or the smallest nonzero |x0_j|
    for the components that start at zero (callers that know the physics should pass `scale`)."""
    a = np.abs(x0)
    nz = a[a > 0]
    floor = nz.min() if nz.size else 1.0
    return np.where(a > 0, a, floor)


def _validate(method, x0, n, t_end, tol, h, n_out, scale, time_scale, what, max_steps):
    lookup(method)
    if x0.shape != (n,):
        raise UserError(f"initial state has shape {x0.shape}, the part has {n} states; pass {n} numbers")
    if not np.all(np.isfinite(x0)):
        raise UserError("initial state is not finite; check the initial conditions")
    check_options(method, t_end, tol, h, n_out, time_scale, what, max_steps)
    if scale is not None:
        s = np.asarray(scale, dtype=float)
        if s.shape != (n,) or not np.all(np.isfinite(s)) or np.any(s <= 0):
            raise UserError(f"scale must be {n} positive numbers (state magnitudes)")


def integrate(part, x0, t_end: float, method: str = "dop853", tol: float | None = 1e-8,
              h: float | None = None, p=None, box: Box | None = None, n_out: int = 200,
              scale=None, monitor_energy: bool = False, max_steps: int | None = None,
              scipy_rhs: str = "auto", time_scale: float | None = None,
              time_scale_what: str = "the fastest period") -> Result:
    """Integrate `part` from x0 over [0, t_end] with `method` (see the module docstring).

    tol: adaptive methods (rtol = tol, atol_k = tol * scale_k). h: fixed-step methods.
    n_out: number of output intervals (adaptive: dense output on a uniform grid; fixed: every
    ceil(N / n_out)-th step). time_scale: the fastest period of the motion (runtime.simulate);
    it sets the default step budget and the limits of runtime.step_budget.check_options.
    max_steps: the step budget (None: runtime.step_budget.default_budget). A run that uses it up
    stops with status "step_budget". Raises UserError for bad options."""
    x0 = _f64(x0)
    n = len(part.states)
    _validate(method, x0, n, t_end, tol, h, n_out, scale, time_scale, time_scale_what, max_steps)
    t_end, n_out = float(t_end), int(n_out)
    budget = int(max_steps) if max_steps is not None else default_budget(method, t_end, h, time_scale)
    p = _f64(part.p if p is None else p)
    scale = default_scale(x0) if scale is None else _f64(scale)
    backend = lookup(method).backend
    if backend == "c":
        return _integrate_c(part, method, x0, p, t_end, tol, h, box, n_out, scale,
                            monitor_energy, budget)
    if backend == "casadi":
        return _integrate_casadi(part, method, x0, p, t_end, tol, h, box, n_out, scale, budget)
    return _integrate_scipy(part, method, x0, p, t_end, tol, box, n_out, scale, scipy_rhs, budget)


def _integrate_c(part, method, x0, p, t_end, tol, h, box, n_out, scale, monitor_energy, max_steps):
    lib = _lib_of(part)
    rhs = part.c_function("rhs")
    energy = part.c_function("energy") if monitor_energy else None
    if not lookup(method).fixed_step:
        t_out = np.linspace(0.0, t_end, n_out + 1)
        return run_c(lib, method, rhs, x0, p, t_end, rtol=tol, atol=tol * scale, energy=energy,
                     box=box, t_out=t_out, max_steps=max_steps)
    n_steps = fixed_steps(t_end, h)
    every = max(1, math.ceil(n_steps / n_out))
    jac = (part.c_function("jac") if lookup(method).needs_jacobian and _has_function(part, "jac")
           else None)
    return run_c(lib, method, rhs, x0, p, t_end, h=h, jac=jac, energy=energy, box=box,
                 every=every, max_samples=n_steps // every + 3, max_steps=max_steps)


def _truncate_at_box(t, X, box: Box | None):
    """First sample outside the box or non-finite: (k, status) or (None, None)."""
    for k in range(len(t)):
        if not np.all(np.isfinite(X[k])):
            return k, "nonfinite"
        if box is not None and box.excess(X[k]) > 0:
            return k, "left_box"
    return None, None


def _integrate_casadi(part, method, x0, p, t_end, tol, h, box, n_out, scale, max_steps):
    """CasADi's integrators. The budget: cvodes gets max_num_steps per output interval (CVODES
    counts its steps per call, one call per output time), so at most max_steps in all once
    max_steps >= n_out; the fixed-step plugins run the budgeted steps only, to t = max_steps h."""
    import casadi as ca
    plugin = lookup(method).engine
    F = part.casadi("rhs")
    n = x0.size
    u = ca.MX.sym("u", n)
    pp = ca.MX.sym("p", F.size1_in(1), F.size2_in(1))
    S = ca.DM(scale)
    ode = F(S * u, pp) / S                      # scaled states: one scalar atol serves all
    opts: dict[str, Any] = {}
    n_steps = 0
    status, message = "completed", "completed: reached t_end"
    t_run = t_end
    if plugin == "cvodes":
        opts = {"abstol": tol, "reltol": tol, "max_num_steps": max(1, max_steps // n_out),
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
    integ = ca.integrator("lev_" + plugin, plugin, {"x": u, "p": pp, "ode": ode}, 0.0,
                          list(t_grid[1:]), opts)
    start = time.perf_counter()
    try:
        out = integ(x0=ca.DM(x0 / scale), p=ca.DM(p))
        U = np.asarray(out["xf"].full()).T
    except RuntimeError as err:
        U = np.full((n_out, n), np.nan)
        status, message = "solver_error", f"casadi {plugin}: {str(err).splitlines()[0]}"
        if "TOO_MUCH_WORK" in str(err):
            status, message = "step_budget", (budget_message(max_steps) +
                                              " (cvodes: max_num_steps per output interval)")
    wall = time.perf_counter() - start
    X = np.vstack([x0[None, :], U * scale[None, :]])
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


def _integrate_scipy(part, method, x0, p, t_end, tol, box, n_out, scale, scipy_rhs, max_steps):
    """scipy's solvers stepped one accepted step at a time (solve_ivp's own loop, with its dense
    output and box event), so that the run stops after max_steps steps, or once the right-hand
    side was called more than CALLS_PER_STEP * max_steps times (counted in the wrapper: implicit
    methods may call it many times inside one step)."""
    import scipy.integrate
    from scipy.optimize import brentq
    f, kind = numpy_rhs(part, p, scipy_rhs)
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
        dense = solver.dense_output()
        t_stop = t_new
        if box is not None and box.excess(solver.y) > 0:
            t_stop = t_old
            if box.excess(dense(t_old)) <= 0:
                t_stop = brentq(lambda s, d=dense: box.excess(d(s)), t_old, t_new,
                                xtol=4 * np.finfo(float).eps * max(abs(t_new), 1e-300))
                if box.excess(dense(t_stop)) <= 0:      # the root's side inside: step just past it
                    t_stop = float(np.nextafter(t_stop, t_new))
            status, message = "left_box", "stopped: the state left the box"
        while i_out <= n_out and t_grid[i_out] <= t_stop:
            ts.append(float(t_grid[i_out]))
            xs.append(np.asarray(dense(t_grid[i_out]), float))
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


class CSystem:
    """A Part-like view of the C functions ``<prefix>_rhs``, ``_energy``, ``_jac`` in a library
    (the test systems of runtime/csrc/circle.c), usable wherever ``integrate`` takes a part."""

    def __init__(self, lib: ctypes.CDLL, prefix: str, states: Sequence[str], p: Sequence[float]):
        self.lib = _bind(lib)
        self.prefix = prefix
        self.states = tuple(states)
        self.params = tuple(f"p{i}" for i in range(len(p)))
        self.p = _f64(p)

    def c_function(self, name: str):
        return getattr(self.lib, f"{self.prefix}_{name}")

    def _call(self, name: str, x, p, n_out: int) -> np.ndarray:
        from runtime.model import CFunction
        return CFunction(self.c_function(name), len(self.states), n_out,
                         self.p if p is None else _f64(p))(x)

    def rhs(self, x, p=None, backend: str = "c") -> np.ndarray:
        return self._call("rhs", x, p, len(self.states))

    def energy(self, x, p=None, backend: str = "c") -> float:
        return float(self._call("energy", x, p, 1)[0])

    def jac(self, x, p=None, backend: str = "c") -> np.ndarray:
        n = len(self.states)
        return self._call("jac", x, p, n * n).reshape(n, n)
