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

A counted task opened inside a stage (the report's launch odds: a Monte Carlo, quiet or not) is that
stage's progress: the stage shows its count, "report thesis_air: launch odds 5/5: launch 120/200",
and an ETA that moves with it (the rest of this stage by the task's own pace, the stages after it by
the pace of those before), on a terminal in the stage's bar and off one in a line at most every
LOG_EVERY seconds. On a terminal a row without a count (the CLI's spinner) yields to the rows opened
inside it.
"""
from __future__ import annotations

import contextlib
import os
import sys
import time

_state: dict = {"enabled": True, "bar": None, "stage": None}
LOG_EVERY = 10.0     # s: off a terminal, a count inside a stage writes its line at most this often


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
            if "eta" in task.fields:          # a stage's: its own estimate, counting down between updates
                eta, at = task.fields["eta"]
                left = f", eta {hms(max(0.0, eta - (time.monotonic() - at)))}" if eta is not None else ""
                return Text(text + left, style="progress.elapsed")
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
    Tasks opened inside another share its display (one line each; a spinner yields its line). quiet:
    no display of its own (inside a stage, a counted task is the stage's progress: module
    docstring). log_every (seconds): off a terminal, a line of the count and the ETA at most that often."""
    stage = _state["stage"]
    if stage is not None and total and stage.inner is None:
        with stage.adopt(description, total, log_every) as tick:
            yield tick
        return
    with _row(description, total, quiet, log_every) as tick:
        yield tick


@contextlib.contextmanager
def _row(description: str, total: int | None, quiet: bool, log_every: float | None):
    """task() outside a stage: a row of the terminal's bar, timed lines off it, or nothing."""
    if quiet or not active():
        if not quiet and total and log_every and lines_allowed():
            yield _timed_lines(description, total, log_every)
        else:
            yield _noop
        return
    outer = _state["bar"]
    if outer is not None:
        hidden = [t.id for t in outer.tasks if t.visible and not t.total]    # spinners yield
        for tid in hidden:
            outer.update(tid, visible=False)
        tid = outer.add_task(description, total=total)
        try:
            yield lambda n=1: outer.advance(tid, n)
        finally:
            outer.remove_task(tid)
            for t in hidden:
                if t in outer.task_ids:
                    outer.update(t, visible=True)
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


class _Stages:
    """An open `stages` step: which stage runs, the counted task inside it (`adopt`), and what shows
    them: a row of the terminal's bar (`bar`, `tid`) or lines on stderr."""

    def __init__(self, description: str, names: list, weights: list, bar=None, tid=None):
        self.description, self.names, self.w = description, names, weights
        self.total, self.start = sum(weights), time.monotonic()
        self.bar, self.tid = bar, tid
        self.i, self.began, self.inner = -1, self.start, None

    def label(self, i: int) -> str:
        return f"{self.description}: {self.names[i]} {i + 1}/{len(self.names)}"

    def eta(self, fraction: float | None = None, since: float = 0.0) -> float | None:
        """Seconds left: the rest of stage i by the pace of the counted task begun at `since`
        (fraction: its share done), the stages after it by the pace of those before it (or, before
        any, of the step so far)."""
        now, i = time.monotonic(), max(self.i, 0)
        before, after = sum(self.w[:i]), sum(self.w[i + 1:])
        if fraction is None:            # no count inside: the step's pace by the weights
            done = before
            return (now - self.start) / done * (self.total - done) if done >= 0.1 * self.total else None
        if fraction <= 0:
            return None
        here = (now - since) / fraction * (1 - fraction)
        per_weight = (self.began - self.start) / before if before > 0 else \
            (now - self.start) / (before + fraction * self.w[i])
        return here + after * per_weight

    def begin(self, i) -> None:
        i = self.names.index(i) if isinstance(i, str) else int(i)
        self.i, self.began = i, time.monotonic()
        if self.bar is not None:
            self.bar.update(self.tid, completed=sum(self.w[:i]), description=self.label(i),
                            eta=(self.eta(), time.monotonic()))
            return
        elapsed = time.monotonic() - self.start
        eta = self.eta()
        print(f"levitron: {self.label(i)} ({_hms(elapsed)} elapsed"
              + (f", eta {_hms(eta)})" if eta is not None else ")"), file=sys.stderr, flush=True)

    @contextlib.contextmanager
    def adopt(self, description: str, total: int, log_every: float | None):
        """A counted task inside the current stage: its count and pace are the stage's."""
        i, since = max(self.i, 0), time.monotonic()
        state = {"done": 0, "last": since}
        every = LOG_EVERY if log_every is None else log_every
        self.inner = description

        def tick(n: int = 1) -> None:
            state["done"] += n
            now, done = time.monotonic(), state["done"]
            fraction = min(1.0, done / total)
            text = f"{self.label(i)}: {description} {done}/{total}"
            eta = self.eta(fraction, since)
            if self.bar is not None:
                if self.tid in self.bar.task_ids:
                    completed = max(self.bar.tasks[self.bar.task_ids.index(self.tid)].completed,
                                    sum(self.w[:i]) + fraction * self.w[i])
                    self.bar.update(self.tid, completed=completed, description=text, eta=(eta, now))
            elif now - state["last"] >= every and done < total:
                state["last"] = now
                print(f"levitron: {text} ({_hms(now - self.start)} elapsed"
                      + (f", eta {_hms(eta)})" if eta is not None else ")"), file=sys.stderr, flush=True)
        try:
            yield tick
        finally:
            self.inner = None
            if self.bar is not None and self.tid in self.bar.task_ids and self.i == i:
                self.bar.update(self.tid, description=self.label(i))


@contextlib.contextmanager
def stages(description: str, names, weights=None, quiet: bool = False):
    """A slow step in named stages; yields stage(i) (or stage(name)) to call as stage i begins.
    weights: the stages' expected shares of the time (default equal), for the ETA. On a terminal
    a bar ("deriving: Hamilton's equations 3/7 ... eta"); off one, when progress is on, one line per
    stage on stderr, a note like the CLI's others: "levitron: deriving: Hamilton's equations 3/7 (0:12
    elapsed, eta 0:30)". A counted task inside a stage shows there (module docstring)."""
    names = list(names)
    w = [float(x) for x in (weights or [1.0] * len(names))]
    if quiet or not lines_allowed():
        yield lambda i: None
        return
    outer = _state["stage"]
    if active():
        with _row(description, sum(w), False, None):
            bar = _state["bar"]
            group = _Stages(description, names, w, bar, bar.tasks[-1].id if bar is not None else None)
            if bar is not None:
                bar.update(group.tid, eta=(None, time.monotonic()))
            _state["stage"] = group
            try:
                yield group.begin
            finally:
                _state["stage"] = outer
        return
    group = _state["stage"] = _Stages(description, names, w)
    try:
        yield group.begin
    finally:
        _state["stage"] = outer


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
