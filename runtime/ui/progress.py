"""The one progress helper: a rich progress bar with an ETA on stderr, never on stdout.

    with progress.task("scan", total=N) as tick:
        for ...:
            ...
            tick()            # one step done (tick(k) for k steps)

It shows nothing when progress is off: `progress.disable()` (the CLI calls it for --json and
--quiet), LEVITRON_PROGRESS=0, or stderr not a terminal (a log file, a pipe, a test). The setting is
per process: worker processes never draw (their stderr is the parent's, and only the parent ticks).
"""
from __future__ import annotations

import contextlib
import os
import sys

_state = {"enabled": True}


def disable() -> None:
    """Turn progress off for this process (--json, --quiet)."""
    _state["enabled"] = False


def enable() -> None:
    _state["enabled"] = True


def active() -> bool:
    """True when a bar would be drawn: enabled, LEVITRON_PROGRESS not 0, stderr a terminal."""
    if not _state["enabled"] or os.environ.get("LEVITRON_PROGRESS", "1") == "0":
        return False
    if _state.get("bar") is not None:     # a bar is drawn (rich then wraps sys.stderr)
        return True
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


def _count_column():
    from rich.progress import ProgressColumn
    from rich.text import Text

    class Count(ProgressColumn):
        """"3/12, 0:00:04 elapsed, eta 0:00:12" with a total, else the elapsed time."""

        def render(self, task):
            def hms(t):
                t = int(t or 0)
                return f"{t // 3600}:{t // 60 % 60:02d}:{t % 60:02d}"
            text = f"{hms(task.elapsed)} elapsed"
            if task.total:
                eta = f", eta {hms(task.time_remaining)}" if task.time_remaining is not None else ""
                text = f"{int(task.completed)}/{int(task.total)}, {text}{eta}"
            return Text(text, style="progress.elapsed")

    return Count()


def _noop(n: int = 1) -> None:
    return None


@contextlib.contextmanager
def task(description: str, total: int | None = None, quiet: bool = False):
    """A progress bar for `total` steps (None: a spinner with elapsed time); yields tick(n=1).
    Tasks opened inside another share its display (one line each). quiet: none at all."""
    if quiet or not active():
        yield _noop
        return
    outer = _state.get("bar")
    if outer is not None:
        tid = outer.add_task(description, total=total)
        try:
            yield lambda n=1: outer.advance(tid, n)
        finally:
            outer.remove_task(tid)
        return
    from rich.console import Console
    from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn
    columns = [SpinnerColumn(), TextColumn("[bold]{task.description}"), BarColumn(), _count_column()]
    with Progress(*columns, console=Console(file=sys.stderr), transient=True) as bar:
        _state["bar"] = bar
        tid = bar.add_task(description, total=total)
        try:
            yield lambda n=1: bar.advance(tid, n)
        finally:
            _state["bar"] = None


def track(items, description: str):
    """Iterate over a sized sequence with a progress bar (task() around a for loop)."""
    items = list(items)
    with task(description, total=len(items)) as tick:
        for item in items:
            yield item
            tick()
