"""A chunk of a stability map in one C call (runtime/csrc/scan_driver.c; thesis 3.1-3.2, fig. 3.8).

The Python side builds, once per chunk, the inputs of every point from levitron.runtime.simulate.run's pieces
(runtime.scan.points.point_setup: the initial state through the Legendre map of the generated
rhs, thesis eq. 2.3.8; the box; the fastest time scale; the state scales), and the step budget of
runtime/integrate/budget.py exactly as runtime.integrate.run gives it; then `lev_scan_chunk` integrates all
points in C, each stopped at its first exit from the box, with no output samples and no energy
monitor (neither changes the steps of a run, so status and survival time equal those of the
Python path, point_run). It returns status, t_survived and rhs_evals per point.
"""
from __future__ import annotations

import ctypes
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from levitron.runtime.integrate.c_backend import STATUS, bind, fn_address
from levitron.runtime.errors import UserError
from levitron.runtime.integrate.methods import lookup
from levitron.runtime.integrate.budget import check_options, default_budget

_DP = ctypes.POINTER(ctypes.c_double)
_LP = ctypes.POINTER(ctypes.c_long)
_IP = ctypes.POINTER(ctypes.c_int)
MAX_STATES = 256       # LEV_MAX_STATES (integrators.h): the C limit on the state dimension


def bind_driver(lib: ctypes.CDLL) -> ctypes.CDLL:
    """Declare lev_scan_chunk's signature (idempotent; the integrators' through cintegrate.bind)."""
    bind(lib)
    f = lib.lev_scan_chunk
    if f.argtypes is None:
        f.argtypes = [ctypes.c_int, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_int,
                      ctypes.c_int, ctypes.c_double, ctypes.c_double, ctypes.c_int, ctypes.c_int,
                      ctypes.c_int, ctypes.c_int, ctypes.c_long, _DP, _DP, _DP, _DP, _DP, _LP,
                      ctypes.c_void_p, _IP, _DP, _LP, _LP, _DP]
        f.restype = ctypes.c_long
        lib.lev_scan_work_bytes.argtypes = [ctypes.c_int, ctypes.c_int]
        lib.lev_scan_work_bytes.restype = ctypes.c_size_t
    return lib


LANES = 4              # LEV_LANES (integrators.h) = derive/emit/c/emitter.py LANES
LANES_CHECK = 32       # states on which a lane variant must equal the scalar rhs bit for bit
LANES_METHODS = ("dop853", "vern9")     # the methods of lev_integrate_lanes (scan_driver.c)


def lanes_of(model, rhs_name: str):
    """The generated lane variant `<rhs_name>_lanes` of a model's rhs (derive/emit/c: the same
    statements for LEV_LANES points at once), or None where the library has none."""
    try:
        return getattr(model.lib, model.symbol(f"{rhs_name}_lanes"))
    except AttributeError:
        return None


def lanes_call(fn, X: np.ndarray, P: np.ndarray) -> np.ndarray:
    """One call of a lane variant on LANES states X (LANES, n) with parameters P (LANES, n_p)."""
    inp = np.ascontiguousarray(X.T.reshape(-1), dtype=float)
    pp = np.ascontiguousarray(P.T.reshape(-1), dtype=float)
    out = np.zeros_like(inp)
    ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)(fn_address(fn))(
        inp.ctypes.data, pp.ctypes.data, out.ctypes.data)
    return out.reshape(X.shape[1], LANES).T


def verified_lanes(model, part, x0: np.ndarray, p: np.ndarray, scale: np.ndarray):
    """The lane variant of the part's rhs if it equals the scalar rhs bit for bit on LANES_CHECK
    states about x0 (relative changes of 1e-3 of the state scales, each lane its own parameters
    p scaled by 1 +- 1e-3), else None; the verdict is kept per library. The two are the same
    statements with the same explicit fused multiply-adds and no others (derive/emit/c/printer.py),
    so they agree by construction; the check stays because maps must not depend on the engine: a
    compiler that still rounded the vectorised loop differently would get a variant that is not
    used, and the scan would run one point at a time."""
    verdicts = lib_verdicts(model.lib)
    key = f"{part.name}_rhs"
    if key not in verdicts:
        fn = lanes_of(model, key)
        ok = fn is not None
        rng = np.random.default_rng(0)
        for _ in range(LANES_CHECK // LANES if ok else 0):
            X = x0 + 1e-3 * scale * rng.standard_normal((LANES, x0.size))
            P = p * (1 + 1e-3 * rng.uniform(-1, 1, (LANES, p.size)))
            got = lanes_call(fn, X, P)
            ok = ok and all(np.array_equal(got[k], part.rhs(X[k], P[k])) for k in range(LANES))
        verdicts[key] = fn if ok else None
    return verdicts[key]


def lib_verdicts(lib: ctypes.CDLL) -> dict:
    """The per-library record of verified lane variants (an attribute of the loaded library)."""
    if "_lev_lanes" not in lib.__dict__:
        lib.__dict__["_lev_lanes"] = {}
    return lib.__dict__["_lev_lanes"]


def _p(a: np.ndarray | None, kind=_DP):
    return None if a is None else a.ctypes.data_as(kind)


def drive(lib: ctypes.CDLL, method: str, rhs, jac, t_end: float, rtol: float, ix: int, iy: int,
          iz: int, x0: np.ndarray, p: np.ndarray, atol: np.ndarray | None, h: np.ndarray,
          box: np.ndarray, max_steps: np.ndarray, max_iter: int = 0, rhs_lanes=None) -> dict:
    """One lev_scan_chunk call over k points: x0 (k, n), p (k, n_p), atol (k, n) or None (fixed
    step), h (k,), box (k, 3) = z_lo, z_hi, r_max, max_steps (k,); rhs_lanes: the lane variant of
    rhs (lanes_of) or None. Returns the arrays status (names of runtime.integrate.c_backend.STATUS),
    t_final, rhs_evals, steps, x_final."""
    bind_driver(lib)
    entry = lookup(method)
    x0 = np.ascontiguousarray(x0, float)
    k, n = x0.shape
    if n > MAX_STATES:
        raise UserError(f"the chunk driver takes at most {MAX_STATES} states, the model has {n}")
    p = np.ascontiguousarray(p, float).reshape(k, -1)
    atol = None if atol is None else np.ascontiguousarray(atol, float).reshape(k, n)
    h = np.ascontiguousarray(h, float).reshape(k)
    box = np.ascontiguousarray(box, float).reshape(k, 3)
    max_steps = np.ascontiguousarray(max_steps, np.int64).reshape(k)
    work = np.zeros(int(lib.lev_scan_work_bytes(entry.c_id, n)) // 8 + 2)
    status = np.zeros(k, np.intc)
    t_final = np.zeros(k)
    rhs_evals = np.zeros(k, np.int64)
    steps = np.zeros(k, np.int64)
    x_final = np.zeros((k, n))
    ran = lib.lev_scan_chunk(entry.c_id, fn_address(rhs), fn_address(rhs_lanes), fn_address(jac),
                             n, p.shape[1],
                             float(t_end), float(rtol), ix, iy, iz, int(max_iter), k, _p(x0), _p(p),
                             _p(atol), _p(h), _p(box), _p(max_steps, _LP),
                             work.ctypes.data_as(ctypes.c_void_p), _p(status, _IP), _p(t_final),
                             _p(rhs_evals, _LP), _p(steps, _LP), _p(x_final))
    if ran != k:
        raise ValueError(f"lev_scan_chunk refused its arguments ({method}, {k} points of {n} states)")
    return {"status": [STATUS.get(int(s), str(int(s))) for s in status], "t_final": t_final,
            "rhs_evals": rhs_evals, "steps": steps, "x_final": x_final}


def drive_runs(model, part, method: str, t_end: float, tol: float | None, x0: np.ndarray,
               p: np.ndarray, scale: np.ndarray, h: np.ndarray, box: np.ndarray,
               max_steps: np.ndarray) -> dict:
    """Runs of one model part from x0 (k, n) with parameters p (k, n_p) in one lev_scan_chunk
    call: adaptive methods with rtol = tol, atol = tol * scale (k, n) (runtime.integrate.run's
    tolerances), fixed-step ones with the steps h (k,); box (k, 3) = z_lo, z_hi, r_max around each
    run's hover height; max_steps (k,) the step budgets; the generated Jacobian where the method
    needs it; the lane variant of the rhs where it verifies (verified_lanes). What the stability
    maps, the launch odds and the batched simulations share. Returns drive's arrays and `lanes`
    (whether the lane variant ran)."""
    from levitron.runtime.simulate.start import default_box
    entry = lookup(method)
    jac = part.c_function("jac") if entry.needs_jacobian and part.has("jac") else None
    bx = default_box(part, 1.0)                # the state indices of x, y and z
    x0 = np.asarray(x0, float)
    lanes = verified_lanes(model, part, x0[0], np.asarray(p, float)[0], np.asarray(scale, float)[0])
    res = drive(model.lib, method, part.c_function("rhs"), jac, t_end,
                0.0 if entry.fixed_step else tol, bx.ix, bx.iy, bx.iz, x0, p,
                None if entry.fixed_step else tol * np.asarray(scale, float), h, box, max_steps,
                rhs_lanes=lanes)
    res["lanes"] = lanes is not None and method in LANES_METHODS
    return res


def run_chunk_c(model, common, points: Sequence[tuple]) -> list[dict]:
    """The grid points [(task, point_setup keywords)] of one chunk through lev_scan_chunk, with the
    options runtime.integrate.run would give each run (atol = tol * scale, rtol = tol; the default step
    budget at the point's fastest time scale; the same option checks)."""
    from levitron.runtime.scan.points import N_OUT, point_setup
    choice = common.choice
    common = replace(common, integrator=choice.name)
    tol = choice.tol
    memo: dict = {}      # the spin-free inputs, once per tilt (or height, mass) of the chunk
    setups = [point_setup(model, memo=memo, **kw) for _, kw in points]
    if not setups:
        return []
    for su in setups:
        check_options(common.integrator, common.t_end, tol, su.h, N_OUT, su.time_scale,
                      su.time_scale_what)
    res = drive_runs(model, setups[0].part, common.integrator, common.t_end, tol,
                     np.array([su.x0 for su in setups]), np.array([su.p for su in setups]),
                     np.array([su.scale for su in setups]), np.array([su.h or 0.0 for su in setups]),
                     np.array([(su.box.z_lo, su.box.z_hi, su.box.r_max) for su in setups]),
                     np.array([default_budget(common.integrator, common.t_end, su.h, su.time_scale)
                               for su in setups]))
    return [{"i": task[0], "j": task[1], "levitating": res["status"][k] == "completed",
             "t_survived": float(res["t_final"][k]), "status": res["status"][k],
             "rhs_evals": int(res["rhs_evals"][k])}
            for k, (task, _) in enumerate(points)]
