"""Child processes die with their parent, and a command stops when asked, cleaning up as it goes.

`die_with_parent` is the preexec_fn of the runtime's children (the derive subprocess, the C
compiler) and the first call of a scan's worker: on Linux prctl(PR_SET_PDEATHSIG, SIGKILL) makes
the kernel kill the child when the parent dies, however it dies (kill -9 too), so no orphaned
derivation goes on writing into the cache.

`stop_on_signals` is the one stop path of the command line: SIGINT and SIGTERM (what `timeout` and
most supervisors send) both raise KeyboardInterrupt in the main thread, so the `finally` blocks run
(temporaries removed, worker pools terminated: runtime/scan/runners.py) and the CLI exits 128 +
the signal's number. A long call into a library that checks for signals itself and turns the
interruption into an error of its own (CasADi's CVODES: "rhs failed: KeyboardInterrupt", a
RuntimeError its caller may read as "no orbit here") does not swallow the stop: the interruption
is raised again at the next line of Python that runs outside the cleanup of one (a trace function,
armed by the signal until the CLI has the stop: a bare `except:` in a library does not swallow it
either), the signal is delivered again every REDELIVER_S (ignored while a KeyboardInterrupt is being
cleaned up after), and STOP_GRACE_S after the first signal the process ends regardless.
From the signal until the stop is handled (`stopped`), sys.stderr is dropped: what a library
prints as it is interrupted (CasADi: its failure and a dump of the function's inputs, a hundred
lines) is not shown; LEVITRON_DEBUG=1 shows everything.
"""
from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import io
import os
import signal
import sys
import threading
import time

PR_SET_PDEATHSIG = 1
# resolved here, in the parent: the child between fork and exec only calls it (no dlopen, no
# allocation that could wait on a lock another thread of the parent held at the fork)
_PRCTL = ctypes.CDLL(ctypes.util.find_library("c") or None).prctl if sys.platform.startswith("linux") \
    else None

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
REDELIVER_S = 0.25    # a stop not yet on its way (swallowed in C code) is raised again this often
STOP_GRACE_S = 4.0    # after the first stop signal the process ends within this, cleaned up or not


def die_with_parent() -> None:
    """In a child before exec: ask for SIGKILL when the parent dies (Linux; elsewhere nothing)."""
    if _PRCTL is not None:
        _PRCTL(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)


def ignore_interrupts() -> None:
    """In a worker process: Ctrl-C (sent to the terminal's whole process group) is its parent's to
    handle; the parent ends its workers (runtime/scan/runners.py), none prints a traceback."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def end_pool(executor) -> None:
    """End a concurrent.futures ProcessPoolExecutor's workers at once (SIGKILL): on an interruption
    or an error the command does not wait behind the chunks in flight (shutdown(wait=True) would, a
    minute and more), and no worker runs on. (Python 3.14's kill_workers; ._processes before it.)
    Before 3.14 it also waits (at most a second) for the pool's manager thread: it closes its wake-up
    pipe as it ends, and an exit racing that close printed "Exception ignored ... Bad file
    descriptor" from concurrent.futures' exit hook (3.11 has no lock there; CPython added one
    later, gh-125451)."""
    kill = getattr(executor, "kill_workers", None)
    if kill is not None:
        kill()
        return
    workers = list((getattr(executor, "_processes", None) or {}).values())
    manager = getattr(executor, "_executor_manager_thread", None)    # shutdown(wait=False) drops it
    for proc in workers:
        with contextlib.suppress(OSError, ValueError):
            proc.kill()
    executor.shutdown(wait=False, cancel_futures=True)
    for proc in workers:
        with contextlib.suppress(OSError, ValueError, AssertionError):
            proc.join(1.0)
    if manager is not None and manager is not threading.current_thread():
        manager.join(1.0)


def ending_on_error(executor, then=None):
    """An exit callback (contextlib.ExitStack.push) for a block that uses `executor`: leaving it by
    an exception (KeyboardInterrupt too) ends the workers at once (end_pool), then calls then()."""
    def leave(kind, *_) -> None:
        if kind is not None:
            end_pool(executor)
            if then is not None:
                then()
    return leave


# signum: the first stop signal; handled: the CLI caught it; over: outside stop_on_signals;
# frames, trace: the armed frames and the trace function before; stderr, dropped: stderr's swap
_stop: dict = {"signum": None, "handled": False, "over": True, "frames": [], "trace": None}


def stop_signal() -> int | None:
    """The signal that asked this command to stop (SIGINT, SIGTERM), or None."""
    return _stop["signum"]


def exit_code(default: int = 130) -> int:
    """128 + the stop signal's number (130 for SIGINT, 143 for SIGTERM); `default` without one."""
    return 128 + _stop["signum"] if _stop["signum"] is not None else default


def _disarm() -> None:
    for frame in _stop["frames"]:
        frame.f_trace = None
    _stop["frames"] = []
    sys.settrace(_stop["trace"])
    _stop["trace"] = None


def _cleaning_up() -> bool:
    """Whether the main thread is handling a KeyboardInterrupt (an except or finally block on its
    way out, or a function called from one): the stop is on its way; let it clean up."""
    return isinstance(sys.exc_info()[1], KeyboardInterrupt)


def _tracer(frame, event, arg):
    """Armed by a stop signal until the CLI has it: any event of Python code that is not a
    KeyboardInterrupt on its way or its cleanup raises one (the stop was swallowed: by a
    library's bare `except:`, or turned into its own error)."""
    if _stop["over"] or _stop["handled"]:
        _disarm()
        return None
    if event == "exception" and issubclass(arg[0], KeyboardInterrupt) or _cleaning_up():
        return _tracer
    if event == "return":         # a value handed back (to C code, perhaps): at the next event instead
        return _tracer
    raise KeyboardInterrupt


def _on_signal(signum, frame) -> None:
    if _stop["over"] or _stop["handled"] or _cleaning_up():    # reported, ended, or on its way
        return
    if _stop["signum"] is None:
        _stop["signum"] = signum
        if os.environ.get("LEVITRON_DEBUG", "") in ("", "0"):      # a stream in C: CasADi writes
            _stop["stderr"] = sys.stderr                                # with an exception set
            sys.stderr = _stop["dropped"] = io.StringIO()
        threading.Thread(target=_watchdog, args=(signum, time.monotonic()), daemon=True,
                         name="levitron-stop").start()
    if not _stop["frames"]:      # arm: the frames on the stack and the ones to come
        _stop["trace"] = sys.gettrace()
        f = frame
        while f is not None:
            f.f_trace = _tracer
            _stop["frames"].append(f)
            f = f.f_back
        sys.settrace(_tracer)
    raise KeyboardInterrupt


def _watchdog(signum: int, start: float) -> None:
    """Deliver the signal again every REDELIVER_S until the CLI has it (a stop that C code
    swallowed and no Python line has run since; the handler ignores it during the cleanup), and
    end the process STOP_GRACE_S after the first signal."""
    main, again = threading.main_thread(), start + REDELIVER_S
    while not _stop["over"]:
        time.sleep(0.05)
        now = time.monotonic()
        if _stop["over"]:
            return
        if now - start >= STOP_GRACE_S:
            os.write(2, f"levitron: still running {STOP_GRACE_S:g} s after the signal to stop: ending "
                     "without its cleanup\n".encode())
            os._exit(128 + signum)
        if now >= again and not _stop["handled"]:
            again += REDELIVER_S
            signal.pthread_kill(main.ident, signum)


def _speak_again() -> None:
    """stderr back, after the stop's silence (module docstring), unless another hand (a progress bar
    ending) has put its own back meanwhile."""
    saved, quiet = _stop.pop("stderr", None), _stop.pop("dropped", None)
    if quiet is not None:
        if sys.stderr is quiet:
            sys.stderr = saved
        quiet.close()


def stopped() -> None:
    """The stop (or an error it caused) has reached the CLI's handler: no more raises, stderr back."""
    if _stop["signum"] is None:
        return
    _stop["handled"] = True
    if _stop["frames"]:
        _disarm()
    _speak_again()


@contextlib.contextmanager
def stop_on_signals():
    """Inside the block (in the main thread) SIGINT and SIGTERM raise KeyboardInterrupt, as the
    module's docstring says; the handlers before it are restored after it (a test calling the CLI
    in-process keeps its own)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    old = {s: signal.signal(s, _on_signal) for s in STOP_SIGNALS}
    _stop.update(signum=None, handled=False, over=False, frames=[], trace=None)
    try:
        yield
    finally:
        _stop["over"] = True
        if _stop["frames"]:
            _disarm()
        _speak_again()
        for s, handler in old.items():
            signal.signal(s, handler)
