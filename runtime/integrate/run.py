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
- ``vern9``        Verner's 9(8) pair, adaptive like dop853, dense output, box event
- ``taylor``       Taylor's method over the part's generated coefficients (derive/emit/taylor.py;
                   the reduced model): order ceil(-ln(tol)/2 + 1), the step that holds the first
                   omitted term to 0.1 tol w_k (integrators.c taylor_step), no
                   rejected steps, dense output from the step's polynomial, box event
- ``auto``         dop853 or vern9, whichever the bench measured cheapest at the requested tol
                   (runtime.integrate.methods.resolve); the Result names the method that ran
                   (``method``) and records the request (``details["integrator_requested"]``,
                   ``details["auto"]``)

CasADi (through ``part.casadi("rhs")``): ``cvodes`` (adaptive BDF/Adams of SUNDIALS, here
Adams-Moulton for the non-stiff levitron), ``casadi-rk`` (CasADi's fixed-step RK4) and
``casadi-collocation`` (CasADi's fixed-step Legendre collocation).
scipy: ``scipy-dop853``, ``scipy-rk45``, ``scipy-radau``, ``scipy-bdf``, ``scipy-lsoda``, scipy's
OdeSolver classes stepped as ``solve_ivp`` does, with the part's numpy-facing right-hand side (one
Python call per stage). runtime/integrate/methods.py is the one list of these names and their facts.

The pieces: runtime/integrate/c_backend.py (the C integrators through ctypes), runtime/integrate/casadi_backend.py,
runtime/integrate/scipy_backend.py, runtime/integrate/trajectory.py (Box, Result) and runtime/integrate/budget.py.

Every run has a step budget (runtime/integrate/budget.py) and stops with status "step_budget" once it is
used up: in C a counter compare per step, in CasADi CVODES' max_num_steps, in scipy a count of steps
and of right-hand side calls.

A ``quadrature`` (the name of a scalar function of the part, e.g. "dissipation", and the size of
its integral) is integrated inside the run as one more state W, dW/dt = f(x), by every backend
(C: integrators.h's lev_system.quad; CasADi: its integrators' "quad"; scipy: the right-hand side
extended by f), by the method's own stages and dense output. In C and CasADi W does not steer the
steps (it is left out of the error norm: the states are those of the run without it, in C bit for
bit); scipy's solvers control it as one more state, atol tol * that size. The Result carries W at
the samples (``work``, ``work_final``) and the states without it.

Tolerances are made dimension-aware by a per-component ``scale`` (state magnitudes): every
adaptive backend controls |local error_k| <= tol * (scale_k + |x_k|). The box (``Box``) stops a
C or scipy run at the first exit (dense-output bisection in C, event root in scipy); CasADi has no
events, so a CasADi run is checked on its output grid and truncated at the first sample outside.
"""
from __future__ import annotations

import ctypes
import math

import numpy as np

from levitron.runtime.integrate.c_backend import CSystem, bind, _f64, csrc_library, run_c, time_fn_ns
from levitron.runtime.errors import UserError
from levitron.runtime.integrate.casadi_backend import integrate_casadi
from levitron.runtime.integrate.scipy_backend import integrate_scipy
from levitron.runtime.integrate.methods import DEFAULT, Choice, lookup, resolve
from levitron.runtime.integrate.budget import check_options, default_budget, fixed_steps
from levitron.runtime.integrate.trajectory import Box, Result

# the names callers import from here (the pieces live in the modules above)
__all__ = ["Box", "CSystem", "Result", "backend_of", "csrc_library", "default_scale", "integrate",
           "run_c", "time_fn_ns"]


def backend_of(method: str) -> str:
    """The backend name of docs/contract.md's bench rows: "c", "casadi" or "scipy"."""
    return lookup(method).backend


def _lib_of(part) -> ctypes.CDLL:
    lib = getattr(part, "lib", None)
    if lib is None and getattr(part, "model", None) is not None:
        lib = part.model.lib
    if lib is None:
        raise TypeError("the part exposes no compiled library (part.lib or part.model.lib)")
    return bind(lib)


def _has_function(part, name: str) -> bool:
    try:
        return part.c_function(name) is not None
    except (AttributeError, KeyError, LookupError):
        return False


TINY = 1e-12      # a start below this fraction of the largest |x0_j| is a zero with rounding


def default_scale(x0: np.ndarray) -> np.ndarray:
    """Per-component magnitudes when the caller gives none: |x0_k|, or the smallest |x0_j| that is
    not a zero for the components that start at zero or at a rounding's worth of it (a periodic
    orbit's zeta of 1e-28 once asked dop853 for an error of 1e-40 there). Callers that know the
    physics pass `scale` (the state's own sizes)."""
    a = np.abs(x0)
    real = a > TINY * a.max() if a.size else a > 0
    floor = a[real].min() if real.any() else 1.0
    return np.where(real, a, floor)


def _validate(method, x0, n, t_end, tol, h, n_out, scale, time_scale, what, max_steps):
    lookup(method)
    if x0.shape != (n,):
        raise UserError(f"initial state has shape {x0.shape}, the part has {n} states; pass {n} numbers")
    if not np.isfinite(x0).all():
        raise UserError("initial state is not finite; check the initial conditions")
    check_options(method, t_end, tol, h, n_out, time_scale, what, max_steps)
    if scale is not None:
        s = np.asarray(scale, dtype=float)
        if s.shape != (n,) or not np.isfinite(s).all() or (s <= 0).any():
            raise UserError(f"scale must be {n} positive numbers (state magnitudes)")


def integrate(part, x0, t_end: float, method: str = DEFAULT, tol: float | None = 1e-8,
              h: float | None = None, p=None, box: Box | None = None, n_out: int = 200,
              scale=None, monitor_energy: bool = False, max_steps: int | None = None,
              scipy_rhs: str = "auto", time_scale: float | None = None,
              time_scale_what: str = "the fastest period",
              quadrature: tuple[str, float] | None = None) -> Result:
    """Integrate `part` from x0 over [0, t_end] with `method` (see the module docstring).

    tol: adaptive methods (rtol = tol, atol_k = tol * scale_k). h: fixed-step methods.
    n_out: number of output intervals (adaptive: dense output on a uniform grid; fixed: every
    ceil(N / n_out)-th step). time_scale: the fastest period of the motion (runtime.simulate.run);
    it sets the default step budget and the limits of runtime.integrate.budget.check_options.
    max_steps: the step budget (None: runtime.integrate.budget.default_budget). A run that uses it up
    stops with status "step_budget". method "auto": the C method resolve(tol) picks (its name in
    Result.method, the request in Result.details). quadrature: (kind, size), the part's function
    `kind` integrated beside the state, atol tol * size (module docstring). Raises UserError for
    bad options."""
    choice = resolve(method, tol, h)         # once: every step below reads its entry
    res = _integrate(part, x0, t_end, choice, p, box, n_out, scale, monitor_energy,
                     max_steps, scipy_rhs, time_scale, time_scale_what, quadrature)
    res.details.update(choice.details())
    return res


def _integrate(part, x0, t_end, choice: Choice, p, box, n_out, scale, monitor_energy, max_steps,
               scipy_rhs, time_scale, time_scale_what, quadrature=None) -> Result:
    x0 = _f64(x0)
    n = len(part.states)
    method, entry, tol, h = choice.name, choice.entry, choice.tol, choice.h
    _validate(method, x0, n, t_end, tol, h, n_out, scale, time_scale, time_scale_what, max_steps)
    t_end, n_out = float(t_end), int(n_out)
    budget = int(max_steps) if max_steps is not None else default_budget(method, t_end, h, time_scale)
    p = _f64(part.p if p is None else p)
    scale = default_scale(x0) if scale is None else _f64(scale)
    quad = None
    if quadrature is not None:
        quad, size = quadrature
        if not (math.isfinite(size) and size > 0):
            raise ValueError(f"quadrature size {size!r}: a positive number")
        if entry.needs_taylor:
            taylor_of(part)      # a part without coefficients (the full model) says that first
            raise UserError(f"integrator {method} integrates no quadrature (the energy balance in "
                            "air): choose dop853, vern9 or auto")
        x0, scale = np.append(x0, 0.0), np.append(scale, float(size))
    backend = entry.backend
    if backend == "c":
        res = _integrate_c(part, choice, x0, p, t_end, box, n_out, scale, monitor_energy, budget, quad)
    elif backend == "casadi":
        res = integrate_casadi(part, method, x0, p, t_end, tol, h, box, n_out, scale, budget, quad)
    else:
        res = integrate_scipy(part, method, x0, p, t_end, tol, box, n_out, scale, scipy_rhs, budget,
                              quad)
    return res if quad is None else split_quadrature(res, n)


def split_quadrature(res: Result, n: int) -> Result:
    """The Result of a run with a quadrature as the last of n + 1 states: W moved to res.work and
    res.work_final, the states (X, x_final) without it."""
    X = np.atleast_2d(res.X)
    res.work, res.work_final = X[:, n].copy(), float(res.x_final[n])
    res.X, res.x_final = X[:, :n].copy(), res.x_final[:n].copy()
    return res


_GRIDS: dict = {}
_GRIDS_KEPT = 64


def output_grid(t_end: float, n_out: int) -> np.ndarray:
    """np.linspace(0, t_end, n_out + 1), kept (read-only) for the last _GRIDS_KEPT (t_end, n_out):
    a sweep or an optimisation loop asks for the same grid at every call."""
    key = (t_end, n_out)
    grid = _GRIDS.get(key)
    if grid is None:
        if len(_GRIDS) >= _GRIDS_KEPT:
            _GRIDS.pop(next(iter(_GRIDS)))
        grid = np.linspace(0.0, t_end, n_out + 1)
        grid.flags.writeable = False
        _GRIDS[key] = grid
    return grid


def taylor_of(part):
    """The part's generated Taylor function, or a UserError naming the methods that run it."""
    fn = part.taylor_function() if hasattr(part, "taylor_function") else None
    if fn is None:
        scene = getattr(getattr(getattr(part, "model", None), "scene", None), "name", "this scene")
        name = getattr(part, "name", "given")
        why = ("its rhs has an operation without a recurrence in derive/emit/taylor.py" if name == "reduced"
               else "derive generates them for the reduced model only")
        raise UserError(f"integrator taylor needs Taylor coefficients, and the {name} model of scene "
                        f"'{scene}' has none ({why}): choose dop853, vern9 or auto")
    return fn


def _integrate_c(part, choice: Choice, x0, p, t_end, box, n_out, scale, monitor_energy, max_steps,
                 quad=None):
    lib = _lib_of(part)
    entry, tol, h = choice.entry, choice.tol, choice.h
    rhs = part.c_function("rhs")
    energy = part.c_function("energy") if monitor_energy else None
    quad = part.c_function(quad) if quad is not None else None
    if not entry.fixed_step:
        t_out = output_grid(t_end, n_out)
        taylor = taylor_of(part) if entry.needs_taylor else None
        return run_c(lib, choice, rhs, x0, p, t_end, rtol=tol, atol=tol * scale, energy=energy,
                     taylor=taylor, box=box, t_out=t_out, max_steps=max_steps, quad=quad)
    n_steps = fixed_steps(t_end, h)
    every = max(1, math.ceil(n_steps / n_out))
    jac = (part.c_function("jac") if entry.needs_jacobian and _has_function(part, "jac")
           else None)
    return run_c(lib, choice, rhs, x0, p, t_end, h=h, jac=jac, energy=energy, box=box,
                 every=every, max_samples=n_steps // every + 3, max_steps=max_steps, quad=quad)
