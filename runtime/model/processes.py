"""Child processes die with their parent, and a terminated parent cleans up as it goes.

`die_with_parent` is the preexec_fn of the runtime's children (the derive subprocess, the C
compiler): on Linux prctl(PR_SET_PDEATHSIG, SIGKILL) makes the kernel kill the child when the
parent dies, however it dies (kill -9 too), so no orphaned derivation goes on writing into the
cache. `terminate_as_exit` turns SIGTERM (what `timeout` and most supervisors send) into
SystemExit, so the `finally` blocks that remove temporary folders and files run.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import signal
import sys

PR_SET_PDEATHSIG = 1
# resolved here, in the parent: the child between fork and exec only calls it (no dlopen, no
# allocation that could wait on a lock another thread of the parent held at the fork)
_PRCTL = ctypes.CDLL(ctypes.util.find_library("c") or None).prctl if sys.platform.startswith("linux") \
    else None


def die_with_parent() -> None:
    """In a child before exec: ask for SIGKILL when the parent dies (Linux; elsewhere nothing)."""
    if _PRCTL is not None:
        _PRCTL(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)


def terminate_as_exit() -> None:
    """SIGTERM raises SystemExit(143) in the main thread (cleanup runs, exit code 128 + 15)."""
    def handler(signum, frame):
        raise SystemExit(128 + signum)
    signal.signal(signal.SIGTERM, handler)
