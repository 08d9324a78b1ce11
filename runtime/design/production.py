"""The yield of a production run: the chance that a kit off the line, trimmed by its owner with
the washers in the box, floats a launch by hand.

A maker cannot buy magnets without a spread (ferrite grades: about +-2.5 % in remanence), so a kit
is not the scene as written: its magnets' strength and its top's mass are drawn from the
manufacturing spread (`Production.kit`: relative spreads of "strength", the product of the top's
moment and the plate's strength, thesis 2.2.1, and of "mass"), and so may any scene key that is a
parameter of the model (`Production.keys`: a plate's thickness, its remanence, the top's moment;
runtime/design/kits.py), each kit then with its own parameter vector. Each kit ships with the same
washers; its owner puts on the subset of them with which the top floats most often, and launches
by the scene's hand (the spread of `levitron launch`, pinned as a design pins it). The yield is the
probability that such a launch floats at least the success time: over kits and launches, one
launch a kit, so its 95 % interval is the Wilson interval of independent draws.

The owner's choice (`owner_choice`). The owner knows the scene's odds against the top's place in
its stable band (`owner_curve`: CURVE_POINTS masses across the band, CURVE_N launches each on
common draws, judged at the design's search time, runtime/design/launch_design.py; each mass's
position (m - lo) / (hi - lo) in the band [lo, hi]), and puts the kit's trimmed top where they are
best in the kit's own band, the band of its own plate and magnet (kits.py kit_bands): the washer
total whose position (m + w - lo_k) / (hi_k - lo_k) has the best odds on the curve (0 outside the
band; ties: the one nearest the curve's best, the middle of its plateau). This is an owner who knows
the curve, as one who tries each washer set with many launches learns it. Where only the strength
and the mass spread, the kit's band is the scene's times its strength s (the hover condition
m g = -mu Phi'(z), thesis 3.3.1, depends on m / mu only), and the position is that of the
"equivalent mass" (m + w) / s in the scene's band: the same choice. The spin window moves with s as
well (the torque scales with mu, the inertia does not), which the kits' own launches, run at their
own parameters, count, and the curve does not.

The decision (`production_yield`): every kit's one launch at its trimmed mass and its own
parameters, run in full to the success time on fresh draws. Beside it the same kits and launches as
shipped (no washer): what the washers buy, launch by launch. The cost is CURVE_POINTS x CURVE_N
launches at the search time and 2 x kits at the success time; with k scene keys spread, 2 k + 1
exact bands (kits.py band_model) and a hover survey for each kit's launch.
"""
from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from levitron.runtime.design.kits import KeySpread, kit_bands, kit_points, kit_vectors, parse_spread
from levitron.runtime.integrate.verdict import PAST_WINDOW
from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan.launch_summary import wilson
from levitron.runtime.scan.launch_window import WindowJudge
from levitron.runtime.scan.spreads import Dist, parse_input
from levitron.runtime.ui.validate import count
from levitron.runtime.words import si

KITS = 300                 # kits of a production run, one launch each
CURVE_POINTS = 9           # masses of the owner's curve across the stable band
CURVE_N = 150              # launches at each, on common draws
MAX_WASHERS = 8            # washers in the box (2^8 subsets)
KIT_SPREAD = {"strength": "rel:normal:0,0.02", "mass": "rel:normal:0,0.003"}
STREAMS = {"curve": 1, "kits": 2, "hand": 3}      # the random streams after the seed


class Each:
    """A launch input given launch by launch (the values, in order): what a kit's trim sets."""
    kind = "each"
    a = b = 0.0
    spread = True

    def __init__(self, values: Sequence[float]):
        self.values = np.asarray(values, float)

    def sample(self, rng, n: int) -> np.ndarray:
        return self.values[:n]


@dataclass(frozen=True)
class Production:
    """A production run: the kits' manufacturing spread (relative: {"strength": Dist, "mass": Dist};
    `keys`: the scene keys' spreads, kits.py), the washers in each box (masses, each put on at most
    once), how many kits, the seed."""
    kit: Mapping[str, Dist]
    washers: tuple[float, ...] = ()
    kits: int = KITS
    seed: int = 0
    specs: Mapping[str, str] = field(default_factory=dict)       # the spreads as given
    keys: tuple[KeySpread, ...] = ()

    @classmethod
    def of(cls, kit: Mapping[str, str] | None = None, washers: Sequence[float] | None = None,
           kits: int | None = None, seed: int = 0, table: Mapping | None = None) -> Production:
        """Checked: kit {"strength"|"mass": relative spread, or a scene key "section.key": its
        deviation (kits.py)} over the scene's [production] table's over KIT_SPREAD's defaults,
        washers positive masses (at most MAX_WASHERS), kits a whole number >= 10; washers and kits
        None: the table's, else none and KITS. table: the scene's [production] (kit, washers, kits)."""
        t = table_settings(table)
        tabled = {f"«kit» {k}" for k in set(t.get("kit", {})) - set(kit or {})} | \
            ({"«washers»"} if washers is None and "washers" in t else set()) | \
            ({"«kits»"} if kits is None and "kits" in t else set())
        try:
            return cls._of(dict(kit or {}), washers, kits, seed, t)
        except UserError as exc:       # a value of the scene's table is refused as the table's
            said = str(exc)
            if not any(said.startswith(m) for m in tabled):
                raise
            raise UserError(said.replace("«kit» ", "[production.kit] ").replace("«washers»", "[production] washers")
                            .replace("«kits»", "[production] kits")) from None

    @classmethod
    def _of(cls, kit: Mapping[str, str], washers, kits, seed: int, t: Mapping) -> Production:
        specs = {**KIT_SPREAD, **t.get("kit", {}), **kit}
        washers = t.get("washers", ()) if washers is None else washers
        kits = t.get("kits", KITS) if kits is None else kits
        unknown = sorted(k for k in set(specs) - set(KIT_SPREAD) if "." not in str(k))
        if unknown:
            raise UserError(f"«kit» {unknown[0]}: a kit's spread is of strength or mass, e.g. «kit» "
                            "strength=rel:normal:0,0.02, or of a scene key, e.g. «kit» "
                            "plate.thickness=abs:normal:0,0.0002")
        dists = {k: parse_input(k, specs[k]) for k in KIT_SPREAD}
        for k in dists:
            if not str(specs[k]).strip().lower().startswith("rel:"):
                raise UserError(f"«kit» {k}={specs[k]}: a kit's spread is relative, e.g. rel:normal:0,0.02")
        keys = tuple(parse_spread(k, specs[k]) for k in sorted(set(specs) - set(KIT_SPREAD)))
        ws = []
        for w in washers:
            try:
                v = float(w)
            except (TypeError, ValueError):
                raise UserError(f"«washers» {w!r} is not a mass: give masses, e.g. «washers» 0.0002,0.0005") \
                    from None
            if not (math.isfinite(v) and v > 0):
                raise UserError(f"«washers» {w!r}: a washer's mass must be a positive number")
            ws.append(v)
        if len(ws) > MAX_WASHERS:
            raise UserError(f"«washers»: {len(ws)} washers; give at most {MAX_WASHERS}")
        if isinstance(kits, bool) or not isinstance(kits, (int, np.integer)) or not 10 <= kits <= mc.MAX_N:
            raise UserError(f"«kits» {kits!r}: give a whole number of kits from 10 to {mc.MAX_N}")
        return cls(dists, tuple(ws), int(kits), int(seed), specs, keys)

    def totals(self) -> np.ndarray:
        """Every mass the washers can add (each at most once), 0 included, sorted, distinct."""
        sums = {round(sum(c), 15) for r in range(len(self.washers) + 1)
                for c in itertools.combinations(self.washers, r)}
        return np.array(sorted(sums))

    def with_seed(self, seed: int) -> Production:
        return replace(self, seed=int(seed))

    def with_kits(self, kits: int) -> Production:
        return replace(self, kits=int(kits))


def table_settings(table: Mapping | None) -> dict:
    """The scene's [production] table (scene/load.py checked its keys): {"kit": {key: spec} (a
    nested table's keys joined: [production.kit] plate.thickness = ...), "washers", "kits"}, each
    where given; one-line UserErrors naming the table's key."""
    if not table:
        return {}
    out: dict = {}
    if "kit" in table:
        if not isinstance(table["kit"], Mapping):
            raise UserError("[production] kit must be a table of spreads, e.g. [production.kit] with "
                            "strength = \"rel:normal:0,0.02\" and plate.thickness = \"abs:normal:0,0.0002\"")
        out["kit"] = dict(_joined(table["kit"]))
    if "washers" in table:
        if not isinstance(table["washers"], list):
            raise UserError(f"[production] washers = {table['washers']!r} must be a list of masses, e.g. "
                            "washers = [\"0.2 g\", \"0.4 g\"]")
        out["washers"] = table["washers"]
    if "kits" in table:
        out["kits"] = count(table["kits"], "[production] kits", low=10, high=mc.MAX_N)
    return out


def _joined(table: Mapping, prefix: str = ""):
    for k, v in table.items():
        if isinstance(v, Mapping):
            yield from _joined(v, f"{prefix}{k}.")
        else:
            yield f"{prefix}{k}", v


def _rng(seed: int, stream: str) -> np.random.Generator:
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence([int(seed), STREAMS[stream]])))


def _hand(plan: mc.Plan, n: int, rng) -> dict[str, np.ndarray]:
    """n draws of the pinned hand's every input (mass and strength: relative deviations)."""
    return {name: np.asarray(d.sample(rng, n), float) for name, d in plan.dists}


def _verdicts(model, plan: mc.Plan, draws: Mapping[str, np.ndarray], success_time: float, pool,
              rows: np.ndarray | None = None, scheduler: str | None = None) -> np.ndarray:
    """The launches `draws` (every input launch by launch) run to plan.t_end: floats or not. rows
    (n, P): each launch at its own parameter vector, mass and strength deviating from its (kits.py)."""
    n = len(next(iter(draws.values())))
    each = replace(plan, dists=tuple((k, Each(draws[k])) for k, _ in plan.dists), n=n)
    if rows is not None:
        pts = kit_points(model, each, rows, pool, plan_workers(n), scheduler)
    else:
        prep = mc.Prepared(each, success_time, None, math.nan, None, {}, (), plan_workers(n), scheduler)
        pts = sorted((p for r in mc.execute(prep, model, range(n), quiet=True, pool=pool) for p in r["points"]),
                     key=lambda p: p["i"])
    # a launch up past its window floats no more than in `launch` (runtime/scan/launch_window.py)
    WindowJudge(model, _interval(model), None if rows is None else rows.__getitem__).mark(
        draws["spin"], success_time, [{"points": pts}])
    return np.array([p["t"] >= success_time * (1 - 1e-12) and p["status"] != PAST_WINDOW for p in pts])


def _interval(model):
    """The scene's top's spin interval (the exact route), None where it has none or no friction
    asks for it; kept on the model (a design asks it of one model for every curve and kit run)."""
    from levitron.runtime.physics.apparatus.friction import has_friction
    from levitron.runtime.physics.stability.analysis import stability_of
    if not has_friction(model):
        return None
    if "_window_interval" not in model.__dict__:
        try:
            model.__dict__["_window_interval"] = stability_of(model, eigen=False).spin_interval
        except UserError:
            model.__dict__["_window_interval"] = None
    return model.__dict__["_window_interval"]


def plan_workers(n: int) -> int:
    from levitron.runtime.scan import runners
    from levitron.runtime.scan.workers import auto_workers
    return min(auto_workers(n), runners.usable_cores())


def scene_band(model):
    """The stable band of the model's scene (runtime/physics equilibria, bands=True), None if none."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    return eqm.equilibria_of(model, bands=True).stable_band


def owner_curve(model, plan: mc.Plan, search_time: float, seed: int, pool=None, band=None,
                scheduler: str | None = None) -> dict:
    """The scene's odds against the top's place in its stable band (module docstring): CURVE_POINTS
    masses inside the band (band: scene_band's, computed where None), CURVE_N launches each on the
    same draws, judged at search_time. {"mass" (kg), "position" in the band, "odds", "best" (kg),
    "best_position", "band" [lo, hi] kg}; None where no mass hovers."""
    band = scene_band(model) if band is None else band
    if band is None:
        return None
    lo, hi = band.mass
    position = (np.arange(CURVE_POINTS) + 0.5) / CURVE_POINTS
    masses = lo + (hi - lo) * position
    hand = _hand(plan, CURVE_N, _rng(seed, "curve"))
    m0 = model.param("m")
    draws = {k: np.tile(v, CURVE_POINTS) for k, v in hand.items()}
    draws["mass"] = np.repeat(masses / m0, CURVE_N) * (1 + draws["mass"]) - 1
    ok = _verdicts(model, replace(plan, t_end=search_time), draws, search_time, pool, scheduler=scheduler)
    odds = ok.reshape(CURVE_POINTS, CURVE_N).mean(axis=1)
    top = masses[odds >= odds.max()]
    best = 0.5 * float(top.min() + top.max())
    return {"mass": masses.tolist(), "position": position.tolist(), "odds": odds.tolist(), "best": best,
            "best_position": (best - lo) / (hi - lo), "band": [float(lo), float(hi)]}


def owner_choice(curve: dict, mass: np.ndarray, band: np.ndarray, totals: np.ndarray) -> np.ndarray:
    """Each kit's washer total (module docstring): the one whose position (m + w - lo_k) / (hi_k - lo_k)
    in the kit's own band band[k] = [lo_k, hi_k] (nan: none) has the best odds on the curve (0
    outside the band), ties to the curve's best position (a kit without a band: no washer)."""
    x, f = np.asarray(curve["position"]), np.asarray(curve["odds"])
    lo, hi = band[:, :1], band[:, 1:]
    with np.errstate(invalid="ignore"):
        pos = (mass[:, None] + totals[None, :] - lo) / (hi - lo)
        inside = (pos >= 0) & (pos <= 1)
    score = np.where(inside, np.interp(np.where(inside, pos, 0.0), x, f), 0.0)
    near = np.where(np.isnan(pos), -totals[None, :], -np.abs(pos - curve["best_position"]))
    order = np.lexsort((near, score), axis=1)[:, -1]         # best score, then nearest the best
    return totals[order]


def draw_kits(model, prod: Production, band) -> dict:
    """The production run's kits at the model (a design point): {"strength", "mass" (kg), "band"
    (n, 2) kg, "rows" (n, P) each kit's parameter vector, None where only strength and mass
    spread}, from the seed's "kits" stream (strength, mass, then the keys in order)."""
    n = prod.kits
    rng = _rng(prod.seed, "kits")
    kit = {k: 1 + np.asarray(prod.kit[k].sample(rng, n), float) for k in ("strength", "mass")}
    deviations = {s.key: np.asarray(s.dist.sample(rng, n), float) for s in prod.keys}
    if not prod.keys:
        return {"strength": kit["strength"], "mass": model.param("m") * kit["mass"],
                "band": np.outer(kit["strength"], band.mass), "rows": None}
    rows = kit_vectors(model, prod.keys, deviations)
    im, imu = model.param_names.index("m"), model.param_names.index("mu")
    mass = rows[:, im] * kit["mass"]
    bands = kit_bands(model, prod.keys, deviations, rows, kit["strength"], band)
    rows[:, imu] *= kit["strength"]
    return {"strength": kit["strength"], "mass": mass, "band": bands, "rows": rows}


def production_yield(model, plan: mc.Plan, success_time: float, search_time: float, prod: Production,
                     pool=None, as_shipped: bool = True, scheduler: str | None = None) -> dict:
    """The yield of the module docstring at the loaded model (a design point): {"yield": the answer
    block (probability, probability_ci95, kits, seed, successes), "as_shipped" (the same kits and
    launches with no washer; as_shipped False: not run), "untrimmable" (the fraction of kits no
    washer total puts in their band's odds), "washers_used" {total: kits}, "curve", "verdicts" (each
    kit's launch, in order: the pairing of two designs)}; where no mass hovers over the model,
    yield 0 with the reason. scheduler: a dask scheduler's address the launches run on (as launch's)."""
    if prod.keys:
        from levitron.runtime.design.kits import check_spreads
        check_spreads(model.scene, model.param_names, prod.keys)
    band = scene_band(model)
    curve = owner_curve(model, plan, search_time, prod.seed, pool, band, scheduler) if band is not None else None
    n = prod.kits
    if curve is None or max(curve["odds"]) <= 0:
        reason = ("no mass hovers over this design (no stable band)" if curve is None else
                  "no launch of the owner's curve floats: no washer can help")
        zero = {"probability": 0.0, "probability_ci95": [0.0, wilson(0, n)[1]], "kits": n, "seed": prod.seed,
                "successes": 0}
        return {"yield": zero, "as_shipped": zero if as_shipped else None, "untrimmable": 1.0,
                "washers_used": {}, "curve": curve, "reason": reason, "verdicts": [False] * n}
    kits = draw_kits(model, prod, band)
    mass, totals = kits["mass"], prod.totals()
    chosen = owner_choice(curve, mass, kits["band"], totals)
    lo, hi = kits["band"][:, :1], kits["band"][:, 1:]
    with np.errstate(invalid="ignore"):
        pos = (mass[:, None] + totals[None, :] - lo) / (hi - lo)
        reach = ((pos >= 0) & (pos <= 1) & (np.interp(np.nan_to_num(pos), curve["position"], curve["odds"]) > 0))
    hand = _hand(plan, n, _rng(prod.seed, "hand"))
    m0 = model.param("m")

    def run(added):
        draws = dict(hand)
        if kits["rows"] is not None:        # each kit at its own parameters, the hand's deviations on top
            rows = kits["rows"].copy()
            rows[:, model.param_names.index("m")] = mass + added
            return _verdicts(model, plan, draws, success_time, pool, rows, scheduler)
        draws["mass"] = (mass + added) / m0 * (1 + hand["mass"]) - 1
        draws["strength"] = kits["strength"] * (1 + hand["strength"]) - 1
        return _verdicts(model, plan, draws, success_time, pool, scheduler=scheduler)

    def block(ok):
        k = int(ok.sum())
        return {"probability": k / n, "probability_ci95": list(wilson(k, n)), "kits": n, "seed": prod.seed,
                "successes": k}
    ok = run(chosen)
    used = {float(w): int(np.sum(chosen == w)) for w in totals}
    return {"yield": block(ok), "as_shipped": block(run(np.zeros(n))) if as_shipped else None,
            "untrimmable": float(1 - reach.any(axis=1).mean()), "washers_used": used, "curve": curve,
            "verdicts": ok.tolist()}


def washer_text(used: Mapping[float, int], mass=lambda w: si(w, "kg")) -> str:
    """How the kits were trimmed: the totals their owners chose (mass(w) its words), most used first."""
    parts = [f"{mass(w) if w else 'none'}: {k}" for w, k in sorted(used.items(), key=lambda t: -t[1]) if k]
    return ", ".join(parts)
