"""Injected faults for the kill tests: a process dies (SIGKILL) at a named point, once.

`LEVITRON_FAULT=POINT:MARKER` makes the first process that reaches `die_at(POINT)` create the file
MARKER and kill itself with SIGKILL (which no handler can catch: what `kill -9`, the OOM killer or
a lost machine do); every later process finds MARKER and goes on. Without the variable, die_at is
one dictionary look-up. Pure Python (no sympy): the runtime uses it too. The points:
"scan.worker_chunk" (a local scan worker, runtime/scan/runners.py), "write_atomic.written",
"write_atomic.swapped" and "write_atomic.between_renames" (derive/build.py), "derive.child" (the
derive subprocess, derive/__main__.py) and "runtime.deriving" (the runtime while its derive child
runs, runtime/model/load.py).
"""
from __future__ import annotations

import os
import signal

ENV = "LEVITRON_FAULT"


def die_at(point: str) -> None:
    """SIGKILL this process if LEVITRON_FAULT names `point` and its marker file is not there yet."""
    spec = os.environ.get(ENV)
    if not spec:
        return
    name, _, marker = spec.partition(":")
    if name != point or not marker:
        return
    try:
        fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return
    os.close(fd)
    os.kill(os.getpid(), signal.SIGKILL)
