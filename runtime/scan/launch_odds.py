"""Launch odds by Monte Carlo: how likely a launch by hand is to float, and which input matters most.

Every sample is one full nonlinear run of the full model (thesis 2.3, with air friction where the
scene declares it, derive/friction.py) from a launch drawn from distributions:

    spin          the spin rate about the axis (rad/s)
    tilt          the tilt of the axis (rad), towards tilt_azimuth (rad from +x towards +y)
    offset        the horizontal offset of the centre of mass along x (m)
    velocity      the initial horizontal velocity along y (m/s), p_y = m v
    mass          the top's mass (washers, manufacture), sampled as m (1 + d): given as the mass
                  in kg ("normal:0.0515,0.0001") or as a relative spread that says so
                  ("rel:normal:0,0.002", "rel:0.2%"; parse_input)
    strength      the magnets' strength, sampled as mu (1 + d) (thesis 2.2.1: only the product of
                  the top's moment and the plate's strength enters the dynamics): a factor
                  ("normal:1,0.005") or relative ("rel:0.5%")
    temperature   the magnets' temperature (degC), through the scene's temperature coefficients

and the apparatus' imperfections (APPARATUS), each sample setting a runtime parameter of
a model that has the term (a scene without it is refused with the key that adds it):

    base_tilt          the base's tilt from level (rad; runtime parameter base_tilt, plate.tilt)
    base_tilt_azimuth  its downhill direction (rad from +x towards +y; base_tilt_azimuth)
    moment_tilt        the angle of the magnet's moment from the top's axis (rad; moment_tilt,
                       top.moment_tilt): the moment turns with the spin, so the top wobbles

Over a tilted base the launch is aimed where a person aims it: at the level hover point, the axis
along the plate's normal (spun on the lifter resting on the base), the spreads about that point; the
tilted equilibrium (runtime/physics/apparatus/tilted_equilibrium.py) lies downhill, for the top to find.

Each is "normal:MEAN,SD", "uniform:LO,HI" or a number (fixed), given by a flag or the scene's
[launch] table. The defaults scale with the scene (never SI magnitudes: scenes may be
dimensionless): the spin normal about the geometric mean of the spin interval with a 10 % spread,
a tilt up to 0.02 rad, an offset of 1 % of z_s, a velocity of 1 % of sqrt(g z_s), 0.2 % of mass and
0.5 % of strength. Each sample starts at the hover height of its own mass and strength
(runtime.physics.equilibrium.finder.hover_height; none: the sample "cannot hover"), a chunk of
launches at a time through runtime/scan/launch_chunk.py.

Success means floating at least success_time (default: the run length, or in air half the spin
decay time; without friction and without a run length, runtime/scan/stability_map.py's PERIODS slow periods).
The probability comes with its 95 % Wilson score interval; the flight times with median and
quartiles; each input's effect is the spread of the success rate over its quintiles.

The samples are drawn once from PCG64 at the seed, in a fixed order; the runs go through the C chunk
driver (runtime/scan/chunk_c.py): serial, on local processes or on dask (runtime/scan/runners.py),
every run is the same arithmetic, so a seed gives the same verdicts everywhere. A launch up at the
end past its stable window (in air) has no verdict (runtime/scan/launch_window.py).
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus.friction import has_friction
from levitron.runtime.integrate.verdict import PAST_WINDOW
from levitron.runtime.integrate.methods import DEFAULT, refuse_on_full_model, resolve
from levitron.runtime.scan.launch_answer import LaunchOdds
from levitron.runtime.scan.launch_summary import cannot_hover, effects, launches, wilson
from levitron.runtime.scan.launch_chunk import run_chunk, samples  # noqa: F401  (samples: the plan's draws)
from levitron.runtime.scan.launch_window import WindowJudge, no_verdicts, none_decided
from levitron.runtime.scan.launch_inputs import (ALL_INPUTS, INPUTS, apparatus_of, check_bounds, reach_warnings,
                                                  refuse_apparatus, resonance_warnings)
from levitron.runtime.scan.spreads import Dist, parse_input, spec_text
from levitron.runtime.scan.workers import auto_workers, dask_errors_as_ours
from levitron.runtime.ui.validate import count, launch_settings, real, spread_range, temperature

MAX_N = 10**6
# a launch's tolerance: its odds well inside their Wilson interval (runtime/bench/verdict_tolerance.py)
LAUNCH_TOL = 1e-6


@dataclass(frozen=True)
class Plan:
    """What every chunk of a Monte Carlo shares (picklable: sent to the workers)."""
    scene: str
    overrides: tuple
    dists: tuple                 # ((input name, Dist), ...) in ALL_INPUTS order (apparatus: the model's)
    n: int
    seed: int
    t_end: float
    integrator: str
    tol: float


def defaults(model, interval, z_s: float) -> dict[str, Dist]:
    """The default launch spread of the module docstring, scaled by the scene."""
    pv = model.pvals()
    spin = math.sqrt(interval[0] * interval[1]) if interval else None
    out = {"tilt": Dist("uniform", 0.0, 0.02), "tilt_azimuth": Dist("uniform", 0.0, 2 * math.pi),
           "offset": Dist("normal", 0.0, 0.01 * z_s),
           "velocity": Dist("normal", 0.0, 0.01 * math.sqrt(pv["g"] * z_s)),
           "mass": Dist("normal", 0.0, 0.002), "strength": Dist("normal", 0.0, 0.005),
           "temperature": Dist("fixed", float(model.scene.data.get("temperature", 20.0)))}
    if spin is not None:
        out["spin"] = Dist("normal", spin, 0.1 * spin)
    for a in apparatus_of(model):
        out[a.name] = a.default(model) if a.default else Dist("fixed", float(pv[a.param]))
    return out


def table_settings(table: Mapping) -> tuple[dict, dict]:
    """The scene's [launch] table as (inputs, settings): the inputs' distribution specs as given
    (parse_dist checks them), and n, seed, success_time, t_end checked here under their own names
    ("[launch] n = 'many' must be a whole number"), for the CLI and the API alike; a flag or an
    argument given by the caller takes precedence over either."""
    inputs = {k: table[k] for k in ALL_INPUTS if k in table}
    for k, v in inputs.items():          # each spread's spelling, refused as the table's
        parse_input(k, v, None, table=True)
    checks = {"n": lambda v, label: count(v, label, low=1, high=MAX_N),
              "seed": lambda v, label: count(v, label, low=0),
              "success_time": lambda v, label: real(v, label, positive=True, unit="s", what="time"),
              "t_end": lambda v, label: real(v, label, positive=True, unit="s", what="time")}
    return inputs, {k: check(table[k], f"[launch] {k}") for k, check in checks.items() if k in table}


# the keyword options of monte_carlo beyond the inputs (the API's launch(**options) takes these)
LAUNCH_OPTIONS = ("success_time", "t_end", "integrator", "tol", "workers", "scheduler")
DEFAULT_N = 1000
DEFAULT_SEED = 0


@dataclass(frozen=True)
class Request:
    """One launch Monte Carlo as asked (flags or API arguments over the scene's [launch] table, over
    the defaults): what `launch`, `optimize --maximize launch-odds` and `trim` all run, so that a
    design's odds are the odds `launch` gives at the same scene keys. given: input name -> spec
    (inputs not given take `defaults`); defaulted: the inputs left to `defaults`."""
    given: Mapping[str, object]
    n: int = DEFAULT_N
    seed: int = DEFAULT_SEED
    success_time: float | None = None
    t_end: float | None = None
    integrator: str = DEFAULT
    tol: float = LAUNCH_TOL
    workers: int | None = None      # None: every usable core (runtime/scan/workers.py)
    scheduler: str | None = None

    @classmethod
    def of(cls, table: Mapping, given: Mapping[str, object] | None = None, **options) -> Request:
        """The request from the scene's [launch] table and the caller's inputs and options (None:
        not given); the caller's win, then the table's, then the defaults."""
        inputs, settings = table_settings(table)
        if given is not None and not isinstance(given, Mapping):
            raise UserError(f"launch inputs = {given!r} must map input names to distributions, e.g. "
                            "{'spin': 'normal:1000,100'}")
        inputs.update(given or {})
        chosen = {k: v for k, v in options.items() if v is not None}
        unknown = sorted(set(chosen) - set(LAUNCH_OPTIONS) - {"n", "seed"})
        if unknown:
            raise UserError(f"launch: unknown option {unknown[0]!r}: use {', '.join(LAUNCH_OPTIONS)}")
        for key in ("n", "seed", "success_time", "t_end"):
            if key not in chosen and key in settings:
                chosen[key] = settings[key]
        launch_settings(chosen, MAX_N)      # before any model: a design's refusal as it is
        return cls(inputs, **chosen)

    def with_seed(self, seed: int) -> Request:
        return replace(self, seed=int(seed))

    def with_n(self, n: int) -> Request:
        return replace(self, n=int(n))

    def run(self, model, quiet: bool = False, pool=None) -> LaunchOdds:
        """monte_carlo of this request on the model (its workers load model.ref); pool: a
        runners.KeptPool its local workers run in (a design's Monte Carlos share one)."""
        return monte_carlo(model, self.given, n=self.n, seed=self.seed,
                           success_time=self.success_time, t_end=self.t_end, integrator=self.integrator,
                           tol=self.tol, workers=self.workers, scheduler=self.scheduler, quiet=quiet,
                           pool=pool)


def monte_carlo(model, given: Mapping[str, object], n: int = 1000,
                seed: int = 0, success_time: float | None = None, t_end: float | None = None,
                integrator: str = DEFAULT, tol: float = LAUNCH_TOL, workers: int | None = None,
                scheduler: str | None = None, quiet: bool = False, pool=None) -> LaunchOdds:
    """The launch odds of the module docstring (runtime/scan/launch_answer.py's LaunchOdds). given:
    input name -> a distribution spec (flags or the scene's [launch] table, flags first); others
    take `defaults`. workers None: every usable core (runtime/scan/workers.py)."""
    from levitron.runtime.physics.equilibrium.finder import NoHover
    try:
        prep = prepare(model, given, n, seed, success_time, t_end, integrator, tol, workers, scheduler)
    except NoHover as exc:          # a design where the top cannot hover is an answer: it floats never
        return LaunchOdds.of(cannot_hover(n, seed, str(exc), given, success_time, t_end), model)
    results = execute(prep, model, range(prep.plan.n), quiet=quiet, pool=pool)
    past = WindowJudge(model, prep.interval).mark(samples(prep.plan)["spin"], prep.success_time, results)
    return LaunchOdds.of(summarize(prep.plan, results, prep.success_time, prep.interval, prep.z_s, prep.tau,
                                   prep.given, prep.warnings, past), model)


@dataclass(frozen=True)
class Prepared:
    """A Monte Carlo checked and planned, not yet run: its Plan and what the summary needs."""
    plan: Plan
    success_time: float
    interval: tuple | None
    z_s: float
    tau: float | None
    given: Mapping
    warnings: tuple
    workers: int
    scheduler: str | None

    def floats(self, points) -> dict[int, bool]:
        """Launch index -> floated the success time, not past its window (summarize's test), for some points."""
        return {p["i"]: p["t"] >= self.success_time * (1 - 1e-12) and p["status"] != PAST_WINDOW for p in points}


def prepare(model, given: Mapping[str, object], n: int = 1000,
            seed: int = 0, success_time: float | None = None, t_end: float | None = None,
            integrator: str = DEFAULT, tol: float = LAUNCH_TOL, workers: int | None = None,
            scheduler: str | None = None, warn: bool = True) -> Prepared:
    """monte_carlo's checks, defaults and plan (one-line UserErrors), without running a launch; warn
    False: without the warnings (a design's search point, whose warnings nobody reads)."""
    from levitron.runtime.scan import launch_inputs as li, runners
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.physics.stability.analysis import stability_of
    from levitron.runtime.ui.validate import launch_count, random_seed, run_length, tolerance
    n, seed = launch_count(n, MAX_N), random_seed(seed)
    if "full" not in model.parts:
        raise UserError("launch runs the full model: this scene's model.needs has no \"full\"; add it")
    unknown = sorted(set(given) - set(ALL_INPUTS))
    if unknown:
        raise UserError(f"unknown launch input {unknown[0]!r}: use one of {', '.join(ALL_INPUTS)}")
    refuse_apparatus(model, given)
    z_s = hover_height(model)
    lin = stability_of(model, z_s=z_s, eigen=False)      # the interval: the exact route alone
    interval = lin.spin_interval
    dists = defaults(model, interval, z_s)
    reference = {"mass": model.param("m"), "strength": 1.0}
    dists.update({k: parse_input(k, v, reference.get(k, 1.0)) for k, v in given.items()})
    for a in apparatus_of(model):       # a direction of nothing (a level base) is not spread
        d = dists.get(a.direction_of)
        if a.direction_of and a.name not in given and not d.spread and d.a == 0:
            dists[a.name] = Dist("fixed", float(model.pvals()[a.param]))
    if "spin" not in dists:
        raise UserError("the scene's top has no spin interval of linear stability at its hover height, "
                        "so there is no default spin: pass «spin» normal:MEAN,SD")
    if all(dists[k].a == 0 and (dists[k].kind == "fixed" or dists[k].b == 0)
           for k in ("tilt", "offset", "velocity") + tuple(a.name for a in apparatus_of(model) if a.moves)):
        raise UserError("tilt, offset and velocity are all exactly 0: every launch starts on the "
                        "invariant set (thesis 3.2.1), where the ideal top stays at any spin, so the "
                        "odds would test nothing; give a spread, e.g. «tilt» uniform:0,0.02")
    check_bounds(dists, given)          # each spread's support against its key's bound
    d = dists["temperature"]             # the check of --temperature, over the spread's range
    lo, hi, how = spread_range(d.kind, d.a, d.b)
    temperature(model.scene.data, lo, hi, f"«temperature_spread» {d.text()}{how}")
    # the given times by their own names, before one is derived from the other
    success_time = None if success_time is None else real(success_time, "«success_time»",
                                                          positive=True, unit="s", what="time")
    t_end = None if t_end is None else run_length(t_end)
    tol = tolerance(tol)
    workers = auto_workers(n) if workers is None else count(workers, "«workers»", low=1)
    if scheduler is not None and not isinstance(scheduler, str):
        raise UserError(f"«scheduler» {scheduler!r}: give the scheduler's address as text, e.g. tcp://127.0.0.1:8786")
    air = has_friction(model) and model.pvals()["k_spin"] > 0
    tau = 1 / model.pvals()["k_spin"] if air else None
    li.check_decay_horizon(model, z_s, dists["spin"], tau, success_time is None and t_end is None)
    success_time = success_time if success_time is not None else t_end if t_end is not None else (
        0.5 * tau if air else None)
    if success_time is None:          # no friction: a map's run length (runtime/scan/stability_map.py)
        from levitron.runtime.scan.stability_map import PERIODS
        from levitron.runtime.scan.physics import slow_period
        success_time = PERIODS * slow_period(model, model.param("m"), z_s, float(dists["spin"].a))
    t_end = success_time if t_end is None else t_end
    for label, v in (("«success_time»", success_time), ("«t_end»", t_end)):
        if not (math.isfinite(v) and v > 0):
            raise UserError(f"{label} {v} must be a positive time")
    if success_time > t_end:
        raise UserError(f"«success_time={success_time:g}» is longer than «t_end={t_end:g}»: no run "
                        "could succeed; make «t_end» at least the success time")
    warnings = (reach_warnings(model, dists["spin"], interval, tau, success_time, "spin" not in given)
                + resonance_warnings(model, lin, dists["spin"], tau, success_time)
                + li.field_order_warnings(model, dists, z_s)) if warn else []
    choice = resolve(integrator, tol, None)
    method = choice.name
    refuse_on_full_model(method, "launch")
    if choice.entry.backend != "c" or choice.fixed_step:
        raise UserError(f"launch runs adaptive C integrators only (dop853, vern9, auto), not {integrator!r}")
    names = INPUTS + tuple(a.name for a in apparatus_of(model))
    plan = Plan(*model.ref, tuple((k, dists[k]) for k in names), int(n), int(seed),
                float(t_end), method, float(tol))
    workers = min(workers, runners.usable_cores())     # more processes than cores only queue
    return Prepared(plan, success_time, interval, z_s, tau, dict(given), tuple(warnings), workers, scheduler)


def execute(prep: Prepared, model, indices, quiet: bool = False, pool=None) -> list[dict]:
    """The launches `indices` of a prepared Monte Carlo: serially, on local processes (in `pool`, a
    runners.KeptPool, where given) or on dask; the chunks' results."""
    from levitron.runtime.scan import runners
    plan, workers, scheduler = prep.plan, prep.workers, prep.scheduler
    indices = list(indices)
    # serial runs go in chunks of ~20 launches too, so that the progress bar moves (the verdicts do
    # not depend on the chunking: each launch is its own run, test_launch_odds)
    n_chunks = max(1, workers) * 4 if (workers > 1 or scheduler) else max(1, min(50, len(indices) // 20))
    chunks = runners.split(indices, n_chunks)
    runners.remember(plan, model)
    if scheduler:
        with dask_errors_as_ours():
            client = runners.dask_client(scheduler)
            try:
                return runners.run_dask(plan, chunks, client, quiet, fn=run_chunk, what="launch")
            finally:
                client.close()
    if workers > 1:
        return runners.run_processes(plan, chunks, workers, quiet, fn=run_chunk, what="launch", pool=pool)
    return runners.run_serial(plan, chunks, quiet, fn=run_chunk, what="launch")


def summarize(plan: Plan, results, success_time: float, interval, z_s: float, tau,
              given=(), warnings=(), past=None) -> dict:
    """The answer (docs/contract.md `launch`) from the chunks' points (past: WindowJudge.mark's)."""
    pts = sorted((p for r in results for p in r["points"]), key=lambda p: p["i"])
    t = np.array([p["t"] for p in pts])
    status = [p["status"] for p in pts]
    up = t >= success_time * (1 - 1e-12)
    undecided = no_verdicts(status, up)            # left out of the odds (launch_window.py)
    ok = up & ~undecided
    decided = plan.n - int(undecided.sum())
    if decided == 0:
        raise UserError(none_decided(plan.n, status))
    k = int(ok.sum())
    S = samples(plan)
    lo, hi = wilson(k, decided)
    q1, med, q3 = (float(v) for v in np.quantile(t, [0.25, 0.5, 0.75]))
    dists = dict(plan.dists)
    return {
        "probability": k / decided, "probability_ci95": [lo, hi], "successes": k, "n": plan.n,
        "no_verdict": plan.n - decided,
        "seed": plan.seed, "success_time": success_time, "t_end": plan.t_end,
        "flight_time": {"median": med, "q1": q1, "q3": q3, "censored": int(np.sum(t >= plan.t_end * (1 - 1e-12))),
                        "values": t.tolist()},
        "outcomes": {s: status.count(s) for s in sorted(set(status))},
        "ranking": effects({k: v[~undecided] for k, v in S.items()}, ok[~undecided], dists),
        "inputs": {name: spec_text(name, d) for name, d in plan.dists},
        "defaulted": sorted(set(dists) - set(given)),
        "z_s": z_s, "spin_interval": list(interval) if interval else None,
        "spin_decay_time": tau, "integrator": plan.integrator, "tol": plan.tol,
        "verdicts": [None if u else bool(v) for v, u in zip(ok, undecided)],
        "past_window": past or {"launches": 0, "reason": None},
        "launches": launches(S, pts, ok, t),
        "warnings": list(warnings),
    }
