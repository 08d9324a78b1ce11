"""Adaptive repeats for the benchmarks: time a call until its minimum is stable.

`best_of(fn)` calls fn() (which returns its own wall time in s, or None to time the call here) at
least `min_runs` times, then stops once the last `patience` runs did not lower the minimum by more
than `rtol` of it, or `max_runs` runs or `budget_s` seconds are spent. A run whose minimum settles
at once costs min_runs + patience calls, a noisy one more, a slow one never more than the budget.
"""
from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass


@dataclass(frozen=True)
class Timing:
    best: float          # the minimum wall time, s
    runs: int            # how many calls were timed
    spent: float         # their total wall time, s
    stable: bool         # stopped because the minimum settled (not by max_runs or the budget)


def best_of(fn: Callable[[], float | None], min_runs: int = 2, patience: int = 2, rtol: float = 0.02,
            max_runs: int = 100, budget_s: float = 2.0) -> Timing:
    """The minimum of repeated timed calls of fn, repeated until it is stable (module docstring)."""
    best, runs, spent, quiet = float("inf"), 0, 0.0, 0
    while True:
        t0 = time.perf_counter()
        own = fn()
        wall = own if own is not None else time.perf_counter() - t0
        runs += 1
        spent += wall
        quiet = quiet + 1 if wall >= best * (1 - rtol) else 0
        best = min(best, wall)
        if runs >= min_runs and quiet >= patience:
            return Timing(best, runs, spent, True)
        if runs >= max_runs or spent >= budget_s:
            return Timing(best, runs, spent, False)
