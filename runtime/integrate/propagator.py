"""A run prepared once and repeated cheaply: one part, one adaptive C method, one tolerance.

    prop = Propagator(part, "dop853", tol=1e-9, scale=scale)
    x1 = prop(x0, t_end)          # the final state of one run from x0 over [0, t_end]

    prop.state[:] = x0            # or in place, as heyoka's taylor_adaptive: no copy out
    prop.propagate(t_end)         # prop.state is now the state at t_end

``integrate`` (runtime/integrate/run.py) checks its options, builds the C structs and output
buffers and returns a Result with samples, per call: about 25 us of Python around a few us of C
for a short reduced-model run. A Propagator does all of that once. A call copies x0 into the
buffer the C integrates in place, runs lev_integrate_job (one ctypes call with one pointer: the
struct lev_job of runtime/csrc/integrators.h) and returns a copy of the final state, so an
optimisation loop or a sweep pays about 1 us of Python per run (`levitron bench`'s per_call,
reports/<scene>/bench_reduced.json). The numbers are those of ``integrate`` with the same method,
tolerance, scale and parameters, bit for bit (tests/runtime/integrate/test_propagator.py): the same C call.

No samples. Without a box a run goes to t_end, or stops with a UserError naming why (its status);
with a Box (runtime/integrate/trajectory.py, the one `simulate` uses) a run that leaves it stops
there, as `simulate`'s does, and returns the state at the crossing with ``status`` "left_box" and
``t_final`` the time (no error: a top that falls is an answer; a start outside the box ends at
once, t_final 0 and the state unchanged, where `simulate` refuses it: a sweep gets its answer for
every start). The statistics of the last run are
``steps``, ``status``, ``t_final``, ``rhs_evals``. ``p`` is the parameter
vector C reads in place (assign into it). One Propagator holds one set of buffers: use one per
thread.
"""
from __future__ import annotations

import ctypes
import math

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.budget import MAX_STEPS_CAP, check_options
from levitron.runtime.integrate.c_backend import (_NO_BOX, STATUS, _Job, _Options, _Stats, _System,
                                                  _f64, bind, fn_address)
from levitron.runtime.integrate.methods import resolve
from levitron.runtime.integrate.trajectory import Box


_LEFT_BOX = next(k for k, v in STATUS.items() if v == "left_box")


class Propagator:
    """Runs of `part` with one adaptive C method (dop853, vern9, taylor or auto) at tolerance `tol`
    (rtol = tol, atol_k = tol * scale_k, as ``integrate``; `scale`: the state magnitudes, required),
    parameters `p` (default the part's), `box` the region the top must stay in (a Box, or None)."""

    def __init__(self, part, method: str = "dop853", tol: float = 1e-9, p=None, scale=None, *,
                 max_steps: int | None = None, box: Box | None = None):
        from levitron.runtime.integrate.run import _lib_of, taylor_of
        choice = resolve(method, tol)
        self.requested, self.method = method, choice.name
        entry = choice.entry
        if entry.backend != "c" or entry.fixed_step:
            raise UserError(f"a Propagator runs an adaptive C method (dop853, vern9, taylor or auto), "
                            f"not {self.method}; integrate() runs the others")
        check_options(self.method, 1.0, tol)
        self.part, self.tol, self.n = part, float(tol), len(part.states)
        lib = _lib_of(part)
        self._p = _f64(part.p if p is None else p).copy()
        if scale is None:
            raise UserError(f"a Propagator needs scale: {self.n} state magnitudes (the tolerance is "
                            "relative to them; Study.propagator passes the scene's)")
        self.scale = _f64(scale).copy()
        if self.scale.shape != (self.n,) or not (np.isfinite(self.scale).all() and (self.scale > 0).all()):
            raise UserError(f"scale must be {self.n} positive numbers (state magnitudes)")
        self.scale.flags.writeable = False
        self._atol = self.tol * self.scale
        taylor = taylor_of(part) if entry.needs_taylor else None
        self.max_steps = MAX_STEPS_CAP if max_steps is None else int(max_steps)
        n_work = int(lib.lev_work_bytes(entry.c_id, self.n)) // 8 + 2
        self._x = np.zeros(self.n)
        self._work = np.zeros(n_work)
        self._sys = _System(self.n, fn_address(part.c_function("rhs")), None, None,
                            self._p.ctypes.data, fn_address(taylor))
        self.box = box
        b = box or _NO_BOX
        self._opt = _Options(t0=0.0, t_end=1.0, rtol=self.tol, atol_v=self._atol.ctypes.data,
                             max_steps=self.max_steps, box_on=int(box is not None), ix=b.ix, iy=b.iy,
                             iz=b.iz, z_lo=b.z_lo, z_hi=b.z_hi, r_max=b.r_max)
        self._st = _Stats()
        self._job = _Job(entry.c_id, ctypes.addressof(self._sys), ctypes.addressof(self._opt),
                         self._x.ctypes.data, self._work.ctypes.data, None, None, None,
                         ctypes.addressof(self._st))
        self._addr = ctypes.addressof(self._job)
        self._run = bind(lib).lev_integrate_job
        self._t_end = 1.0
        self._lib = lib

    @property
    def p(self) -> np.ndarray:
        """The parameter vector of the runs, which C reads in place: `prop.p[:] = p_new` changes
        the next run's parameters (an optimisation loop needs no new Propagator)."""
        return self._p

    @p.setter
    def p(self, value) -> None:
        """`prop.p = p_new` copies into the vector C reads (the same as `prop.p[:] = p_new`)."""
        try:
            new = None if isinstance(value, str) else np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            new = None
        if new is None or new.shape != self._p.shape or not np.isfinite(new).all():
            raise UserError(f"prop.p must be {self._p.size} finite numbers (the parameter vector, "
                            f"e.g. study.p_of({{...}})), not {value!r}")
        self._p[:] = new

    @property
    def states(self) -> tuple[str, ...]:
        """The names of the state components, in order."""
        return tuple(self.part.states)

    @property
    def state(self) -> np.ndarray:
        """The state the next `propagate` starts from and leaves its result in (a view: assign
        into it, state[:] = x0)."""
        return self._x

    def propagate(self, t_end: float) -> None:
        """Run from `state` at t = 0 to t_end, leaving the final state in `state`."""
        if t_end != self._t_end:
            self._set_t_end(t_end)
        status = self._run(self._addr)
        if status and not (status == _LEFT_BOX and self.box is not None):
            self._fail(status)

    def __call__(self, x0, t_end: float) -> np.ndarray:
        """The state at t_end of the run from x0 at t = 0 (a new array)."""
        if t_end != self._t_end:
            self._set_t_end(t_end)
        try:
            self._x[:] = x0
        except (ValueError, TypeError):
            raise UserError(f"initial state must be {self.n} numbers, got {np.shape(x0)}") from None
        status = self._run(self._addr)
        if status and not (status == _LEFT_BOX and self.box is not None):
            self._fail(status)
        return self._x.copy()

    def _set_t_end(self, t_end) -> None:
        t_end = float(t_end)
        if not (t_end > 0.0 and math.isfinite(t_end)):
            raise UserError(f"t_end must be a positive finite time, got {t_end}")
        self._opt.t_end = self._t_end = t_end

    def _fail(self, status: int):
        name = STATUS.get(status, str(status))
        if name == "bad_input" and not np.isfinite(self._x).all():
            raise UserError("initial state is not finite; check the initial conditions")
        msg = self._lib.lev_status_message(status).decode()
        raise UserError(f"the {self.method} run ended '{name}' at t = {self._st.t_final:.6g}: {msg}")

    @property
    def status(self) -> str:
        """The last run's status ("completed", ...)."""
        return STATUS.get(self._st.status, str(self._st.status))

    @property
    def t_final(self) -> float:
        """Where the last run ended: t_end, or the time it left the box."""
        return float(self._st.t_final)

    @property
    def steps(self) -> int:
        return int(self._st.steps)

    @property
    def rhs_evals(self) -> int:
        return int(self._st.rhs_evals)

    def __repr__(self) -> str:
        part = getattr(self.part, "name", "?")
        box = "" if self.box is None else f", box z {self.box.z_lo:.4g}..{self.box.z_hi:.4g}"
        return f"Propagator(part={part}, method={self.method}, tol={self.tol:g}, n={self.n}{box})"
