"""Design by the yield of a production run: the scene keys at which the most kits, trimmed by their
owners with the washers in the box, float a launch by hand (runtime/design/production.py).

1. **One hand and one production run for every design.** The launch spread is pinned at the scene
   as written (runtime/design/launch_design.py Pinned: the defaults that scale with the scene, the
   success time), and every design point draws the same kits, owners' curve launches and launches
   (common random numbers: production_yield's streams of one seed), so two points differ by the
   design, launch by launch.
2. **Grid, then zoom.** GRID[k] points a key over the --vary box (k keys), then ZOOM_GRID points a
   key over the two grid cells around the best; each point's yield on min(kits, SEARCH_KITS) kits.
   Where several points share the best yield the answer is the middle of them (launch_design's
   plateau_middle).
3. **Decide on fresh kits.** The yield at the answer and at the scene as written again, on the
   next seed's kits and launches, with their Wilson intervals, and the same kits as shipped (no
   washer) beside them: the search's own best is biased upwards, the fresh one is not.
4. **Say how sharp it is.** The yield at +- a maker's tolerance of each key on the answer's fresh
   kits, paired with the answer (paired_fresh.paired_side), and for two or three keys the ridge
   (runtime/design/sharpness.py).

The cost: (GRID[k]^k + ZOOM_GRID^k) evaluations of CURVE_POINTS x CURVE_N launches at the search
time and min(kits, SEARCH_KITS) at the success time, then 2 + 2 k of kits (the answer and the start
also as shipped).
"""
from __future__ import annotations

import contextlib
import itertools
import time
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from levitron.runtime.design import launch_design as ld
from levitron.runtime.design import paired_fresh, sharpness
from levitron.runtime.design.kits import check_spreads
from levitron.runtime.design.production import Production, production_yield
from levitron.runtime.design.scene_keys import Vary, key_value
from levitron.runtime.design.yield_answer import YieldDesign
from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.ui import progress

GRID = {1: 7, 2: 5, 3: 3}
ZOOM_GRID = 3
SEARCH_KITS = 300
FRESH = 1


def _points(box, n: int) -> list[tuple[float, ...]]:
    return [tuple(float(v) for v in x) for x in itertools.product(*(np.linspace(lo, hi, n) for lo, hi in box))]


def maximize_yield(model, varies: Sequence[Vary], request: mc.Request, prod: Production,
                   pool=None, tolerance: dict | None = None) -> YieldDesign:
    """The design of the module docstring over the --vary box. With local workers every
    evaluation runs in one kept pool (launch_design.kept_pool). tolerance {key: value}: the
    makers' tolerances of its sharpness (runtime/design/sharpness.py; default per key there)."""
    if not 1 <= len(varies) <= 3:
        raise UserError("«vary»: give one to three keys for «maximize» yield")
    sharpness.tolerances(model.scene, {v.key: v.lo for v in varies}, tolerance)     # checked before the search
    check_spreads(model.scene, model.param_names, prod.keys)          # the kits' scene keys, likewise
    with contextlib.ExitStack() as stack:
        pool = pool or ld.kept_pool(stack, request, prod.kits)
        return _maximize(model, varies, request, prod, pool, tolerance)


def _maximize(model, varies, request, prod: Production, pool, tolerance=None) -> YieldDesign:
    t0 = time.perf_counter()
    keys = [v.key for v in varies]
    pinned = ld.Pinned.at_start(model, request, varies)
    start_x = tuple(float(key_value(model.scene.data, k)) for k in keys)
    at = model if pinned.at is None else ld._model_at(model.ref, keys, tuple(pinned.at.values()))
    prep = mc.prepare(at, pinned.request.given, prod.kits, request.seed, pinned.request.success_time,
                      pinned.request.t_end, request.integrator, request.tol, request.workers, request.scheduler)
    search = prod.with_kits(min(prod.kits, SEARCH_KITS))
    box = [(v.lo, v.hi) for v in varies]
    evaluated: dict[tuple[float, ...], dict] = {}
    n_grid, n_zoom = GRID[len(keys)] ** len(keys), ZOOM_GRID ** len(keys)

    def run(x, p: Production, as_shipped: bool = False) -> dict:
        here = ld._model_at(model.ref, keys, x)
        plan = replace(prep.plan, scene=here.ref[0], overrides=tuple(here.ref[1]))
        return production_yield(here, plan, prep.success_time, pinned.search_time or prep.success_time, p,
                                pool, as_shipped, prep.scheduler)
    with progress.task(f"yield design over {', '.join(keys)}: evaluations", total=n_grid + n_zoom + 2 + 2 * len(keys),
                       log_every=10.0) as tick:
        for grid in (_points(box, GRID[len(keys)]), None):
            if grid is None:
                best = _best(evaluated)
                cells = [(hi - lo) / (GRID[len(keys)] - 1) for lo, hi in box]
                grid = _points([(max(v.lo, b - c), min(v.hi, b + c)) for v, b, c in zip(varies, best, cells)],
                               ZOOM_GRID)
            for x in grid:
                if x not in evaluated:
                    evaluated[x] = run(x, search)
                tick()
        best = _best(evaluated)
        if evaluated.get(best, {"yield": {"successes": 0}})["yield"]["successes"] <= 0:
            reasons = sorted({r["reason"] for r in evaluated.values() if r.get("reason")})
            raise UserError("no kit floats anywhere in the «vary» box" + (f" ({reasons[0]})" if reasons else "")
                            + ": widen or move the box, or give more or other «washers»")
        fresh = prod.with_seed(prod.seed + FRESH)
        final = run(best, fresh, True)
        tick()
        first = run(start_x, fresh, True)
        tick()

        def side(x):            # the sharpness's sides, paired with the answer on its fresh kits
            tick()
            got = run(x, fresh)
            return paired_fresh.paired_side({**final["yield"], "verdicts": final["verdicts"]},
                                  {**got["yield"], "n": got["yield"]["kits"], "verdicts": got["verdicts"],
                                   **({"reason": got["reason"]} if got.get("reason") else {})})["probability"]
        sharp = sharpness.sharpness(side, model, varies, dict(zip(keys, best)), final["yield"]["probability"],
                                    tolerance, launch=True)
    rows = [{**dict(zip(keys, x)), "yield": r["yield"]["probability"], **({"reason": r["reason"]}
            if r.get("reason") else {})} for x, r in evaluated.items()]
    warnings = []
    for v, b in zip(varies, best):
        span = v.hi - v.lo
        if b <= v.lo + 1e-9 * span or b >= v.hi - 1e-9 * span:
            warnings.append(f"{v.key} = {ld.key_text(v.key, b)} is at a bound of «vary» {v.key}={v.lo:.10g}:"
                            f"{v.hi:.10g}: the box stopped the search, not the yield; widen «vary»")
    if final["untrimmable"] > 0.05:
        warnings.append(f"{100 * final['untrimmable']:.3g} % of the kits at the optimum cannot be trimmed into "
                        "the stable band by these washers (a top too heavy for its magnets, or too light with "
                        "every washer on): move top.mass, or give other «washers»")
    return YieldDesign(dict(zip(keys, best)), dict(zip(keys, start_x)), final, first, prod,
                       dict(pinned.request.given), pinned.request.success_time, rows,
                       evaluated[best]["yield"]["probability"], time.perf_counter() - t0, warnings, model.scene,
                       sharp)


def _best(evaluated: dict) -> tuple[float, ...]:
    """The middle of the points that share the best yield (launch_design.plateau_middle)."""
    pts = [(x, r["yield"]["successes"]) for x, r in evaluated.items()]
    best = ld.plateau_middle(pts)
    if best in evaluated:
        return best
    return min((x for x, v in pts if v >= max(v for _, v in pts)),
               key=lambda x: float(np.sum((np.array(x) - np.array(best)) ** 2)))
