"""A design's other points on its answer's fresh draws, paired with the answer launch by launch.

A design by the launch odds (runtime/design/launch_design.py) decides its answer on a fresh seed,
all n launches, with the answer's Wilson interval. Two more kinds of point are then read on the
same fresh draws, and each differs from the answer only in the launches the step between them
decides, so each is measured by its paired difference, not by binomial noise of its own:

- **a side** (the sharpness's +- a maker's tolerance, trim's widest window): its first
  min(n, SIDE_N) launches (`paired_side`);
- **the start** (the scene as written): in BATCHES batches, stopped as soon as the paired
  difference decides (`start_odds`, McNemar's test as paired_odds.py stops a search point:
  |b - c| >= MIN_DISCORDANT and |b - c| > Z_STOP sqrt(b + c)), so that a change the search found
  is shown on a few hundred launches, not n; where nothing decides it runs all n and gives its own
  Monte Carlo's odds, the ones `levitron launch` gives there. Where the answer is the start itself
  (no change), the answer's own odds, run once.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from levitron.runtime.design.paired_odds import BATCHES, MIN_DISCORDANT, Z_STOP, in_batches, variant
from levitron.runtime.errors import UserError
from levitron.runtime.model.scenes import SceneRef
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan.launch_answer import LaunchOdds
from levitron.runtime.scan.launch_summary import Z95


def paired_side(answer: dict, side: dict) -> dict:
    """A neighbour's odds from its first m launches on the answer's fresh draws (module docstring):
    the answer's odds plus the paired difference (b - c) / m over those m launches (b float at the
    neighbour only, c at the answer only). Unbiased, and far less noisy than m launches alone: the
    two differ in the launches the step between them decides. Its 95 % interval joins the answer's
    Wilson interval and the difference's normal one in quadrature. answer: a Monte Carlo's answer
    (probability, probability_ci95, verdicts); side: the neighbour's (or a refusal with its
    reason: probability 0)."""
    m = side["n"]
    if side.get("reason"):
        return {"probability": 0.0, "probability_ci95": [0.0, 0.0], "n": m, "seed": side["seed"],
                "reason": side["reason"]}
    here = np.array([bool(v) for v in side["verdicts"][:m]])
    there = np.array([bool(v) for v in answer["verdicts"][:m]])
    b, c = int(np.sum(here & ~there)), int(np.sum(~here & there))
    d = (b - c) / m
    sd = np.sqrt(max(0.0, (b + c) / m - d * d) / m)
    p = float(min(1.0, max(0.0, answer["probability"] + d)))
    lo, hi = answer["probability_ci95"]
    down = float(np.hypot(answer["probability"] - lo, Z95 * sd))
    up = float(np.hypot(hi - answer["probability"], Z95 * sd))
    return {"probability": p, "probability_ci95": [max(0.0, p - down), min(1.0, p + up)], "n": m,
            "seed": side["seed"], "paired_with": "the answer's first launches"}


def decided(here: np.ndarray, there: np.ndarray) -> bool:
    """Whether paired verdicts tell two designs apart (McNemar, the module docstring's test)."""
    b, c = int(np.sum(here & ~there)), int(np.sum(~here & there))
    return abs(b - c) >= MIN_DISCORDANT and abs(b - c) > Z_STOP * math.sqrt(b + c)


def start_odds(ref: SceneRef, keys: Sequence[str], x, answer: dict, request: mc.Request, pool=None,
               tick=None) -> dict:
    """The start's odds on the answer's fresh draws `request` (module docstring): the paired
    estimate once the difference decides (`n` the launches run, `successes` the start's own among
    them, `paired_with`), else the start's own Monte Carlo of all n launches; a start where the top
    cannot hover (or the run is refused) floats never: probability 0 with the reason. answer: the
    answer's Monte Carlo (probability, probability_ci95, verdicts); tick(k): k launches done or
    skipped; pool: a runners.KeptPool."""
    from levitron.runtime.scan.runners import model_for
    r, tick = request, tick or (lambda k=1: None)
    n = int(r.n)
    try:
        model = model_for(*variant(ref, keys, x))
        prep = mc.prepare(model, r.given, n, r.seed, r.success_time, r.t_end, r.integrator, r.tol,
                          r.workers, r.scheduler, warn=False)
    except UserError as exc:
        tick(n)
        return {"probability": 0.0, "probability_ci95": [0.0, 0.0], "n": n, "seed": r.seed,
                "successes": 0, "reason": str(exc)}
    there = np.array([bool(v) for v in answer["verdicts"][:n]])
    results, a = [], 0
    for b, floats in in_batches(prep, model, BATCHES, results, pool):
        tick(b - a)
        a = b
        if b < n and decided(floats[:b], there[:b]):
            tick(n - b)
            side = paired_side(answer, {"n": b, "seed": r.seed, "verdicts": floats[:b]})
            return {**side, "successes": int(floats[:b].sum()), "paired_with": f"the answer's first {b} launches"}
    try:
        odds = LaunchOdds.of(mc.summarize(prep.plan, results, prep.success_time, prep.interval, prep.z_s,
                                          prep.tau, prep.given, prep.warnings), model)
    except UserError as exc:            # no launch got a verdict (every one up past its window)
        return {"probability": 0.0, "probability_ci95": [0.0, 0.0], "n": n, "seed": r.seed,
                "successes": 0, "reason": str(exc)}
    return {name: odds[name] for name in ("probability", "probability_ci95", "n", "seed", "successes")}
