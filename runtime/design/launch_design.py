"""Design by the launch odds: the scene keys at which a launch by hand floats most often (issue 26).

The widest linear spin window (spin-range, thesis 3.3) sits next to a band edge, where a small
spread in mass or strength puts the top outside the band: advice computed on the ideal top fails
the person who follows it. This objective is the person's question itself, the probability of
runtime/scan/launch_odds.py, estimated as `levitron launch` estimates it:

1. **One launch spread for every design.** The request (flags over the scene's [launch] table over
   the defaults) is resolved once, at the scene as written: the defaults that scale with the
   scene (the spin about the middle of its interval, offsets with z_s) and the success time are
   pinned there, because the hand that launches does not change with the washer. Mass and
   strength enter as relative deviations, so a varied top.mass keeps its spread.
2. **Common random numbers.** Every design point runs the same seed, hence the same draws: the
   odds of two designs differ by the design, not by the sampling noise, and odds(x) is a
   step function with small steps (one launch in n) that a grid can search. The search runs the
   first min(n, SEARCH_N) launches of the seed at each point (`search_n`): paired, neighbours
   differ in a few launches in a hundred, which a few hundred launches decide.
3. **Grid, then zoom.** GRID[k] points a key over the --vary box (from its middle outwards, so
   that a good point is the first to compare with), then the same number over the
   two grid cells around the best point, ZOOMS times. Where several points share the best odds
   (a plateau: a spread small against the band gives 100 % over a range), the answer is the
   middle of the plateau, the design farthest from both cliffs; for one key each edge of the
   plateau is first bisected EDGE_STEPS times on the same draws.
   Each point is compared launch by launch with the best so far and stopped once it is clearly
   worse; a point within a float step of one already run is not run again
   (runtime/design/paired_odds.py).
4. **Decide on fresh numbers.** The odds of the answer and of the start (the scene as written)
   are estimated again with a fresh seed (seed + 1): the search picked the best of many noisy
   values, so its own estimate is biased upwards; the fresh one is not, and carries its 95 %
   Wilson interval.
5. **Say how sharp it is.** The odds on the same fresh draws at +- a maker's tolerance of each
   key, and for two or three keys the ridge they share (runtime/design/sharpness.py).

The cost is at most (GRID[k] (1 + ZOOMS) + 3 + 2 k) Monte Carlos of n launches, less the launches the
paired comparison saves (make bench: kinds launch-design and advice). With local workers every
Monte Carlo of the design runs in one kept pool: the workers start once for the whole command.
"""
from __future__ import annotations

import contextlib
import itertools
import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from levitron.runtime.design import sharpness
from levitron.runtime.design.launch_design_answer import LaunchDesign
from levitron.runtime.design.paired_odds import PairedOdds, variant
from levitron.runtime.design.scene_keys import Vary, key_value
from levitron.runtime.errors import UserError
from levitron.runtime.words import si
from levitron.runtime.model.scenes import SceneRef
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan import spreads
from levitron.runtime.ui import progress

GRID = {1: 7, 2: 5, 3: 3}       # points a key of each grid, by the number of keys
SEARCH_N = 500                  # the search compares points on the first this many launches of the seed
ZOOMS = 2
EDGE_STEPS = 5                  # bisections of each edge of a one-key plateau
FRESH = 1                       # the deciding Monte Carlo's seed: the search's seed + FRESH
HALF = 0.5                      # other objectives warn below this fraction of the launch-odds optimum


def odds_dict(r: dict) -> dict:
    """The JSON's launch_odds block of one Monte Carlo."""
    return {"probability": r["probability"], "probability_ci95": list(r["probability_ci95"]),
            "n": r["n"], "seed": r["seed"], "successes": r["successes"]}


@dataclass
class Pinned:
    """The launch request resolved at the scene as written (module docstring, step 1)."""
    request: mc.Request
    start: dict                     # the Monte Carlo where it was pinned, search seed
    at: dict | None = None          # where it was pinned: None (the scene as written) or keys -> values

    @classmethod
    def at_start(cls, model, request: mc.Request, varies: Sequence[Vary], pool=None) -> Pinned:
        """Pinned at the scene as written; where its top cannot hover there (or has no spin
        interval for the default spin), at the box's middle, else its first grid point that can."""
        keys = [v.key for v in varies]
        if "top.mass" in keys and "mass" in request.given and \
                not str(request.given["mass"]).strip().lower().startswith(spreads.REL):
            raise UserError("«vary» top.mass moves the top's mass, so its spread must be relative: "
                            "write «mass» rel:normal:0,0.002 (or rel:0.2%)")
        tries = [None, tuple(0.5 * (v.lo + v.hi) for v in varies),
                 *_axes(varies, [(v.lo, v.hi) for v in varies], GRID[len(varies)])]
        first = None
        for x in tries:
            try:
                probe = request.with_n(search_n(request.n))      # pins the spread: no odds needed
                if x is None:
                    start = probe.run(model, quiet=True, pool=pool)
                else:
                    from levitron.runtime.scan.runners import model_for
                    start = probe.run(model_for(*variant(model.ref, keys, x)), quiet=True, pool=pool)
            except UserError as exc:
                first = first or exc
                continue
            if start.get("reason"):          # the top cannot hover there: no launch spread to pin
                first = first or UserError(start["reason"])
                continue
            pinned = mc.Request(dict(start["inputs"]), request.n, request.seed, start["success_time"],
                                start["t_end"], request.integrator, request.tol, request.workers,
                                request.scheduler)
            return cls(pinned, start, None if x is None else dict(zip(keys, x)))
        raise UserError(f"{first} (and at every point of the «vary» box's grid): move or widen the box")


def search_n(n: int) -> int:
    """The launches a search point runs (module docstring, step 2): the first min(n, SEARCH_N) of the
    seed's draws. Paired on common draws, neighbouring designs differ in a few launches in a
    hundred, so a few hundred decide between them; the answer is then judged on all n fresh ones."""
    return min(int(n), SEARCH_N)


def key_text(key: str, value: float) -> str:
    """A varied key's value in a warning: the top's mass a quantity (runtime/words.py), shown in
    the scene's units (the plain view's SI in g)."""
    return si(value, "kg") if key == "top.mass" else f"{value:.6g}"


def odds_at(ref: SceneRef, keys: Sequence[str], x, request: mc.Request, pool=None) -> dict:
    """The Monte Carlo of `request` at the scene keys x (its local workers in `pool`, a
    runners.KeptPool, where given); a design where the top cannot hover (or the run is refused)
    floats never: probability 0 with the reason."""
    from levitron.runtime.scan.runners import model_for
    try:
        return request.run(model_for(*variant(ref, keys, x)), quiet=True, pool=pool)
    except UserError as exc:
        return {"probability": 0.0, "probability_ci95": [0.0, 0.0], "n": request.n, "seed": request.seed,
                "successes": 0, "reason": str(exc)}


def _axes(varies: Sequence[Vary], box: Sequence[tuple[float, float]], n: int) -> list[tuple[float, ...]]:
    return list(itertools.product(*(np.linspace(lo, hi, n) for lo, hi in box)))


def _middle_out(points: Sequence[tuple[float, ...]], box) -> list[tuple[float, ...]]:
    """The grid's points from the box's middle outwards (ties in grid order)."""
    mid = [0.5 * (lo + hi) for lo, hi in box]
    width = [max(hi - lo, 1e-300) for lo, hi in box]
    return sorted(points, key=lambda x: sum(((v - m) / w) ** 2 for v, m, w in zip(x, mid, width)))


def _plateau(evaluated: dict) -> bool:
    top = max(evaluated.values())
    return sum(v >= top for v in evaluated.values()) > 1


def plateau_middle(points: Sequence[tuple[tuple[float, ...], float]]) -> tuple[float, ...]:
    """The middle of the points that share the best value (module docstring, step 3): for one key
    the middle of their range, for more the best point nearest their mean."""
    best = max(v for _, v in points)
    top = [np.array(x) for x, v in points if v >= best]
    if len(top[0]) == 1:
        return (0.5 * float(min(top)[0] + max(top)[0]),)
    mean = np.mean(top, axis=0)
    return tuple(float(v) for v in min(top, key=lambda x: float(np.sum((x - mean) ** 2))))


def kept_pool(stack: contextlib.ExitStack, request: mc.Request, n_tasks: int):
    """One runners.KeptPool for every Monte Carlo of a command (a design, a trim), entered on
    `stack`; None where they run serially or on dask."""
    from levitron.runtime.scan import runners
    from levitron.runtime.scan.workers import auto_workers
    if request.scheduler:
        return None
    workers = auto_workers(n_tasks) if request.workers is None else request.workers
    workers = min(workers, runners.usable_cores())
    return stack.enter_context(runners.KeptPool(workers)) if workers > 1 else None


def maximize_launch_odds(model, varies: Sequence[Vary], request: mc.Request, pinned: Pinned | None = None,
                         where: str = "the «vary» box", pool=None, early: bool = True,
                         tolerance: dict | None = None) -> LaunchDesign:
    """The design of the module docstring over the --vary box (`where`: what its messages call it).
    With local workers every Monte Carlo of the design runs in one kept pool (runners.KeptPool:
    the workers start once, not once an evaluation): `pool` where the caller keeps one, else
    this design's own. early False: every point runs all its launches (no paired stopping).
    tolerance {key: value}: the makers' tolerances of its sharpness (runtime/design/sharpness.py;
    default per key there)."""
    sharpness.tolerances(model.scene, {v.key: v.lo for v in varies}, tolerance)     # checked before the search
    with contextlib.ExitStack() as stack:
        pool = pool or kept_pool(stack, request, request.n)
        return _maximize(model, varies, request, pinned, where, pool, early, tolerance)


def _maximize(model, varies: Sequence[Vary], request: mc.Request, pinned: Pinned | None, where: str,
              pool, early: bool, tolerance: dict | None = None) -> LaunchDesign:
    t0 = time.perf_counter()
    if not 1 <= len(varies) <= 3:
        raise UserError("«vary»: give one to three keys for «maximize» launch-odds")
    keys = [v.key for v in varies]
    n_axis = GRID[len(varies)]
    most = n_axis ** len(varies) * (ZOOMS + 1) + (2 * EDGE_STEPS if len(varies) == 1 else 0) + 4 + 2 * len(varies)
    m = search_n(request.n)
    with progress.task(f"launch-odds design over {', '.join(keys)}: launches (at most {most} evaluations)",
                       total=(most - 4 - 2 * len(varies)) * m + (4 + 2 * len(varies)) * request.n,
                       log_every=10.0) as tick:
        pinned = pinned or Pinned.at_start(model, request, varies, pool)
        tick(m)
        req = pinned.request
        box = [(v.lo, v.hi) for v in varies]
        odds = PairedOdds(model.ref, keys, req.with_n(m), box, pool, tick, early)
        return _search(model, varies, keys, pinned, req, box, odds, where, t0, tolerance)


def _search(model, varies, keys, pinned: Pinned, req: mc.Request, box, odds: PairedOdds, where: str,
            t0: float, tolerance: dict | None = None) -> LaunchDesign:
    n_axis = GRID[len(varies)]
    evaluated: dict[tuple[float, ...], float] = {}
    rows = []

    def run(x):
        r = odds(x)
        evaluated[x] = r["probability"]
        rows.append({**dict(zip(keys, x)), "probability": r["probability"],
                     **{k: r[k] for k in ("reason", "stopped_early", "launches_run") if k in r}})
        return r["probability"]
    for _ in range(ZOOMS + 1):
        for x in _middle_out(_axes(varies, box, n_axis), box):
            x = tuple(float(v) for v in x)
            if x not in evaluated:
                run(x)
        best = plateau_middle(list(evaluated.items()))
        if len(varies) == 1 and _plateau(evaluated):
            break                       # 1 key, a plateau: its edges are bisected below
        cells = [(hi - lo) / (n_axis - 1) for lo, hi in box]
        box = [(max(v.lo, b - c), min(v.hi, b + c)) for v, b, c in zip(varies, best, cells)]

    if len(varies) == 1 and _plateau(evaluated):
        for _ in range(EDGE_STEPS):     # bisect each edge of the plateau on the same draws
            top = max(evaluated.values())
            xs = sorted(evaluated)
            inside = [x for x in xs if evaluated[x] >= top]
            for edge, step in ((inside[0], -1), (inside[-1], 1)):
                k = xs.index(edge) + step
                if 0 <= k < len(xs):
                    mid = (0.5 * (edge[0] + xs[k][0]),)
                    if mid not in evaluated:
                        run(mid)
        best = plateau_middle(list(evaluated.items()))
    if best not in evaluated:            # a plateau's middle between grid points: run it too
        if run(best) < max(evaluated.values()):
            best = max(evaluated, key=evaluated.get)
    if max(evaluated.values()) <= 0:
        reasons = sorted({row["reason"] for row in rows if "reason" in row})
        raise UserError(f"no launch floats anywhere in {where}"
                        + (f" ({reasons[0]})" if reasons else "") + ": "
                        + ("widen or move the box, or " if where == "the «vary» box" else "")
                        + "check the launch spread with `«levitron=launch»` (a steadier hand: smaller "
                        "«mass», «strength» or «tilt» spreads)")
    fresh = req.with_seed(req.seed + FRESH)
    final = odds_at(model.ref, keys, best, fresh, odds.pool)
    odds.tick(req.n)
    start_x = [key_value(model.scene.data, k) for k in keys]
    first = odds_at(model.ref, keys, start_x, fresh, odds.pool)
    odds.tick(req.n)
    warnings = list(final.get("warnings", []))     # the launches' own at the optimum (reach, resonances)
    for v, b in zip(varies, best):
        span = v.hi - v.lo
        if b <= v.lo + 1e-9 * span or b >= v.hi - 1e-9 * span:
            warnings.append(f"{v.key} = {key_text(v.key, b)} is at a bound of «vary» {v.key}={v.lo:.10g}:{v.hi:.10g}: "
                            "the box stopped the search, not the odds; widen «vary»")
    if pinned.at is not None:
        where = ", ".join(f"{k} = {key_text(k, v)}" for k, v in pinned.at.items())
        warnings.append(f"the scene as written cannot be launched ({first.get('reason', 'no hover')}); "
                        f"the launch spread's defaults are taken at {where}")
    def fresh_odds(x):              # the sharpness's evaluations: the optimum's fresh draws, kept pool
        odds.tick(req.n)
        return odds_at(model.ref, keys, x, fresh, odds.pool)["probability"]
    sharp = sharpness.sharpness(fresh_odds, model, varies, dict(zip(keys, best)), final["probability"],
                                tolerance, launch=True)
    return LaunchDesign(dict(zip(keys, best)), dict(zip(keys, map(float, start_x))), odds_dict(final),
                        odds_dict(first), evaluated[best], rows, dict(req.given), req.success_time,
                        req.t_end, req.seed, req.n, time.perf_counter() - t0, warnings,
                        list(pinned.start.get("defaulted", [])), model.scene, dict(odds.counts), sharp)


def what_it_costs(model, varies: Sequence[Vary], request: mc.Request, optimum: dict[str, float], objective: str,
                  unit_text) -> dict:
    """Another objective's optimum in launches (issue 26): its odds and the start's (fresh seed),
    the launch-odds optimum's, and a warning where the optimum floats less than HALF as often.
    unit_text(key, value) -> the key's value in the scene's units, for the warning."""
    keys = [v.key for v in varies]
    pinned = Pinned.at_start(model, request, varies)
    fresh = pinned.request.with_seed(pinned.request.seed + FRESH)
    at_opt = odds_at(model.ref, keys, [optimum[k] for k in keys], fresh)
    best = maximize_launch_odds(model, varies, request, pinned)
    out = {"launch_odds": odds_dict(at_opt), "start_launch_odds": best.start_launch_odds,
           "launch_odds_optimum": {"optimum": best.optimum, "launch_odds": best.launch_odds}}
    p, q = at_opt["probability"], best.probability
    if p < HALF * q:
        where = ", ".join(f"{k} = {unit_text(k, optimum[k])}" for k in keys)
        there = ", ".join(f"{k} = {unit_text(k, v)}" for k, v in best.optimum.items())
        out["warning"] = (f"the {objective} optimum ({where}) floats {100 * p:.3g} % of hand launches; "
                          f"«maximize» launch-odds gives {100 * q:.3g} % at {there}")
    return out


def worth_the_launches(model) -> bool:
    """Whether a design's launches are worth counting: the scene has air friction or a [launch] table."""
    from levitron.runtime.physics.friction import has_friction
    return bool(model.scene.data.get("launch")) or (has_friction(model) and model.pvals()["k_spin"] > 0)

