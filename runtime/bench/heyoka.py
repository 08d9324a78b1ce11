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

Compiled integrators are kept on disk (heyoka pickles them with their machine code): in the cache
folder ($LEVITRON_CACHE/heyoka/<key>.pickle), where the key hashes what the compiled code is made
of (expressions_key): the part's expressions, by the sha256 of its generated rhs (the CasADi file
manifest.json lists: the graph the C computes, from the same lowered expressions) with the
parameters in order and the translation's source (derive/emit/heyoka.py), the state scales, the
tolerance, and heyoka's version, the machine and its CPU flags (a pickle is not portable across
either). Not the model's input hash, which changes with every edit of derive's sources: a bench
after one would compile some 10 minutes again for the same expressions. A second bench loads instead of building the
expressions (sympy, seconds per part) and compiling; `compile_cached` says which it did. A file is
written under a temporary name carrying the writer's pid and renamed into place, so a kill leaves
no half-written pickle, only a temporary that runtime/model/cache_sweep.py removes; a pickle that
cannot be read is built again. (The kill test's fault point between writing and renaming is
"heyoka_cache.written", scene/faults.py's die_at.)
"""
from __future__ import annotations

import hashlib
import math
import importlib.util
import json
import os
import pickle
import platform
import secrets
import time
from pathlib import Path

import numpy as np

CACHE_SUBDIR = "heyoka"


def available() -> bool:
    """Whether heyoka is installed (the bench says so when it is not)."""
    return importlib.util.find_spec("heyoka") is not None


def _cpu_identity() -> str:
    """The CPU's model and flags (compiled code may use any of them), or what platform knows."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8", errors="replace") as fh:
            info = [ln for ln in fh if ln.startswith(("model name", "flags", "Features"))]
        return "".join(sorted(set(info)))
    except OSError:
        return platform.processor()


def cache_key(**what) -> str:
    """The cache key of a compiled integrator: a hash of `what` (module docstring) with heyoka's
    version, the machine and its CPU."""
    import heyoka as hy
    ident = {**what, "heyoka": hy.__version__, "machine": platform.machine(),
             "cpu": hashlib.sha256(_cpu_identity().encode()).hexdigest()}
    return hashlib.sha256(json.dumps(ident, sort_keys=True).encode()).hexdigest()[:32]


def expressions_key(model, part: str) -> dict:
    """What heyoka's expressions of `part` are made of (module docstring): the digest of the part's
    generated rhs, the parameter names in order and the digest of the translation's source."""
    spec = importlib.util.find_spec("levitron.derive.emit.heyoka")     # found, not imported (sympy)
    casadi_file = model.manifest.functions[f"{part}_rhs"].casadi
    return {"rhs": model.manifest.files[casadi_file], "parameters": list(model.param_names),
            "translation": hashlib.sha256(Path(spec.origin).read_bytes()).hexdigest()}


def cache_folder() -> Path:
    from levitron.runtime.model.cbuild import cache_dir
    return cache_dir() / CACHE_SUBDIR


def _load(path: Path):
    try:
        with open(path, "rb") as fh:
            return pickle.load(fh)
    except FileNotFoundError:
        return None
    except Exception:     # noqa: BLE001 (a damaged pickle, another heyoka's: build it again)
        return None


def _store(path: Path, obj) -> None:
    """Write obj's pickle to path atomically (module docstring). No fsync: the rename is what a
    kill cannot split; after a power loss a truncated pickle fails to load and is built again."""
    from levitron.scene.faults import die_at
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}-{os.getpid()}-{secrets.token_hex(4)}.tmp")
    try:
        with open(tmp, "wb") as fh:
            pickle.dump(obj, fh, protocol=pickle.HIGHEST_PROTOCOL)
        die_at("heyoka_cache.written")
        os.replace(tmp, path)
        tmp = None
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.unlink(tmp)


def integrator(make_sys, X0: np.ndarray, p: np.ndarray, tol: float, key: str | None = None):
    """heyoka's taylor_adaptive for tol: from the cache when `key` is given and has one, else
    compiled from make_sys() (and stored under key). Returns (ta, seconds, from_cache)."""
    import heyoka as hy
    path = None if key is None else cache_folder() / f"{key}.pickle"
    t0 = time.perf_counter()
    ta = None if path is None else _load(path)
    if ta is not None and hasattr(ta, "propagate_until"):
        ta.pars[:] = list(map(float, p))
        return ta, time.perf_counter() - t0, True
    sys_ = make_sys()
    t0 = time.perf_counter()
    ta = hy.taylor_adaptive(sys_, X0.copy(), tol=tol, pars=list(map(float, p)))
    compile_s = time.perf_counter() - t0
    if path is not None:
        _store(path, ta)
    return ta, compile_s, False


def run(make_sys, x0: np.ndarray, p: np.ndarray, scale: np.ndarray, t_end: float, tol: float,
        repeat: dict, key: str | None = None) -> dict:
    """One tolerance: compile (timed apart; or load it from the cache under `key`), then the best
    of adaptive repeats of the run to t_end (runtime/bench/repeat.py's best_of with the options
    `repeat`: runtime/bench/work_precision.py's, the same for every backend). make_sys() gives the
    system (module docstring); it is called only when the cache has no integrator."""
    import heyoka as hy

    from levitron.runtime.bench.repeat import best_of
    X0 = np.asarray(x0, float) / scale
    ta, compile_s, cached = integrator(make_sys, X0, p, tol, key)
    best, steps, outcome = np.inf, None, None

    def once() -> float:
        nonlocal best, steps, outcome
        ta.state[:] = X0
        ta.time = 0.0
        t0 = time.perf_counter()
        res = ta.propagate_until(float(t_end))
        wall = time.perf_counter() - t0
        if wall < best:
            best, steps, outcome = wall, int(res[3]), res[0]
        return wall

    best_of(once, **repeat)
    ok = outcome == hy.taylor_outcome.time_limit
    return {"x_final": ta.state * scale, "wall_s": best, "steps": steps, "compile_s": compile_s,
            "compile_cached": cached, "order": int(ta.order),
            "status": "completed" if ok else str(outcome)}


def batch_map(make_sys, X0: np.ndarray, P: np.ndarray, box, scale: np.ndarray, t_end: float,
              tol: float, key: str | None = None) -> dict:
    """A stability map's points through heyoka's batch mode (taylor_adaptive_batch: one SIMD lane
    per point, the recommended batch size): X0 (k, n) the points' initial states, P (k, n_p) their
    parameters; each point runs to t_end or to its first exit from `box` (terminal events on
    z = z_lo, z = z_hi and x^2 + y^2 = r_max^2, as the C driver's box), in the states scaled by
    `scale` (one vector for all points). A batch call stops every lane when one lane's event
    fires, so lanes are refilled as a work queue: a lane that left the box or reached t_end takes
    the next point. The compiled integrator is cached as `integrator`'s. Returns per point
    levitating and t_survived, the wall time of the integration (compile apart) and compile_s."""
    import heyoka as hy
    k, n = X0.shape
    B = int(hy.recommended_simd_size())
    Xs = np.asarray(X0, float) / scale

    def make_batch():
        sys_ = make_sys()
        X = hy.make_vars(*[f"X{i}" for i in range(n)])
        z = X[box.iz] * float(scale[box.iz])
        events = [hy.t_event_batch(z - float(box.z_lo)), hy.t_event_batch(z - float(box.z_hi))]
        if box.ix >= 0 and math.isfinite(box.r_max):
            x, y = X[box.ix] * float(scale[box.ix]), X[box.iy] * float(scale[box.iy])
            events.append(hy.t_event_batch(x * x + y * y - float(box.r_max) ** 2))
        lanes = [i % k for i in range(B)]
        return hy.taylor_adaptive_batch(sys_, Xs[lanes].T.copy(), tol=tol, pars=P[lanes].T.copy(),
                                        t_events=events)

    path = None if key is None else cache_folder() / f"{key}.pickle"
    t0 = time.perf_counter()
    ta = None if path is None else _load(path)
    cached = ta is not None and hasattr(ta, "propagate_until")
    if not cached:
        ta = make_batch()
        if path is not None:
            _store(path, ta)
    compile_s = time.perf_counter() - t0
    lev = np.zeros(k, bool)
    t_surv = np.zeros(k)
    t0 = time.perf_counter()
    nxt, lane_pt = 0, [-1] * B
    state, pars, times = ta.state, ta.pars, ta.time.copy()
    for lane in range(B):                      # the first B points (idle lanes parked at t_end)
        if nxt < k:
            state[:, lane], pars[:, lane], times[lane] = Xs[nxt], P[nxt], 0.0
            lane_pt[lane], nxt = nxt, nxt + 1
        else:
            times[lane] = t_end
    ta.set_time(times)
    ta.reset_cooldowns()
    while any(pt >= 0 for pt in lane_pt):
        ta.propagate_until(float(t_end))
        times, refill = ta.time.copy(), False
        for lane in range(B):
            pt = lane_pt[lane]
            if pt < 0:
                continue
            out = ta.propagate_res[lane][0]
            if times[lane] < t_end and out == hy.taylor_outcome.success:
                continue                       # stopped by another lane's event: goes on
            lev[pt] = times[lane] >= t_end and out == hy.taylor_outcome.time_limit
            t_surv[pt] = min(float(times[lane]), float(t_end))
            if nxt < k:
                ta.state[:, lane], ta.pars[:, lane], times[lane] = Xs[nxt], P[nxt], 0.0
                lane_pt[lane], nxt = nxt, nxt + 1
            else:
                lane_pt[lane], times[lane] = -1, t_end
            refill = True
        if refill:
            ta.set_time(times)
            ta.reset_cooldowns()
    return {"levitating": lev, "t_survived": t_surv, "wall_s": time.perf_counter() - t0,
            "compile_s": compile_s, "compile_cached": cached, "batch_size": B}
