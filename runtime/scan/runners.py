"""The grid points of a stability map and the runners that share the grid out (runtime/scan/stability_map.py).

Every grid point is one nonlinear run of the full model from levitron.runtime.simulate.run's pieces
(`point_setup`: initial state, box, time scale, scales; thesis 3.1-3.3). The grid is dealt into
chunks (`split`); a chunk runs in one thread (`run_chunk`): for the C integrators through the C
chunk driver (runtime/scan/chunk_c.py: one C call per chunk, no Python per run, no output samples, no
energy monitor), otherwise (or with engine "python") one `point_run` per point, which is simulate()
number for number. Both give the same status and survival time per point (test_scan_driver.py).

Runners: serial, local processes (concurrent.futures.ProcessPoolExecutor, spawn; each worker loads
the model once in its initializer, and the compiled C library is found in the content-hash cache
of runtime/model/cbuild.py, so no worker recompiles), or a dask.distributed cluster (optional dependency,
the `cluster` extra; the workers need this package and the scene file at the same path). Runs are
deterministic, so all three give the same map.
"""
from __future__ import annotations

import contextlib
import os
import sys
import threading
import time
from concurrent.futures import CancelledError
from collections.abc import Sequence
from dataclasses import dataclass, replace

from levitron.runtime.ui import progress
from levitron.runtime.ui.human import duration      # wall times: the computer's seconds, any scene
from levitron.runtime.errors import UserError
from levitron.scene.faults import die_at
from levitron.runtime.integrate.methods import resolve
from levitron.runtime.model.processes import end_pool, ending_on_error
from levitron.runtime.scan.points import point_run

CONNECT_TIMEOUT_S = 20  # how long to try to reach a dask scheduler (and to wait for a worker)
CONNECT_GRACE_S = 5.0   # at most this much longer for dask's own connect error (half the timeout, >= 1 s)
DASK_POLL_S = 0.5       # how often a dask scan looks at its cluster's workers
MAX_POOL_RESTARTS = 3   # new local pools after lost workers, per scan


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
    h: float | None = None      # fixed-step integrators: None = runtime.simulate.run's default step
    engine: str = "c"           # "c": the chunk driver (C integrators); "python": run_point per point

    @property
    def choice(self):
        """The integrator as it runs (runtime/integrate/methods.py resolve: "auto" is its pick)."""
        return resolve(self.integrator, self.tol, self.h)


_MODELS: dict = {}
_LOCK = threading.Lock()


def model_for(scene: str, overrides: Sequence[str]):
    """The loaded model of (scene, overrides), once per process (and per dask worker)."""
    key = (scene, tuple(overrides))
    with _LOCK:
        model = _MODELS.get(key)
        if model is None:
            from levitron.scene.load import SceneError, load_scene
            from levitron.runtime.model.load import load_model
            try:
                sc = load_scene(scene, list(overrides))
            except SceneError as exc:
                raise UserError(str(exc)) from None
            model = load_model(sc)
            _ = model.lib  # compile or load from the content-hash cache now, not inside a timed run
            _MODELS[key] = model
        return model


def remember(common: Common, model) -> None:
    """Register an already loaded model (serial runs reuse the caller's)."""
    with _LOCK:
        _MODELS[(common.scene, tuple(common.overrides))] = model


def _init_worker(scene: str, overrides: tuple[str, ...], parent: int | None = None) -> None:
    """A local worker's start: it dies with its parent (runtime/model/processes.py: a kill -9 of
    the command leaves no worker running on, nor the resource tracker the workers keep open), leaves
    Ctrl-C to its parent (which ends it), loads the model once and the C driver."""
    from levitron.runtime.model.processes import die_with_parent, ignore_interrupts
    die_with_parent()
    ignore_interrupts()
    if parent is not None and os.getppid() != parent:      # the parent died before the line above
        os._exit(1)
    model_for(scene, overrides)
    import levitron.runtime.scan.chunk_c  # noqa: F401  (import once here, not inside the first timed chunk)


def task_point(common: Common, task: tuple[int, int, float, float]) -> dict:
    """The keyword arguments of point_setup / point_run for one task (i, j, spin, other)."""
    _, j, spin, other = task
    model = model_for(common.scene, common.overrides)
    return {"spin": spin, "tilt": other if common.axis == "tilt" else common.base_tilt,
            "height": other if common.axis == "height" else 0.0, "integrator": common.integrator,
            "h": common.h, "z_s": common.hover[j],
            "p": model.with_params({"m": other}) if common.axis == "mass" else model.p}


def run_point(common: Common, task: tuple[int, int, float, float]) -> dict:
    """One grid point (i_spin, j_other, spin, other) -> its survival (a thesis 3.1-3.2 run), through
    runtime.simulate.run's Python path (one integrate call with dense output and energy monitor)."""
    model = model_for(common.scene, common.overrides)
    r = point_run(model, t_end=common.t_end, tol=common.tol, **task_point(common, task))
    return {"i": task[0], "j": task[1], "levitating": bool(r["levitating"]),
            "t_survived": float(r["t_survived"]), "status": r["status"], "rhs_evals": r["rhs_evals"]}


def run_chunk(common: Common, tasks: Sequence[tuple]) -> dict:
    """A chunk of grid points in this thread: through the C chunk driver (runtime/scan/chunk_c.py, one C
    call, no Python per run) for the C integrators unless common.engine is "python", else one
    `run_point` per point. Returns the points, the chunk's CPU time (this thread's) and the method
    that ran (common.integrator, or for "auto" the one runtime.integrate.methods.resolve picks)."""
    choice = common.choice
    common = replace(common, integrator=choice.name)
    model = model_for(common.scene, common.overrides)
    cpu0 = time.thread_time()
    if common.engine == "c" and choice.entry.backend == "c":
        from levitron.runtime.scan.chunk_c import run_chunk_c
        points, engine = run_chunk_c(model, common, [(t, task_point(common, t)) for t in tasks]), "c"
    else:
        points, engine = [run_point(common, t) for t in tasks], "python"
    return {"points": points, "cpu_s": time.thread_time() - cpu0, "engine": engine,
            "method": common.integrator}


def _run_chunk_packed(args: tuple) -> dict:
    return args[0](*args[1:])          # (fn, common, chunk)


def split(tasks: Sequence[tuple], n_chunks: int) -> list[list[tuple]]:
    """`tasks` dealt into at most n_chunks chunks, every n_chunks-th task into the same one, so
    that each chunk samples the whole grid and the chunks take about the same time."""
    n = max(1, min(int(n_chunks), len(tasks)))
    return [list(tasks[c::n]) for c in range(n)] if tasks else []


LOG_EVERY = 10.0     # s: off a terminal, a scan's count and ETA at most this often (runtime/ui/progress.py)


def run_serial(common: Common, chunks: Sequence[list], quiet: bool = False, fn=None,
               what: str = "scan") -> list[dict]:
    """The chunks one after the other in this process (progress: runtime/ui/progress.py, points).
    fn(common, chunk) -> {"points": [...], ...} runs one chunk (default run_chunk: a map's; the
    launch Monte Carlo, runtime/scan/launch_odds.py, brings its own); `common` needs .scene and .overrides."""
    fn = fn or run_chunk
    out = []
    with progress.task(what, total=sum(map(len, chunks)), quiet=quiet,
                       log_every=LOG_EVERY) as tick:
        for chunk in chunks:
            out.append(fn(common, chunk))
            tick(len(chunk))
    return out


def run_worker_chunk(fn, common: Common, tasks: Sequence[tuple]) -> dict:
    """fn(common, tasks) (run_chunk, or the launch Monte Carlo's) in a local worker process, with
    the kill tests' injected fault point."""
    die_at("scan.worker_chunk")
    return fn(common, tasks)


def usable_cores() -> int:
    """The cores this process may run on (its CPU affinity), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def unguarded_script() -> str | None:
    """The script this process runs (python SCRIPT.py) when its top level has no
    `if __name__ == "__main__":` block, else None. Worker processes are spawned: each imports the
    script again, so a script without the guard starts the whole computation again in every
    worker, whose pool then breaks (docs/api.md)."""
    import ast
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if path is None or getattr(main, "__spec__", None) is not None or not path.endswith(".py"):
        return None                     # a notebook, python -c, python -m: nothing imported again
    try:
        tree = ast.parse(open(path, encoding="utf-8").read())
    except (OSError, SyntaxError, UnicodeDecodeError, ValueError):
        return None
    for node in tree.body:
        if isinstance(node, ast.If) and isinstance(node.test, ast.Compare):
            names = [node.test.left, *node.test.comparators]
            if any(isinstance(n, ast.Name) and n.id == "__name__" for n in names) and any(
                    isinstance(n, ast.Constant) and n.value == "__main__" for n in names):
                return None
    return path


class KeptPool:
    """One pool of local worker processes kept across several runs (a design's Monte Carlos), so
    that each run does not pay the start of its workers (spawn, imports: about 1 s). A worker loads
    each (scene, overrides) model once (model_for). `with KeptPool(workers) as pool:` and pass
    `pool` to run_processes; it ends with the block (an exception, Ctrl-C, SIGTERM: its workers
    killed at once, not waited for); a broken pool is replaced."""

    def __init__(self, workers: int):
        self.workers = workers
        self._ex = None

    def executor(self, common: Common):
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor
        if self._ex is None:
            self._ex = ProcessPoolExecutor(max_workers=self.workers, mp_context=multiprocessing.get_context("spawn"),
                                           initializer=_init_worker,
                                           initargs=(common.scene, tuple(common.overrides), os.getpid()))
        return self._ex

    def broken(self) -> None:
        """Drop a broken pool: the next executor() starts a new one."""
        if self._ex is not None:
            self._ex.shutdown(wait=False, cancel_futures=True)
            self._ex = None

    def __enter__(self) -> KeptPool:
        return self

    def __exit__(self, kind, *_) -> None:
        if self._ex is not None:
            end_pool(self._ex) if kind is not None else self._ex.shutdown(wait=True, cancel_futures=True)
            self._ex = None


def run_processes(common: Common, chunks: Sequence[list], workers: int,
                  quiet: bool = False, fn=None, what: str = "scan", pool: KeptPool | None = None) -> list[dict]:
    """Local processes (spawn: no fork of a process holding BLAS threads or a loaded library);
    fn as in run_serial; `pool`: a KeptPool to run in (else a pool for this run alone). A worker
    that dies (killed, out of memory) breaks the pool: the chunks not yet returned run again in a
    new pool, at most MAX_POOL_RESTARTS times; runs are deterministic, so the answer is the one a
    serial run gives. Any other way out (an error, KeyboardInterrupt: Ctrl-C or SIGTERM through
    runtime/model/processes.py) kills the workers at once, the chunks in flight with them."""
    fn = fn or run_chunk
    script = unguarded_script()
    if script is not None:
        raise UserError(f"«workers={workers}» starts worker processes, and each imports {script} again: put "
                        "the script's calls under `if __name__ == \"__main__\":` (docs/api.md), or use «workers=1»")
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool
    ctx = multiprocessing.get_context("spawn")
    pending = dict(enumerate(chunks))
    done: dict[int, dict] = {}
    restarts = 0
    with progress.task(f"{what} ({workers} processes)", total=sum(map(len, chunks)), quiet=quiet,
                       log_every=LOG_EVERY) as tick:
        while pending:
            try:
                with contextlib.ExitStack() as stack:
                    ex = pool.executor(common) if pool is not None else stack.enter_context(ProcessPoolExecutor(
                        max_workers=workers, mp_context=ctx, initializer=_init_worker,
                        initargs=(common.scene, tuple(common.overrides), os.getpid())))
                    stack.push(ending_on_error(ex, pool and pool.broken))
                    futures = {ex.submit(run_worker_chunk, fn, common, c): k for k, c in pending.items()}
                    for fut in as_completed(futures):
                        k = futures[fut]
                        done[k] = fut.result()
                        del pending[k]
                        tick(len(done[k]["points"]))
            except BrokenProcessPool:
                restarts += 1
                if restarts > MAX_POOL_RESTARTS:
                    raise UserError(f"{what}: worker processes died {restarts} times (killed, or out of "
                                    "memory?): run with fewer «workers», or «workers=1»") from None
                print(f"levitron: a {what} worker process died: running its {len(pending)} unfinished "
                      "chunks again in a new pool", file=sys.stderr)
    return [done[k] for k in sorted(done)]


def dask_client(address: str, timeout: float | None = None):
    """A dask.distributed Client of the scheduler at `address` with at least one worker, within
    `timeout` seconds (default CONNECT_TIMEOUT_S) for each step; one-line UserErrors when dask is
    missing, nothing answers, something that is not a dask scheduler answers (its handshake would
    never end: the connection runs in a daemon thread, given up after the timeout), or the
    cluster has no worker."""
    try:
        from dask.distributed import Client
    except ImportError:
        raise UserError("«scheduler» needs dask.distributed, which is not installed: "
                        "pip install 'levitron[cluster]' (or 'dask[distributed]'), or use «workers» N "
                        "for local processes") from None
    timeout = CONNECT_TIMEOUT_S if timeout is None else float(timeout)
    box: dict = {}

    def connect() -> None:
        try:
            box["client"] = Client(address, timeout=timeout)
        except Exception as exc:    # noqa: BLE001 (handed to the caller; one that gave up drops it)
            box["error"] = exc

    th = threading.Thread(target=connect, name="levitron-dask-connect", daemon=True)
    th.start()
    # dask's own timeout fires at `timeout`; the grace lets its error (the better message) arrive
    wait = timeout + min(CONNECT_GRACE_S, max(1.0, 0.5 * timeout))
    th.join(wait)
    if th.is_alive():
        raise UserError(f"no dask scheduler answered at {address!r} within {duration(timeout)} (is it a "
                        "dask scheduler? another service accepts the connection but never answers "
                        "dask's handshake): give the address `dask scheduler` prints, or use «workers» N")
    if isinstance(box.get("error"), MemoryError):      # numpy's _ArrayMemoryError too
        raise UserError(f"what answers at {address!r} is not a dask scheduler (its reply, read as "
                        "dask's protocol, announced an impossible message size; an HTTP server?): give "
                        "the address `dask scheduler` prints, or use «workers» N")
    if "error" in box and not isinstance(box["error"], (OSError, TimeoutError, ValueError)):
        raise box["error"]
    if "error" in box:
        raise UserError(f"cannot reach the dask scheduler at {address!r} ({box['error']}); start one "
                        "with `dask scheduler` and workers with `dask worker ADDRESS`, or use "
                        "«workers» N") from None
    client = box["client"]
    try:
        client.wait_for_workers(1, timeout=timeout)
    except TimeoutError:
        client.close()
        raise UserError(f"the dask scheduler at {address!r} has no workers (waited {duration(timeout)}): "
                        f"start some with `dask worker {address}`, or use «workers» N") from None
    return client


def dask_threads(client) -> int:
    """The number of worker threads of the cluster (at least 1)."""
    return max(1, sum(client.nthreads().values()))


def run_dask(common: Common, chunks: Sequence[list], client, quiet: bool = False, fn=None,
             what: str = "scan", timeout: float | None = None) -> list[dict]:
    """The chunks as tasks of a dask.distributed cluster (`client`, from dask_client). Every worker
    loads the model once (runtime.scan.runners.model_for, per process) and runs its chunks through the
    C chunk driver, which releases the GIL: threads of one worker run in parallel. fn as in
    run_serial. A cluster that loses every worker keeps the tasks for one that may never come:
    after `timeout` seconds (default CONNECT_TIMEOUT_S) without a worker, or when the scheduler
    gives a task up (it killed workers), a one-line UserError says how far the scan got."""
    from dask.distributed import wait
    fn = fn or run_chunk
    timeout = CONNECT_TIMEOUT_S if timeout is None else float(timeout)
    address = getattr(client.scheduler, "address", "?")
    total = sum(map(len, chunks))
    out: list[dict] = []

    def lost(why: str) -> UserError:
        done, unit = sum(len(r["points"]) for r in out), "launches" if what == "launch" else "points"
        return UserError(f"the dask cluster at {address!r} {why} ({done} of {total} {unit} done): "
                         f"start workers with `dask worker {address}` and run again, or use "
                         "«workers» N")

    with progress.task(f"{what} (dask)", total=total, quiet=quiet, log_every=LOG_EVERY) as tick:
        futures = client.map(_run_chunk_packed, [(fn, common, c) for c in chunks], pure=False)
        pending, alone_since = set(futures), None
        try:
            while pending:
                try:
                    done, pending = wait(pending, timeout=DASK_POLL_S, return_when="FIRST_COMPLETED")
                except TimeoutError:
                    done = set()
                except CancelledError as exc:       # dask's FuturesCancelledError: the scheduler died
                    raise lost(f"cancelled the work ({type(exc).__name__}: its scheduler died?)") from None
                for fut in done:
                    try:    # bounded: a result can leave with its worker before the gather
                        out.append(fut.result(timeout=DASK_POLL_S))
                    except TimeoutError:
                        pending.add(fut)
                        continue
                    except Exception as exc:    # noqa: BLE001 (dask's own errors, named below)
                        if isinstance(exc, CancelledError) or type(exc).__name__ == "KilledWorker":
                            raise lost(f"gave a chunk up ({type(exc).__name__}: the workers or the "
                                       "scheduler running it died)") from None
                        raise
                    tick(len(out[-1]["points"]))
                if not pending:
                    break
                try:
                    workers = len(client.nthreads())
                except (OSError, TimeoutError) as exc:
                    raise lost(f"stopped answering ({exc})") from None
                if workers:
                    alone_since = None
                elif alone_since is None:
                    alone_since = time.monotonic()
                elif time.monotonic() - alone_since > timeout:
                    raise lost(f"lost every worker mid-{what} (none for {duration(timeout)})")
        finally:
            with contextlib.suppress(OSError, TimeoutError, CancelledError):    # a dead scheduler too
                client.cancel(list(pending)) if pending else None
    return out
