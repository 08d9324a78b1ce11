"""Design by the launch odds: the scene keys at which a launch by hand floats most often.

The widest linear spin window (spin-range, thesis 3.3) sits next to a band edge, where a small
spread in mass or strength puts the top outside the band: advice computed on the ideal top fails
the person who follows it. This objective is the person's question itself, the probability of
runtime/scan/launch_odds.py, estimated as `levitron launch` estimates it:

1. **One launch spread for every design.** The request (flags over the scene's [launch] table over
   the defaults) is resolved once, at the scene as written: the defaults that scale with the
   scene (the spin about the middle of its interval, offsets with z_s) and the success time are
   pinned there, because the hand that launches does not change with the washer. Mass and
   strength enter as relative deviations, so a varied top.mass keeps its spread. Pinning is the
   Monte Carlo's plan (launch_odds.prepare): no launch runs for it.
2. **Common random numbers.** Every design point runs the same seed, hence the same draws: the
   odds of two designs differ by the design, not by the sampling noise, and odds(x) is a
   step function with small steps (one launch in n) that a grid can search. The search runs the
   first min(n, SEARCH_N) launches of the seed at each point (`search_n`): paired, neighbours
   differ in a few launches in a hundred, which a few hundred launches decide. The search judges
   them at its search time (`searching`): SEARCH_HORIZON of the success time, but at least
   SEARCH_PERIODS periods of the slowest motion. The search needs the ranking, not the odds, and
   the launches that fall between the search time and the success time are about the same share
   at every point: `levitron bench --kind search-horizon` (runtime/bench/search_horizon.py, 600
   launches at 7 masses across the band, reports/search_horizon/) finds the odds judged at T/8 and
   at T/4 within 0.33 points of each other at every mass on thesis_air (whose late falls, after
   T/8, vary by 2 points across the band) and within 1.3 points on levitron_toy (whose spin decays
   out of the window: its late falls vary by 66 points across the band, a share no search time
   short of T sees, so its answer's fresh odds at T are the ones to read). So the search ranks
   its points at an eighth of their flight as it did at a quarter, and the answer itself is judged
   at the success time (step 4).
3. **Grid, then zoom.** GRID[k] points a key over the --vary box (from its middle outwards, so
   that a good point is the first to compare with), then the same number over the
   two grid cells around the best point, ZOOMS times, but not once the zoom would step every
   key finer than its maker's tolerance (step 5's; thesis_air's mass: 0.1 g, so a box of 2.1 g
   zooms once, to steps of 0.12 g): no one sets a key closer than that, and the sharpness then
   says what +- the tolerance does. Where several points are level with the
   best, launch by launch (a plateau: a spread small against the band gives 100 % over a range;
   a broad optimum whose points differ by single launches), the answer is the middle of the
   plateau, the design farthest from both cliffs; for one key each edge of the plateau is first
   bisected on the same draws, at most EDGE_STEPS times and not once it is known to within the
   key's tolerance.
   Each point is compared launch by launch with the best so far and stopped once it is clearly
   worse; a point within a float step of one already run is not run again
   (runtime/design/paired_odds.py).
4. **Decide on fresh numbers.** The odds of the answer are estimated again with a fresh seed
   (seed + 1), all n launches: the search picked the best of many noisy values, so its own
   estimate is biased upwards; the fresh one is not, and carries its 95 % Wilson interval. The
   start (the scene as written) runs on the same fresh draws, paired with the answer, and stops
   once the paired difference decides (runtime/design/paired_fresh.py `start_odds`): a change
   the search found shows on a few hundred launches; where none decides it runs all n. Where
   the answer is the start, its odds are the answer's.
5. **Say how sharp it is.** The odds at +- a maker's tolerance of each key, on the first
   min(n, SIDE_N) of the answer's fresh draws, paired with the answer (paired_fresh.py `paired_side`); for two
   or three keys the ridge they share (runtime/design/sharpness.py). A side reports the answer's
   odds plus the paired difference, which 250 paired launches measure to 1.1-1.5 points (sd;
   thesis_air's trim at +-0.1 g: 3-6 % of the launches differ), beside the answer's own 0.75
   points on 1000 launches; 500 would give 0.9 points (the side's 95 % interval about 2.3 points
   wide each way instead of 2.9) at twice the cost.

The cost is a Monte Carlo of n launches at the success time (the answer), the start's paired
launches (n/BATCHES to n), at most GRID[k]^k (1 + ZOOMS) + 1 of min(n, SEARCH_N) launches at the
search time and 2 k of min(n, SIDE_N) at the success time (the sharpness), less the launches the
paired comparison saves (make bench: kinds launch-design and advice). With local workers every
Monte Carlo of the design runs in one kept pool: the workers start once for the whole command.
"""
from __future__ import annotations

import contextlib
import itertools
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from levitron.runtime.design import paired_fresh, sharpness
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
SEARCH_HORIZON = 0.125          # the search judges its launches at this fraction of the success time,
SEARCH_PERIODS = 3              # but over at least this many of the slowest motion's periods
SEARCH_N = 500                  # the search compares points on the first this many launches of the seed
SIDE_N = 250                    # a neighbour of the answer (sharpness, trim's widest): its first this many
ZOOMS = 2
EDGE_STEPS = 4                  # bisections of each edge of a one-key plateau
FRESH = 1                       # the deciding Monte Carlo's seed: the search's seed + FRESH
HALF = 0.5                      # other objectives warn below this fraction of the launch-odds optimum


def odds_dict(r: dict) -> dict:
    """The JSON's launch_odds block of one Monte Carlo."""
    return {"probability": r["probability"], "probability_ci95": list(r["probability_ci95"]),
            "n": r["n"], "seed": r["seed"], "successes": r["successes"],
            **({"paired_with": r["paired_with"]} if r.get("paired_with") else {})}


@dataclass
class Pinned:
    """The launch request resolved at the scene as written (module docstring, step 1)."""
    request: mc.Request
    start: dict                     # the Monte Carlo where it was pinned, search seed
    at: dict | None = None          # where it was pinned: None (the scene as written) or keys -> values
    search_time: float | None = None    # when the search judges its launches (None: the success time)

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
            try:            # the spread is pinned by the Monte Carlo's plan: no launch need run
                at = model if x is None else _model_at(model.ref, keys, x)
                prep = mc.prepare(at, request.given, request.n, request.seed, request.success_time,
                                  request.t_end, request.integrator, request.tol, request.workers,
                                  request.scheduler)
            except UserError as exc:            # among them: the top cannot hover there
                first = first or exc
                continue
            inputs = {name: spreads.spec_text(name, d) for name, d in prep.plan.dists}
            pinned = replace(request, given=inputs, success_time=prep.success_time, t_end=prep.plan.t_end)
            start = {"defaulted": sorted(set(inputs) - set(request.given))}
            return cls(pinned, start, None if x is None else dict(zip(keys, x)), _search_time(at, prep))
        raise UserError(f"{first} (and at every point of the «vary» box's grid): move or widen the box")


def side_n(n: int) -> int:
    """The launches of a neighbour of the answer (module docstring, step 5): min(n, SIDE_N)."""
    return min(int(n), SIDE_N)


def search_n(n: int) -> int:
    """The launches a search point runs (module docstring, step 2): the first min(n, SEARCH_N) of the
    seed's draws. Paired on common draws, neighbouring designs differ in a few launches in a
    hundred, so a few hundred decide between them; the answer is then judged on all n fresh ones."""
    return min(int(n), SEARCH_N)


def _search_time(model, prep: mc.Prepared) -> float:
    """When the search judges its launches (module docstring, step 2): SEARCH_HORIZON of the success
    time, but never less than SEARCH_PERIODS of the slowest motion at the launches' mean spin, and
    never more than the success time."""
    from levitron.runtime.simulate.start import slow_period
    spin = dict(prep.plan.dists)["spin"].a
    slow = slow_period(model, model.param("m"), prep.z_s, float(spin))
    return min(prep.success_time, max(SEARCH_HORIZON * prep.success_time, SEARCH_PERIODS * slow))


def searching(pinned: Pinned, n: int, horizon: bool = True) -> mc.Request:
    """The request of the search's points (module docstring, step 2): the first n launches of the
    pinned request, judged at its search time (horizon False: at the success time)."""
    request = pinned.request
    t = pinned.search_time if horizon and pinned.search_time else request.success_time
    return replace(request, n=int(n), success_time=t, t_end=min(t, request.t_end))


def key_text(key: str, value: float) -> str:
    """A varied key's value in a warning: the top's mass a quantity (runtime/words.py), shown in
    the scene's units (the plain view's SI in g)."""
    return si(value, "kg") if key == "top.mass" else f"{value:.6g}"


def _model_at(ref: SceneRef, keys: Sequence[str], x):
    from levitron.runtime.scan.runners import model_for
    return model_for(*variant(ref, keys, x))


def odds_at(ref: SceneRef, keys: Sequence[str], x, request: mc.Request, pool=None) -> dict:
    """The Monte Carlo of `request` at the scene keys x (its local workers in `pool`, a
    runners.KeptPool, where given); a design where the top cannot hover (or the run is refused)
    floats never: probability 0 with the reason."""
    try:
        return request.run(_model_at(ref, keys, x), quiet=True, pool=pool)
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


def plateau_middle(points: Sequence[tuple[tuple[float, ...], float]], level=None) -> tuple[float, ...]:
    """The middle of the best points (module docstring, step 3): for one key the middle of their
    range, for more the best point nearest their mean. level(x): whether x is among the best (the
    paired test, PairedOdds.level); default: the points that share the best value."""
    best = max(v for _, v in points)
    top = [np.array(x) for x, v in points if (level(x) if level else v >= best)]
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
                         tolerance: dict | None = None, horizon: bool = True) -> LaunchDesign:
    """The design of the module docstring over the --vary box (`where`: what its messages call it).
    With local workers every Monte Carlo of the design runs in one kept pool (runners.KeptPool:
    the workers start once, not once an evaluation): `pool` where the caller keeps one, else
    this design's own. early False: every point runs all its launches (no paired stopping).
    tolerance {key: value}: the makers' tolerances of its sharpness (runtime/design/sharpness.py;
    default per key there)."""
    sharpness.tolerances(model.scene, {v.key: v.lo for v in varies}, tolerance)     # checked before the search
    with contextlib.ExitStack() as stack:
        pool = pool or kept_pool(stack, request, request.n)
        return _maximize(model, varies, request, pinned, where, pool, early, tolerance, horizon)


def _maximize(model, varies: Sequence[Vary], request: mc.Request, pinned: Pinned | None, where: str,
              pool, early: bool, tolerance: dict | None = None, horizon: bool = True) -> LaunchDesign:
    t0 = time.perf_counter()
    if not 1 <= len(varies) <= 3:
        raise UserError("«vary»: give one to three keys for «maximize» launch-odds")
    keys = [v.key for v in varies]
    n_axis = GRID[len(varies)]
    searched = n_axis ** len(varies) * (ZOOMS + 1) + (2 * EDGE_STEPS if len(varies) == 1 else 0) + 1
    most = searched + 2 + 2 * len(varies)       # and the answer, the start, the sharpness's sides
    m = search_n(request.n)
    with progress.task(f"launch-odds design over {', '.join(keys)}: launches (at most {most} evaluations)",
                       total=(searched + 2 * len(varies)) * m + 2 * request.n,
                       log_every=10.0) as tick:
        pinned = pinned or Pinned.at_start(model, request, varies, pool)
        req = pinned.request
        box = [(v.lo, v.hi) for v in varies]
        odds = PairedOdds(model.ref, keys, searching(pinned, m, horizon), box, pool, tick, early)
        return _search(model, varies, keys, pinned, req, box, odds, where, t0, tolerance)


def _search(model, varies, keys, pinned: Pinned, req: mc.Request, box, odds: PairedOdds, where: str,
            t0: float, tolerance: dict | None = None) -> LaunchDesign:
    n_axis = GRID[len(varies)]
    tols = list(sharpness.tolerances(model.scene, {v.key: 0.5 * (v.lo + v.hi) for v in varies}, tolerance).values())
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
        best = plateau_middle(list(evaluated.items()), odds.level)
        if len(varies) == 1 and sum(map(odds.level, evaluated)) > 1:
            break                       # 1 key, a plateau: its edges are bisected below
        cells = [(hi - lo) / (n_axis - 1) for lo, hi in box]
        if all(2 * c / (n_axis - 1) < t for c, t in zip(cells, tols)):
            break                       # a zoom would step finer than a maker sets the keys
        box = [(max(v.lo, b - c), min(v.hi, b + c)) for v, b, c in zip(varies, best, cells)]

    if len(varies) == 1 and sum(map(odds.level, evaluated)) > 1:
        for _ in range(EDGE_STEPS):     # bisect each edge of the plateau on the same draws
            xs = sorted(evaluated)
            inside = [x for x in xs if odds.level(x)]
            for edge, step in ((inside[0], -1), (inside[-1], 1)):
                k = xs.index(edge) + step
                if 0 <= k < len(xs) and abs(xs[k][0] - edge[0]) > tols[0]:    # known to within it: done
                    mid = (0.5 * (edge[0] + xs[k][0]),)
                    if mid not in evaluated:
                        run(mid)
        best = plateau_middle(list(evaluated.items()), odds.level)
    if best not in evaluated:            # a plateau's middle between grid points: run it too
        run(best)
        if not odds.level(best):
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
    if odds.key(start_x) == odds.key(best):        # no change: the answer is the start, run once
        first = final
        odds.tick(req.n)
    else:
        first = paired_fresh.start_odds(model.ref, keys, start_x, final, fresh, odds.pool, odds.tick)
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
    def fresh_odds(x):              # the sharpness's sides, paired with the answer on its fresh draws
        odds.tick(side_n(req.n))
        side = odds_at(model.ref, keys, x, fresh.with_n(side_n(req.n)), odds.pool)
        return paired_fresh.paired_side(final, side)["probability"]
    sharp = sharpness.sharpness(fresh_odds, model, varies, dict(zip(keys, best)), final["probability"],
                                tolerance, launch=True)
    return LaunchDesign(dict(zip(keys, best)), dict(zip(keys, map(float, start_x))), odds_dict(final),
                        odds_dict(first), evaluated[best], rows, dict(req.given), req.success_time,
                        req.t_end, req.seed, req.n, time.perf_counter() - t0, warnings,
                        list(pinned.start.get("defaulted", [])), model.scene,
                        {**odds.counts, "search_time": odds.request.success_time}, sharp,
                        {"probability_ci95": final["probability_ci95"], "verdicts": final.get("verdicts", ())})


def what_it_costs(model, varies: Sequence[Vary], request: mc.Request, optimum: dict[str, float], objective: str,
                  unit_text) -> dict:
    """Another objective's optimum in launches: its odds and the start's (fresh seed),
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
    from levitron.runtime.physics.apparatus.friction import has_friction
    return bool(model.scene.data.get("launch")) or (has_friction(model) and model.pvals()["k_spin"] > 0)

