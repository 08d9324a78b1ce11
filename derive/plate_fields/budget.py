"""A wall-clock budget for sympy work on scene text (expression plates: bounded work).

Sympy cannot be interrupted cooperatively, so `time_budget` arms a real-time timer (SIGALRM) that
raises inside the computation; the budget then ends as one SceneError line. The timer repeats
(every RETRY_S after the budget) until the block has ended: an exception raised while Python runs
a finaliser or a weakref callback is printed and dropped, and a one-shot timer would then let the
work run on forever. Where no timer can be
armed (not the main thread, or a platform without setitimer) the work runs unbounded in time, still
bounded in size by the parser's limits (derive/expr_parse.py) and the expression plate's operation
budget (derive/plate_fields/expression.py).
"""
from __future__ import annotations

import signal
import threading
import time
from contextlib import contextmanager

from levitron.scene.checks import SceneError


RETRY_S = 0.05


class _OutOfTime(BaseException):
    """Raised by the timer; a BaseException so that no `except Exception` inside sympy hides it."""


@contextmanager
def time_budget(seconds: float, what: str):
    """Run the block within `seconds` of wall time, else raise SceneError(f"{what} ...")."""
    if threading.current_thread() is not threading.main_thread() or not hasattr(signal, "setitimer"):
        yield
        return

    over = []          # set once the block has ended: a late tick must not raise again

    def _alarm(signum, frame):
        if not over:
            raise _OutOfTime

    old = signal.signal(signal.SIGALRM, _alarm)
    t0 = time.monotonic()
    signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3), RETRY_S)
    try:
        yield
    except _OutOfTime:
        over.append(True)
        raise SceneError(f"{what} took more than {seconds:g} s of symbolic work "
                         f"({time.monotonic() - t0:.1f} s): simplify it") from None
    finally:
        over.append(True)
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
