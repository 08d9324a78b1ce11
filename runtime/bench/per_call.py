"""What one run costs a Python caller at one error bound: the per-call race of `levitron bench`
(runtime/bench/work_precision.py runs it on the rows of its sweep; docs/contract.md `bench`'s
`per_call`). Ours through the public API's prepared run (Study.propagator), heyoka's through its
own `propagate_until`, taking turns so that the machine's load hits all alike."""
from __future__ import annotations

import csv
import math
import time
from pathlib import Path

import numpy as np

from levitron.runtime.bench.operating_point import Setup
from levitron.runtime.integrate.run import integrate
from levitron.runtime.ui.atomic import open_text


PER_CALL_BOUND = 1e-9        # the error bound of the per-call race
PER_CALL_ROUNDS = 20         # rounds, each PER_CALL_CALLS calls of every contestant in turn ...
PER_CALL_CALLS = 50          # ... the minimum over all is kept (quick: 3 rounds)
# ... and rounds go on for at least this long (not in quick): this machine's core runs for 0.1-1 s
# at a time some 40 % slower, a whole run's minimum included (levitron's and heyoka's alike), and
# 20 rounds of a few-us run take 30 ms, which one such stretch holds whole
PER_CALL_SECONDS = 3.0
PER_CALL_CANDIDATES = 3      # each contestant's fastest rows within the bound that are timed so
# ... and its PER_CALL_LOOSEST loosest tolerances within the bound: the sweep times each row once
# in its turn, so a slow stretch of the machine can make the cheapest run (the loosest tolerance
# that meets the bound, for a method whose work grows as the tolerance tightens) look slow; square's
# taylor at 1e-8 (8 steps) once timed 10.8 us beside 7.2 us at 1e-13 and was left out of the race
PER_CALL_LOOSEST = 2
ADAPTIVE_C = ("dop853", "vern9", "taylor")


def race_candidates(rows: list, backend: str, integrator: str) -> list:
    """The rows of one contestant that per_call races: within PER_CALL_BOUND, its PER_CALL_LOOSEST
    loosest tolerances, then its PER_CALL_CANDIDATES fastest rows (wall_s), each once."""
    ok = [r for r in rows if r["backend"] == backend and r["integrator"] == integrator
          and r["status"] == "completed" and r["error"] <= PER_CALL_BOUND]
    both = sorted(ok, key=lambda r: -r["tol"])[:PER_CALL_LOOSEST] + \
        sorted(ok, key=lambda r: r["wall_s"])[:PER_CALL_CANDIDATES]
    return [r for k, r in enumerate(both) if r not in both[:k]]


def per_call(model, part_name: str, x0, su: Setup, scale, rows: list, quick: bool) -> dict:
    """What one run costs a Python caller at the error bound PER_CALL_BOUND, the whole call:

    ours    each adaptive C method at the tolerances of its PER_CALL_CANDIDATES fastest rows
            (wall_s) and its PER_CALL_LOOSEST loosest rows whose error is within the bound,
            through the public API's prepared run (Study.propagator:
            runtime/integrate/propagator.py, `prop.state[:] = x0; prop.propagate(t_end)`);
            the fastest call is kept, with the same run through integrate() beside it, and
            integrate's ctypes call alone (Result.wall_s: lev_integrate's nine arguments
            converted, and the C integration);
    heyoka  its fastest and loosest rows within the bound likewise, `ta.state[:] = X0; ta.time = 0;
            ta.propagate_until(t_end)`, the same pattern (state reset, as a loop would).

    The contestants take turns, PER_CALL_CALLS calls each per round, so a change of the machine's
    load hits all alike, for PER_CALL_ROUNDS rounds and at least PER_CALL_SECONDS, so that every
    contestant meets the machine at its fastest; each figure is the minimum over all its calls, in
    seconds."""
    from levitron.runtime.integrate.propagator import Propagator
    part = model.part(part_name)
    rounds = 3 if quick else PER_CALL_ROUNDS
    x0 = np.asarray(x0, float)

    def candidates(backend: str, integrator: str) -> list:
        return race_candidates(rows, backend, integrator)

    entries = []             # (contestant, row, run)
    for name in ADAPTIVE_C:
        for row in candidates("c", name):
            prop = Propagator(part, name, row["tol"], p=su.p, scale=scale)

            def run(prop=prop):
                prop.state[:] = x0
                prop.propagate(su.t_end)
            entries.append((name, row, run))
    for row in candidates("heyoka", "taylor"):
        entries.append(("heyoka", row, heyoka_call(model, part_name, x0, su, scale, row["tol"])))
    times = [math.inf] * len(entries)
    until, done = time.perf_counter() + (0.0 if quick else PER_CALL_SECONDS), 0
    while done < rounds or time.perf_counter() < until:
        for k, (_, _, run) in enumerate(entries):
            for _ in range(PER_CALL_CALLS):
                t0 = time.perf_counter()
                run()
                times[k] = min(times[k], time.perf_counter() - t0)
        done += 1
    runs: dict = {}          # contestant -> (its fastest row, its time)
    for (name, row, _), t in zip(entries, times):
        if name not in runs or t < runs[name][1]:
            runs[name] = (row, t)
    best = {name: t for name, (_, t) in runs.items()}
    out: dict = {"bound": PER_CALL_BOUND, "calls": done * PER_CALL_CALLS,
                 "candidates_per_contestant": {"fastest": PER_CALL_CANDIDATES, "loosest": PER_CALL_LOOSEST},
                 "contestants": {name: {"integrator": "taylor" if name == "heyoka" else name,
                                        "tol": row["tol"], "error": row["error"], "call_s": t}
                                 for name, (row, t) in runs.items()}}
    ours = [n for n in runs if n != "heyoka"]
    if ours:
        win = min(ours, key=lambda n: best[n])
        row = runs[win][0]
        kw = dict(method=win, tol=row["tol"], p=su.p, scale=scale, n_out=1)
        n = 50 if quick else 500
        out["ours"] = {"integrator": win, "tol": row["tol"], "error": row["error"],
                       "propagator_s": best[win],
                       "integrate_s": min(_timed(lambda: integrate(part, x0, su.t_end, **kw))
                                          for _ in range(n)),
                       "c_call_s": min(integrate(part, x0, su.t_end, **kw).wall_s for _ in range(n))}
    if "heyoka" in runs:
        import heyoka as hy
        hrow = runs["heyoka"][0]
        out["heyoka"] = {"tol": hrow["tol"], "error": hrow["error"],
                         "propagate_until_s": best["heyoka"], "version": hy.__version__}
    if "ours" in out and "heyoka" in out:
        out["heyoka_over_ours"] = out["heyoka"]["propagate_until_s"] / out["ours"]["propagator_s"]
    return out


def write_per_call(calls: dict, path: Path) -> None:
    """per_call's contestants as a table: one row each, the whole Python call in seconds."""
    with open_text(path, "«out»", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["contestant", "integrator", "tol", "error", "call_s", "error_bound"])
        for name, c in sorted(calls.get("contestants", {}).items(), key=lambda kv: kv[1]["call_s"]):
            w.writerow([name, c["integrator"], c["tol"], c["error"], c["call_s"], calls["bound"]])


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def heyoka_call(model, part_name: str, x0, su: Setup, scale, tol: float):
    """heyoka's run from Python at `tol` (its integrator from the disk cache, runtime/bench/heyoka.py)."""
    from levitron.derive.emit.heyoka import lowered_rhs, system
    from levitron.runtime.bench import heyoka as bench_heyoka
    key = bench_heyoka.cache_key(**bench_heyoka.expressions_key(model, part_name), part=part_name,
                                 scale=[float(v).hex() for v in scale], tol=float(tol).hex())
    X0 = np.asarray(x0, float) / scale
    ta, _, _ = bench_heyoka.integrator(lambda: system(lowered_rhs(model.scene, part_name), scale),
                                       X0, su.p, tol, key)
    t_end = float(su.t_end)

    def run():
        ta.state[:] = X0
        ta.time = 0.0
        ta.propagate_until(t_end)
    return run
