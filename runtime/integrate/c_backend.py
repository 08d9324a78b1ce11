"""The C integrators of runtime/csrc/integrators.c through ctypes (thesis 3.1).

The whole trajectory runs inside C over a generated right-hand side, with no Python call per step.
The ctypes mirrors of the C structs are checked against the sizes the library exports
(lev_sizeof_*) before the first call; the method ids come from runtime/integrate/methods.py, which
tests/runtime/integrate/test_budgets.py checks against the library's own table (lev_method_id). Every run has a step
budget (max_steps > 0: the C refuses a run without one).
"""
from __future__ import annotations

import ctypes
import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compile_shared
from levitron.runtime.errors import UserError
from levitron.runtime.integrate.methods import AUTO, Choice, lookup, resolve
from levitron.runtime.integrate.budget import MAX_STEPS_CAP, budget_message, default_budget
from levitron.runtime.integrate.trajectory import Box, Result

STATUS = {0: "completed", 1: "left_box", 2: "nonfinite", 3: "step_underflow", 4: "step_budget",
          5: "no_convergence", 6: "bad_input", 7: "energy_limit"}


CSRC = Path(__file__).resolve().parent.parent / "csrc"


class _System(ctypes.Structure):
    _fields_ = [("n", ctypes.c_int), ("rhs", ctypes.c_void_p), ("jac", ctypes.c_void_p),
                ("energy", ctypes.c_void_p), ("p", ctypes.c_void_p),    # double *: an address
                ("taylor", ctypes.c_void_p), ("quad", ctypes.c_void_p)]


class _Options(ctypes.Structure):
    _fields_ = [("t0", ctypes.c_double), ("t_end", ctypes.c_double), ("h", ctypes.c_double),
                ("rtol", ctypes.c_double), ("atol", ctypes.c_double),
                ("atol_v", ctypes.c_void_p), ("h_max", ctypes.c_double),
                ("max_steps", ctypes.c_long), ("box_on", ctypes.c_int), ("ix", ctypes.c_int),
                ("iy", ctypes.c_int), ("iz", ctypes.c_int), ("z_lo", ctypes.c_double),
                ("z_hi", ctypes.c_double), ("r_max", ctypes.c_double),
                ("t_out", ctypes.c_void_p), ("n_out", ctypes.c_long),
                ("every", ctypes.c_long), ("max_samples", ctypes.c_long), ("max_iter", ctypes.c_int),
                ("energy_limit", ctypes.c_double)]


class _Stats(ctypes.Structure):
    _fields_ = [("status", ctypes.c_int), ("steps", ctypes.c_long), ("rejected", ctypes.c_long),
                ("rhs_evals", ctypes.c_long), ("jac_evals", ctypes.c_long),
                ("energy_evals", ctypes.c_long), ("iterations", ctypes.c_long),
                ("n_samples", ctypes.c_long), ("dropped", ctypes.c_long),
                ("t_final", ctypes.c_double), ("h_last", ctypes.c_double),
                ("energy0", ctypes.c_double), ("energy_max_dev", ctypes.c_double)]


class _Job(ctypes.Structure):
    _fields_ = [("method", ctypes.c_int)] + [(k, ctypes.c_void_p) for k in (
        "sys", "opt", "x", "work", "out_t", "out_x", "out_e", "st")]


_DP = ctypes.POINTER(ctypes.c_double)


_STRUCTS = (("lev_sizeof_system", _System), ("lev_sizeof_options", _Options),
            ("lev_sizeof_stats", _Stats), ("lev_sizeof_job", _Job))


def bind(lib: ctypes.CDLL) -> ctypes.CDLL:
    """Declare the signatures of the integrator entry points (idempotent) and check that the
    ctypes mirrors of the C structs have the sizes the library reports."""
    f = lib.lev_integrate
    if f.argtypes is None:
        for fn_name, struct in _STRUCTS:
            fn = getattr(lib, fn_name)
            fn.argtypes, fn.restype = [], ctypes.c_size_t
            if fn() != ctypes.sizeof(struct):
                raise RuntimeError(f"runtime/integrate/run.py's {struct.__name__} has "
                                   f"{ctypes.sizeof(struct)} bytes, the C library's {fn()}: "
                                   "update the ctypes mirror of runtime/csrc/integrators.h")
        lib.lev_method_id.argtypes, lib.lev_method_id.restype = [ctypes.c_char_p], ctypes.c_int
        lib.lev_method_name.argtypes, lib.lev_method_name.restype = [ctypes.c_int], ctypes.c_char_p
        lib.lev_method_fixed_step.argtypes = [ctypes.c_int]
        lib.lev_method_fixed_step.restype = ctypes.c_int
        # lev_integrate(method, *sys, *opt, *x, *work, *out_t, *out_x, *out_e, *stats): the pointers
        # as c_void_p, passed as plain int addresses (run_c): ctypes converts an int in ~0.1 us, a
        # POINTER instance or byref() in ~0.2 us, ~1 us of a reduced bench run's ~5 us wall time
        f.argtypes = [ctypes.c_int] + [ctypes.c_void_p] * 8
        f.restype = ctypes.c_int
        lib.lev_integrate_job.argtypes, lib.lev_integrate_job.restype = [ctypes.c_void_p], ctypes.c_int
        lib.lev_work_bytes.argtypes = [ctypes.c_int, ctypes.c_int]
        lib.lev_work_bytes.restype = ctypes.c_size_t
        lib.lev_status_message.argtypes = [ctypes.c_int]
        lib.lev_status_message.restype = ctypes.c_char_p
        lib.lev_time_fn.argtypes = [ctypes.c_void_p, _DP, _DP, ctypes.c_int, ctypes.c_long]
        lib.lev_time_fn.restype = ctypes.c_double
        lib.lev_taylor_order.argtypes, lib.lev_taylor_order.restype = [ctypes.c_double], ctypes.c_int
    return lib


def fn_address(fn: Any) -> int | None:
    """The address of a C function given as a ctypes function pointer, an int, or None."""
    if fn is None:
        return None
    if isinstance(fn, int):
        return fn
    return ctypes.cast(fn, ctypes.c_void_p).value


def csrc_library(extra_sources: tuple[Path, ...] = ()) -> ctypes.CDLL:
    """The hand-written C of runtime/csrc alone (the integrators, the scan driver and the thesis's
    circle of circle.c), with `extra_sources` linked in (the tests' own systems: tests/c/systems.c)."""
    flags = DEFAULT_FLAGS + ("-Werror",)
    sources = [*sorted(CSRC.glob("*.c")), *map(Path, extra_sources)]
    return bind(ctypes.CDLL(str(compile_shared(sources, flags=flags, include_dirs=(CSRC,)))))


def _f64(a) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64))


def _ptr(a: np.ndarray | None):
    return None if a is None else a.ctypes.data_as(_DP)


_NO_BOX = Box(-1, -math.inf, math.inf)     # frozen: one instance serves every run without a box


def _per_lib(lib: ctypes.CDLL, key: tuple, make):
    """A constant of the loaded library (a work size, a status message), asked of C once and
    kept with the library (its attribute dict, as the lane verdicts)."""
    memo = lib.__dict__.setdefault("_lev_constants", {})
    if key not in memo:
        memo[key] = make()
    return memo[key]


def _addr(a: np.ndarray | None) -> int | None:
    """The address of a float64 array's data (the structs' double * fields are c_void_p: an int
    is stored as it is, without data_as's ctypes pointer object)."""
    return None if a is None else a.ctypes.data


def _buffers(*sizes: int) -> tuple[list[np.ndarray], list[int]]:
    """Zeroed float64 buffers of the given sizes, carved from one allocation, and their addresses:
    one numpy address lookup (~1.4 us; data_as ~3 us) instead of one per buffer."""
    buf = np.zeros(sum(sizes))
    base = buf.ctypes.data
    views, addrs, k = [], [], 0
    for size in sizes:
        views.append(buf[k:k + size])
        addrs.append(base + 8 * k)
        k += size
    return views, addrs


def time_fn_ns(lib: ctypes.CDLL, fn: Any, x: np.ndarray, p: np.ndarray, n_out: int,
               reps: int = 1_000_000) -> float:
    """Nanoseconds per call of a generated function, timed by a loop in C (lev_time_fn)."""
    bind(lib)
    x, p = _f64(x), _f64(p)
    return float(lib.lev_time_fn(fn_address(fn), _ptr(x), _ptr(p), int(n_out), int(reps)))


def run_c(lib: ctypes.CDLL, method: str | Choice, rhs: Any, x0, p, t_end: float, *, t0: float = 0.0,
          h: float = 0.0, rtol: float = 0.0, atol: float | Sequence[float] = 0.0,
          jac: Any = None, energy: Any = None, taylor: Any = None, box: Box | None = None,
          t_out: Sequence[float] | None = None, every: int = 0, max_samples: int | None = None,
          max_steps: int | None = None, h_max: float = 0.0, max_iter: int = 0,
          energy_limit: float = 0.0, quad: Any = None) -> Result:
    """Run one C integrator (no validation beyond the C's own; see ``integrate``).

    Samples: at the times ``t_out`` (DOP853 dense output), else every ``every``-th step plus the
    first and the last state. Energy, when given, is monitored after every step in C; with
    ``energy_limit`` > 0 the run stops once |H - H0| > energy_limit |H0| (status "energy_limit").
    max_steps: the step budget (attempted steps; status "step_budget"); None: the number of fixed
    steps, or runtime.integrate.budget.MAX_STEPS_CAP for DOP853. method: a name or a Choice (resolved
    once by the caller); "auto": the method resolve(rtol)
    picks (runtime/integrate/methods.py), named in Result.method. taylor: the part's Taylor
    function (method "taylor"; its expansions are Result.iterations, and it makes no rhs call).
    quad: a generated scalar function integrated as the last state of x0 (integrators.h's
    lev_system.quad: rhs gives the other rates; the caller appends W(0) to x0 and its atol)."""
    bind(lib)
    if isinstance(method, Choice):
        choice = method
    else:           # an adaptive method's h here is its first step (h_max beside it), not a fixed one
        choice = resolve(method, rtol, h or None if method == AUTO or lookup(method).fixed_step else None)
    method, code = choice.name, choice.entry.c_id
    if code is None:
        raise UserError(f"integrator {method!r} is not a C integrator")
    if max_steps is None:
        max_steps = (default_budget(method, t_end, h) if choice.fixed_step and h > 0
                     else MAX_STEPS_CAP)
    x0 = _f64(x0)
    n = x0.size
    p = _f64(p if p is not None else [0.0])
    tout = None if t_out is None else _f64(t_out)
    if max_samples is None:
        max_samples = (tout.size + 2) if tout is not None else 2
    atol_v = None
    if np.ndim(atol) > 0:
        atol_v = _f64(atol)
        atol = 0.0
    n_work = _per_lib(lib, ("work", code, n), lambda: int(lib.lev_work_bytes(code, n)) // 8 + 2)
    (x, out_t, out_x, out_e, _), addr = _buffers(n, max_samples, max_samples * n,
                                                 max_samples if energy is not None else 0, n_work)
    x[:] = x0
    out_x = out_x.reshape(max_samples, n)
    sysd = _System(n, fn_address(rhs), fn_address(jac), fn_address(energy), _addr(p),
                   fn_address(taylor), fn_address(quad))
    b = box or _NO_BOX
    opt = _Options(t0, t0 + t_end, h, rtol, float(atol), _addr(atol_v), h_max, max_steps,
                   1 if box is not None else 0, b.ix, b.iy, b.iz, b.z_lo, b.z_hi, b.r_max,
                   _addr(tout), 0 if tout is None else tout.size, every, max_samples, max_iter,
                   energy_limit)
    st = _Stats()
    # every argument an int address before the clock starts (argtypes c_void_p, see bind): wall_s
    # is the ctypes call and the C integrator, with no numpy or ctypes conversion inside it
    args = (code, ctypes.addressof(sysd), ctypes.addressof(opt), addr[0], addr[4], addr[1], addr[2],
            addr[3] if energy is not None else None, ctypes.addressof(st))
    start = time.perf_counter()
    status = lib.lev_integrate(*args)
    wall = time.perf_counter() - start
    k = st.n_samples
    name = STATUS.get(status, str(status))
    message = _per_lib(lib, ("message", status), lambda: lib.lev_status_message(status).decode())
    if name == "step_budget":
        message = budget_message(max_steps, float(st.t_final))
    res = Result(t=out_t[:k].copy(), X=out_x[:k].copy(), status=name, message=message,
                 rhs_evals=int(st.rhs_evals), wall_s=wall, t_final=float(st.t_final),
                 x_final=x.copy(), method=method, backend="c", steps=int(st.steps),
                 rejected=int(st.rejected), jac_evals=int(st.jac_evals),
                 iterations=int(st.iterations),
                 energy=out_e[:k].copy() if energy is not None else None,
                 energy0=float(st.energy0) if energy is not None else None,
                 energy_max_dev=float(st.energy_max_dev) if energy is not None else None,
                 details={"h_last": float(st.h_last), "dropped_samples": int(st.dropped)})
    res.details.update(choice.details())
    return res


class CSystem:
    """A Part-like view of the C functions ``<prefix>_rhs``, ``_energy``, ``_jac`` in a library
    (runtime/csrc/circle.c, the tests' tests/c/systems.c), usable wherever ``integrate`` takes a part."""

    def __init__(self, lib: ctypes.CDLL, prefix: str, states: Sequence[str], p: Sequence[float]):
        self.lib = bind(lib)
        self.prefix = prefix
        self.states = tuple(states)
        self.params = tuple(f"p{i}" for i in range(len(p)))
        self.p = _f64(p)

    def c_function(self, name: str):
        return getattr(self.lib, f"{self.prefix}_{name}")

    def taylor_function(self):
        """`<prefix>_taylor` (int (in, p, order, out), integrators.h's lev_taylor_fn), or None."""
        fn = getattr(self.lib, f"{self.prefix}_taylor", None)
        if fn is not None and fn.argtypes is None:
            fn.argtypes = [_DP, _DP, ctypes.c_int, _DP]
            fn.restype = ctypes.c_int
        return fn

    def _call(self, name: str, x, p, n_out: int) -> np.ndarray:
        from levitron.runtime.model.load import CFunction
        return CFunction(self.c_function(name), len(self.states), n_out,
                         self.p if p is None else _f64(p))(x)

    def rhs(self, x, p=None, backend: str = "c") -> np.ndarray:
        return self._call("rhs", x, p, len(self.states))

    def energy(self, x, p=None, backend: str = "c") -> float:
        return float(self._call("energy", x, p, 1)[0])

    def jac(self, x, p=None, backend: str = "c") -> np.ndarray:
        n = len(self.states)
        return self._call("jac", x, p, n * n).reshape(n, n)
