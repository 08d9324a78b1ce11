"""The one progress helper: a rich progress bar with an ETA on stderr, never on stdout.

    with progress.task("scan", total=N) as tick:
        for ...:
            ...
            tick()            # one step done (tick(k) for k steps)

    with progress.stages("deriving", ["the plate", "Hamilton's equations", ...]) as stage:
        stage(0)          # "deriving: the plate 1/7", with an ETA from the stages' weights
        ...

It shows nothing when progress is off: `progress.disable()` (the CLI calls it for --json and
--quiet), LEVITRON_PROGRESS=0, or stderr not a terminal (a log file, a pipe, a test). The setting is
per process: worker processes never draw (their stderr is the parent's, and only the parent ticks).
Stages are the exception to "not a terminal": a slow step of named stages (a derivation, a
compilation, the figures) writes one line per stage on stderr there, so a log is not silent for a
minute; on a terminal they are the bar's description.
"""
from __future__ import annotations

import contextlib
import os
import sys
import time

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


def _timed_lines(description: str, total: int, every: float):
    """tick(n) that, off a terminal, writes "levitron: scan: 120/1000 (0:10 elapsed, eta 1:20)"
    on stderr at most once per `every` seconds, the first after `every` seconds: a long step is
    not silent in a log, a short one writes nothing."""
    start = time.monotonic()
    state = {"done": 0, "last": start}

    def tick(n: int = 1) -> None:
        state["done"] += n
        now = time.monotonic()
        if now - state["last"] >= every and state["done"] < total:
            state["last"] = now
            done, elapsed = state["done"], now - start
            print(f"levitron: {description}: {done}/{total} ({_hms(elapsed)} elapsed, eta "
                  f"{_hms(elapsed / done * (total - done))})", file=sys.stderr, flush=True)
    return tick


@contextlib.contextmanager
def task(description: str, total: int | None = None, quiet: bool = False,
         log_every: float | None = None):
    """A progress bar for `total` steps (None: a spinner with elapsed time); yields tick(n=1).
    Tasks opened inside another share its display (one line each). quiet: none at all.
    log_every (seconds): off a terminal, a line of the count and the ETA at most that often."""
    if quiet or not active():
        if not quiet and total and log_every and lines_allowed():
            yield _timed_lines(description, total, log_every)
        else:
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


def _hms(t: float) -> str:
    t = int(t)
    return f"{t // 60}:{t % 60:02d}" if t < 3600 else f"{t // 3600}:{t // 60 % 60:02d}:{t % 60:02d}"


def lines_allowed() -> bool:
    """Stage lines off a terminal: progress enabled and LEVITRON_PROGRESS not 0."""
    return _state["enabled"] and os.environ.get("LEVITRON_PROGRESS", "1") != "0"


@contextlib.contextmanager
def stages(description: str, names, weights=None, quiet: bool = False):
    """A slow step in named stages; yields stage(i) (or stage(name)) to call as stage i begins.
    weights: the stages' expected shares of the time (default equal), for the ETA. On a terminal
    a bar ("deriving: Hamilton's equations 3/7 ... eta"); off one, when progress is on, one line per
    stage on stderr, a note like the CLI's others: "levitron: deriving: Hamilton's equations 3/7 (0:12
    elapsed, eta 0:30)"."""
    names = list(names)
    w = [float(x) for x in (weights or [1.0] * len(names))]
    total, start = sum(w), time.monotonic()
    n = len(names)
    if quiet or not lines_allowed():
        yield lambda i: None
        return

    def label(i: int) -> str:
        return f"{description}: {names[i]} {i + 1}/{n}"

    def index(i) -> int:
        return names.index(i) if isinstance(i, str) else int(i)

    if active():
        with task(label(0), total=total) as tick:
            bar = _state.get("bar")
            seen = {"i": -1}

            def stage(i) -> None:
                i = index(i)
                if seen["i"] >= 0:
                    tick(sum(w[seen["i"]:i]))
                seen["i"] = i
                if bar is not None and bar.tasks:
                    bar.update(bar.tasks[-1].id, description=label(i))
            yield stage
        return

    def stage(i) -> None:
        i = index(i)
        elapsed = time.monotonic() - start
        done = sum(w[:i])
        eta = f", eta {_hms(elapsed / done * (total - done))}" if done >= 0.1 * total else ""
        print(f"levitron: {label(i)} ({_hms(elapsed)} elapsed{eta})", file=sys.stderr, flush=True)
    yield stage


def track(items, description: str, stage=None):
    """Iterate over a sized sequence with a progress bar (task() around a for loop). stage(item):
    a name for each item; the items are then stages (a line each off a terminal, see stages)."""
    items = list(items)
    if stage is None:
        with task(description, total=len(items)) as tick:
            for item in items:
                yield item
                tick()
        return
    with stages(description, [stage(it) for it in items]) as begin:
        for k, item in enumerate(items):
            begin(k)
            yield item
