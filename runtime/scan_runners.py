"""One grid point of a stability map and the runners that share the grid out (runtime/scan.py).

Every grid point is one nonlinear run of the full model (`point_run`: runtime.simulate's pieces,
thesis 3.1-3.2). Runners: serial, local processes (concurrent.futures.ProcessPoolExecutor, spawn;
each worker loads the model once in its initializer, and the compiled C library is found in the
content-hash cache of runtime/cbuild.py, so no worker recompiles), or a dask.distributed cluster
(optional dependency, the `cluster` extra; the workers need this package and the scene file at the
same path). Runs are deterministic, so all three give the same map.
"""
from __future__ import annotations

import sys
import threading
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from runtime.errors import UserError
from runtime.integrators_table import DEFAULT

N_OUT = 100            # dense-output samples per run: only the survival matters here


@dataclass(frozen=True)
class Common:
    """What every grid point shares (picklable: sent to the workers)."""
    scene: str                  # a scene name or an absolute path
    overrides: tuple[str, ...]  # the --set strings
    axis: str
    t_end: float
    integrator: str
    tol: float | None
    base_tilt: float
    hover: tuple = ()           # z_s per value of the other axis (None: that mass does not hover)
    h: float | None = None      # fixed-step integrators: None = runtime.simulate's default step


_MODELS: dict = {}
_LOCK = threading.Lock()


def _model(scene: str, overrides: Sequence[str]):
    """The loaded model of (scene, overrides), once per process (and per dask worker)."""
    key = (scene, tuple(overrides))
    with _LOCK:
        model = _MODELS.get(key)
        if model is None:
            from derive.scene import SceneError, load_scene
            from runtime.model import load_model
            try:
                sc = load_scene(scene, list(overrides))
            except SceneError as exc:
                raise UserError(str(exc)) from None
            model = load_model(sc, list(overrides))
            _ = model.lib  # compile or load from the content-hash cache now, not inside a timed run
            _MODELS[key] = model
        return model


def remember(common: Common, model) -> None:
    """Register an already loaded model (serial runs reuse the caller's)."""
    with _LOCK:
        _MODELS[(common.scene, tuple(common.overrides))] = model


def _init_worker(scene: str, overrides: tuple[str, ...]) -> None:
    _model(scene, overrides)
    import runtime.simulate  # noqa: F401  (import once here, not inside the first timed point)


def point_run(model, spin: float, tilt: float = 0.0, height: float = 0.0, t_end: float = 1.0,
              integrator: str = DEFAULT, tol: float | None = 1e-9, h: float | None = None,
              p: np.ndarray | None = None, z_s: float | None = None, n_out: int = N_OUT) -> dict:
    """runtime.simulate.simulate from the same pieces (initial state, box, scales, integrator,
    summary), with two differences: the hover height z_s may be given (a scan finds it once per
    mass, not once per point: it costs more than a short run), and the top may start displaced to
    z_0 = z_s (1 + height), at rest vertically; box and checks stay centred on z_s (thesis 3.3.2).
    With height = 0 the result is simulate()'s, number for number (tests/test_scan.py)."""
    from runtime import simulate as sim
    from runtime.equilibrium import hover_height
    from runtime.integrate import integrate
    from runtime.integrators_table import lookup
    entry = lookup(integrator)
    pt = model.part("full")
    p = model.p if p is None else p
    pvals = model.pvals(p)
    if z_s is None:
        z_s = hover_height(model, p)
    bx = sim.default_box(pt, z_s)
    T, what = sim.time_scale(model, p, z_s, spin, pvals)
    if entry.fixed_step and h is None:
        h = T / 100
    x0 = sim.initial_state(pt, z_s * (1.0 + height), spin, tilt, 0.0, p)
    scale = sim.state_scales(pt, z_s, spin, pvals)
    res = integrate(pt, x0, t_end, method=integrator, tol=None if entry.fixed_step else tol, h=h,
                    p=p, box=bx, n_out=n_out, scale=scale, monitor_energy=entry.monitors_energy,
                    time_scale=T, time_scale_what=what)
    return sim.summarize(pt, res, x0, p, z_s, bx, spin, tilt, 0.0, t_end, integrator, tol, h, None)


def run_point(common: Common, task: tuple[int, int, float, float]) -> dict:
    """One grid point (i_spin, j_other, spin, other) -> its survival (a thesis 3.1-3.2 run)."""
    i, j, spin, other = task
    model = _model(common.scene, common.overrides)
    t0 = time.perf_counter()
    p = model.with_params({"m": other}) if common.axis == "mass" else model.p
    r = point_run(model, spin, tilt=other if common.axis == "tilt" else common.base_tilt,
                  height=other if common.axis == "height" else 0.0, t_end=common.t_end,
                  integrator=common.integrator, tol=common.tol, h=common.h, p=p,
                  z_s=common.hover[j])
    return {"i": i, "j": j, "levitating": bool(r["levitating"]), "t_survived": float(r["t_survived"]),
            "status": r["status"], "rhs_evals": r["rhs_evals"], "wall_s": time.perf_counter() - t0}


def _run_point_packed(args: tuple) -> dict:
    return run_point(*args)


def _progress(done: int, total: int, t0: float, quiet: bool) -> None:
    if quiet:
        return
    step = max(1, total // 10)
    if done % step == 0 or done == total:
        print(f"levitron scan: {done}/{total} points, {time.perf_counter() - t0:.1f} s",
              file=sys.stderr, flush=True)


def run_serial(common: Common, tasks: Sequence[tuple], quiet: bool = False) -> list[dict]:
    t0 = time.perf_counter()
    out = []
    for k, t in enumerate(tasks, 1):
        out.append(run_point(common, t))
        _progress(k, len(tasks), t0, quiet)
    return out


def run_processes(common: Common, tasks: Sequence[tuple], workers: int,
                  quiet: bool = False) -> list[dict]:
    """Local processes (spawn: no fork of a process holding BLAS threads or a loaded library)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    ctx = multiprocessing.get_context("spawn")
    t0 = time.perf_counter()
    out = []
    with ProcessPoolExecutor(max_workers=workers, mp_context=ctx, initializer=_init_worker,
                             initargs=(common.scene, tuple(common.overrides))) as ex:
        futures = [ex.submit(run_point, common, t) for t in tasks]
        for k, fut in enumerate(as_completed(futures), 1):
            out.append(fut.result())
            _progress(k, len(tasks), t0, quiet)
    return out


def run_dask(common: Common, tasks: Sequence[tuple], address: str, quiet: bool = False) -> list[dict]:
    """A dask.distributed cluster at `address` (e.g. tcp://host:8786)."""
    try:
        from dask.distributed import Client
    except ImportError:
        raise UserError("--scheduler needs dask.distributed, which is not installed: "
                        "pip install 'levitron[cluster]' (or 'dask[distributed]'), or use --workers N "
                        "for local processes") from None
    try:
        client = Client(address, timeout=20)
    except (OSError, TimeoutError, ValueError) as exc:
        raise UserError(f"cannot reach the dask scheduler at {address!r} ({exc}); start one with "
                        "`dask scheduler` and workers with `dask worker ADDRESS`, or use --workers N"
                        ) from None
    t0 = time.perf_counter()
    try:
        futures = client.map(_run_point_packed, [(common, t) for t in tasks], pure=False)
        out = client.gather(futures)
    finally:
        client.close()
    _progress(len(tasks), len(tasks), t0, quiet)
    return list(out)
