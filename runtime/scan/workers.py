"""How many local worker processes a run takes when the caller does not say: every usable core.

`levitron launch`, `scan`, `trim` and `optimize --maximize launch-odds` default to the machine's
usable cores (runners.usable_cores: the CPU affinity); `--workers 1` (the API's workers=1) is
serial. Every run is the same arithmetic on any number of workers, so the default changes the wall
time, never the answer. The default stays serial where processes cannot pay for themselves or
cannot start:
- fewer than MIN_TASKS tasks (a worker's start, spawn and imports, is about a second: a few dozen
  launches run serially in less);
- a Python script without the `if __name__ == "__main__":` guard (runners.unguarded_script: each
  spawned worker would import it again); an explicit workers > 1 is refused there, the default
  falls back to serial.
"""
from __future__ import annotations

import contextlib
import logging

MIN_TASKS = 64          # launches (about 10 ms each); a map's points run seconds each: MIN_POINTS


def auto_workers(n_tasks: int, min_tasks: int = MIN_TASKS) -> int:
    """The default number of worker processes for n_tasks independent runs (module docstring)."""
    from levitron.runtime.scan.runners import unguarded_script, usable_cores
    if n_tasks < min_tasks or unguarded_script() is not None:
        return 1
    return usable_cores()


@contextlib.contextmanager
def dask_errors_as_ours():
    """While a run uses a dask client: dask's client logs nothing below CRITICAL. A lost scheduler
    is then one UserError line of runtime/scan/runners.py run_dask, not that line after dask's
    tracebacks of its reconnection; the logger's level is restored afterwards."""
    with contextlib.suppress(ImportError):      # its import sets its loggers' levels: first
        import distributed  # noqa: F401
    log = logging.getLogger("distributed.client")
    level = log.level
    log.setLevel(logging.CRITICAL)
    try:
        yield
    finally:
        log.setLevel(level)
