"""A design point's launch odds by paired comparison: stop a Monte Carlo once it is clearly worse.

A design by the launch odds (runtime/design/launch_design.py) runs, at every design point x, the
Monte Carlo of runtime/scan/launch_odds.py on the same draws (common random numbers): launch i
has the same spin, tilt, offset, ... at every x, so two points' verdicts pair launch by launch,
and their difference is decided by the launches where they disagree (a few in a hundred between
neighbours), not by the binomial noise of either.

So a point is run in BATCHES batches of launches (indices in order). After each batch but the last
its verdicts are compared with the best point so far (the incumbent) on the same launches:
b launches float at x and fall at the incumbent, c the other way round. The point is stopped
as worse when

    c - b > Z_STOP sqrt(b + c)   and   c - b >= MIN_DISCORDANT     (McNemar's paired test)

or when it cannot reach the incumbent's successes even if all its remaining launches float. A
stopped point's odds are the paired estimate p_incumbent + (b - c) / launches run, below the
incumbent's by construction; it is marked `stopped_early`. A point that runs every batch gets the
Monte Carlo's own answer (the one `levitron launch` gives at the same keys and seed) and becomes
the incumbent when it floats more often. The false-stop rate of one look at Z_STOP = 3 is about
1e-3 for a point as good as the incumbent; the search's best is then judged again on fresh draws
(launch_design.py step 4), which early stopping never touches.

Points closer than RESOLUTION of the box's width in every key are one point (a grid and its zoom
can land one float step apart): the second is not run again.

The best points are a set, not one point: a point that ran every batch is level with the
incumbent (`level`) when the incumbent floats in at most Z_LEVEL sqrt(b + c) (and fewer than
MIN_DISCORDANT) more of their paired launches than it does. Neighbours on a broad optimum differ
by single launches, which no answer should follow; the design takes the middle of the level set,
the point farthest from the cliffs (launch_design.py step 3).
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.model.scenes import SceneRef
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan.launch_window import WindowJudge
from levitron.runtime.scan.launch_answer import LaunchOdds

BATCHES = 4
Z_STOP = 3.0
MIN_DISCORDANT = 4
Z_LEVEL = 2.0
RESOLUTION = 1e-9


def variant(ref: SceneRef, keys: Sequence[str], x) -> SceneRef:
    """The recipe of the design at the scene keys x: the scene's overrides, then keys = x."""
    return ref.with_overrides(f"{k}={float(v)!r}" for k, v in zip(keys, x))


def in_batches(prep: mc.Prepared, model, batches: int, results: list, pool=None):
    """Run a prepared Monte Carlo's launches in `batches` batches (indices in order), appending the
    chunks' results to `results` and yielding after each batch (launches done, floats so far:
    launch index -> floated, False for those not yet run); a launch up past its window is no
    verdict, as in launch. The caller stops when its paired test decides (the module docstring;
    paired_fresh.py)."""
    n = prep.plan.n
    edges = np.linspace(0, n, batches + 1).round().astype(int)
    floats = np.zeros(n, bool)
    judge, spins = WindowJudge(model, prep.interval), mc.samples(prep.plan)["spin"]
    for a, b in zip(edges[:-1], edges[1:]):
        if b <= a:
            continue
        got = mc.execute(prep, model, range(a, b), quiet=True, pool=pool)
        judge.mark(spins, prep.success_time, got)
        results += got
        for i, ok in prep.floats(p for g in got for p in g["points"]).items():
            floats[i] = ok
        yield int(b), floats


class PairedOdds:
    """The odds of design points on one launch request (common random numbers), each run against
    the incumbent as the module docstring says. `__call__(x)` -> the answer dict of a Monte Carlo
    (probability, probability_ci95, n, seed, successes; `reason` where the top cannot hover there;
    `stopped_early` and `launches_run` where it was stopped); `counts` the work done."""

    def __init__(self, ref: SceneRef, keys: Sequence[str], request: mc.Request, box, pool=None,
                 tick=None, early: bool = True):
        self.ref, self.keys, self.request, self.pool = ref, list(keys), request, pool
        self.span = [max(abs(hi - lo), 1e-300) for lo, hi in box]
        self.lo = [lo for lo, _ in box]
        self.tick = tick or (lambda k=1: None)
        self.early = early
        self.best: np.ndarray | None = None       # the incumbent's verdicts, launch by launch
        self.best_k = -1
        self.seen: dict[tuple, dict] = {}
        self.verdicts: dict[tuple, np.ndarray] = {}     # every fully run point's, launch by launch
        self.counts = {"evaluations": 0, "stopped_early": 0, "duplicates": 0, "launches_run": 0,
                       "launches_full": 0, "launches_per_point": int(request.n)}

    def key(self, x) -> tuple:
        return tuple(round((float(v) - lo) / s / RESOLUTION) for v, lo, s in zip(x, self.lo, self.span))

    def __call__(self, x) -> dict:
        k = self.key(x)
        if k in self.seen:
            self.counts["duplicates"] += 1
            return self.seen[k]
        out = self._run(tuple(float(v) for v in x), k)
        self.seen[k] = out
        return out

    def level(self, x) -> bool:
        """Whether the point x (already run) is level with the incumbent (module docstring)."""
        here = self.verdicts.get(self.key(x))
        if here is None or self.best is None:
            return False
        b = int(np.sum(here & ~self.best))
        c = int(np.sum(~here & self.best))
        return c - b < MIN_DISCORDANT or c - b <= Z_LEVEL * math.sqrt(b + c)

    def _run(self, x: tuple, k: tuple) -> dict:
        from levitron.runtime.scan.runners import model_for
        r = self.request
        n = r.n
        self.counts["evaluations"] += 1
        self.counts["launches_full"] += n
        try:
            model = model_for(*variant(self.ref, self.keys, x))
            prep = mc.prepare(model, r.given, n, r.seed, r.success_time, r.t_end, r.integrator, r.tol,
                              r.workers, r.scheduler, warn=False)     # a point's odds: no one reads its warnings
        except UserError as exc:
            self.tick(n)
            return {"probability": 0.0, "probability_ci95": [0.0, 0.0], "n": n, "seed": r.seed,
                    "successes": 0, "reason": str(exc)}
        results, floats, a = [], np.zeros(n, bool), 0
        for b, floats in in_batches(prep, model, BATCHES if self.early else 1, results, self.pool):
            self.counts["launches_run"] += b - a
            self.tick(b - a)
            a = b
            if b < n and self._worse(floats, b, n):
                self.counts["stopped_early"] += 1
                self.tick(n - b)
                return self._stopped(floats, b, n)
        odds = LaunchOdds.of(mc.summarize(prep.plan, results, prep.success_time, prep.interval, prep.z_s,
                                             prep.tau, prep.given, prep.warnings), model)
        out = {name: odds[name] for name in ("probability", "probability_ci95", "n", "seed", "successes")}
        self.verdicts[k] = floats
        if self.best is None or odds["successes"] > self.best_k:
            self.best, self.best_k = floats, odds["successes"]
        return out

    def _worse(self, floats: np.ndarray, done: int, n: int) -> bool:
        """The stopping rule of the module docstring on the first `done` launches."""
        if self.best is None:
            return False
        here, there = floats[:done], self.best[:done]
        b = int(np.sum(here & ~there))
        c = int(np.sum(~here & there))
        if int(here.sum()) + (n - done) < self.best_k:
            return True
        return c - b >= MIN_DISCORDANT and c - b > Z_STOP * math.sqrt(b + c)

    def _stopped(self, floats: np.ndarray, done: int, n: int) -> dict:
        b = int(np.sum(floats[:done] & ~self.best[:done]))
        c = int(np.sum(~floats[:done] & self.best[:done]))
        p = max(0.0, self.best_k / n + (b - c) / done)
        return {"probability": p, "probability_ci95": [None, None], "n": n, "seed": self.request.seed,
                "successes": None, "stopped_early": True, "launches_run": done}
