"""Bases compared under one hand: `Comparison`, the answer of `levitron compare SCENE SCENE ...`.

The default launch spread of `levitron launch` is scaled per scene (its spin the geometric mean of
the scene's own window, its offsets 1 % of its own hover height: runtime/scan/launch_odds.py), so
the default odds of two bases answer two different hands. Here every scene is launched by ONE
hand:

1. **The hand.** The launch flags where given; every other input of the hand (spin, tilt, offset,
   velocity, the relative mass and strength spreads) and the success time and run length are the
   FIRST scene's, resolved as `levitron launch` resolves them (its [launch] table over the
   defaults, pinned at its hover point: launch_odds.prepare, the same step as launch_design.py's
   `Pinned`). The magnets' temperature and a base's apparatus (its tilt) are each scene's own
   unless a flag gives them: they are the scene, not the hand. The mass spread must be relative
   (a spread in kg means another thing for another top).
2. **Each scene under it.** The hover height z_s and the stable band (thesis 3.3.2-3.3.3: the
   heights whose top, of mass m(z) = -mu Phi_2(z)/g, has a spin interval of linear stability, and
   their masses), the spin window at z_s (the discriminant route, thesis 3.3.15-3.3.19), the weight
   window (the mass that can go on or come off before the top leaves the band), the launch odds
   at the scene's own mass (the hand's seed: exactly what `levitron launch SCENE` gives with the
   hand as flags) and at its best mass: the trim's launch-odds design over top.mass in the band
   (runtime/design/trim.py; its odds on the fresh seed, seed + 1, as every design decides).
3. **The yield of a production run** of each scene as written under the same hand and the same
   production run (runtime/design/production.py: the kits' spread, the washers in the box, the
   kits; the defaults where not given): the kits that float a launch after their owners trim them,
   and the same kits as shipped.

Every Monte Carlo of the comparison runs in one kept pool of workers (launch_design.kept_pool).
"""
from __future__ import annotations

import contextlib
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from levitron.runtime.design import launch_design as ld
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.errors import UserError
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan import spreads
from levitron.runtime.scan.launch_inputs import INPUTS
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units, sig

HAND = tuple(k for k in INPUTS if k != "temperature")     # the hand's inputs; the temperature is the scene's


@dataclass(frozen=True, repr=False)
class Comparison:
    """Scenes under one launch spread (docs/contract.md `compare`): `rows`, one a scene (SI: z_s,
    band_z, band_mass, mass, spin_interval, weight_window [kg off, kg on], launch_odds at the
    scene's mass, best_mass and best_launch_odds; `reason` where a scene cannot hover), `hand`
    (inputs, source of each, n, seed, success_time, t_end) and `si` (the scenes' units)."""
    rows: list = field(default_factory=list)
    hand: dict = field(default_factory=dict)
    si: bool = True

    @property
    def message(self) -> str:
        """The scene whose top floats most often at its best mass, under the hand."""
        best = max(self.rows, key=lambda r: (r["best_launch_odds"] or r["launch_odds"])["probability"])
        odds = (best["best_launch_odds"] or best["launch_odds"])["probability"]
        if odds <= 0:
            return "no scene floats under this hand, at any mass: a steadier hand, or another spin"
        return f"{best['scene']} floats most often under one hand: {100 * odds:.3g} % at its best mass"

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (comparison_view of as_json: the one wording of every face), in the
        scenes' units (`units`: their quantities' only), worded for `face` (None: markers kept)."""
        u = units or Units(si=self.si)
        return worded(comparison_view(self.as_json()), u, face)

    def __repr__(self) -> str:
        return text_repr("Comparison", [self.message])   # short: the answer

    def _repr_html_(self) -> str:
        return html_table("Comparison", self.lines())

    def as_json(self) -> dict:
        """docs/contract.md's `compare --json` (SI)."""
        return {"rows": self.rows, "hand": self.hand, "units": "SI" if self.si else "dimensionless",
                "message": self.message}


def shared_hand(first, request: mc.Request, flags: Sequence[str] = ()) -> tuple[mc.Request, dict]:
    """The one hand (module docstring, step 1) resolved at the first scene's model, and its block;
    `request` over the first scene's [launch] table, `flags` the inputs the caller gave."""
    mass = request.given.get("mass")
    if mass is not None and not str(mass).strip().lower().startswith(spreads.REL):
        raise UserError("compare launches different tops: the «mass» spread must be relative, e.g. "
                        "rel:normal:0,0.002 (or rel:0.2%)")
    try:
        prep = mc.prepare(first, request.given, request.n, request.seed, request.success_time, request.t_end,
                          request.integrator, request.tol, request.workers, request.scheduler)
    except UserError as exc:
        raise UserError(f"the first scene, {first.scene.name}, gives the shared launch spread and cannot ({exc}): "
                        "put a scene that hovers first, or give every launch input") from None
    dists = dict(prep.plan.dists)
    inputs = {k: spreads.spec_text(k, dists[k]) for k in HAND if k in dists}
    inputs.update({k: str(v) for k, v in request.given.items()})
    hand = mc.Request(inputs, request.n, request.seed, prep.success_time, prep.plan.t_end, request.integrator,
                      request.tol, request.workers, request.scheduler)
    source = {k: "given" if k in flags else first.scene.name for k in inputs}
    return hand, {"inputs": inputs, "source": source, "n": hand.n, "seed": hand.seed,
                  "success_time": hand.success_time, "t_end": hand.t_end, "first_scene": first.scene.name}


def compare(models: Sequence, request: mc.Request, flags: Sequence[str] = (), production=None) -> Comparison:
    """The comparison of the module docstring for loaded models (two or more): `request` the launch
    request over the first scene's [launch] table, `flags` the inputs the caller gave, `production`
    the production run of every scene's yield (None: production.Production.of()'s defaults)."""
    from levitron.runtime.design.production import Production
    production = production or Production.of(seed=request.seed)
    if len(models) < 2:
        raise UserError("compare needs two scenes or more (e.g. thesis_air and levitron_toy): give another")
    kinds = {m.scene.name: Units.of_scene(m.scene).si for m in models}
    if len(set(kinds.values())) > 1:
        raise UserError("compare: " + ", ".join(k for k, v in kinds.items() if not v) + " is dimensionless and "
                        + ", ".join(k for k, v in kinds.items() if v) + " is in SI: compare scenes of one kind")
    hand, block = shared_hand(models[0], request, flags)
    with contextlib.ExitStack() as stack:
        pool = ld.kept_pool(stack, hand, hand.n)
        rows = [{**_row(m, hand, pool), **_yield(m, hand, production, pool)} for m in models]
    block["production"] = {"kit": dict(production.specs), "washers": list(production.washers),
                           "kits": production.kits, "seed": production.seed}
    return Comparison(rows, block, next(iter(kinds.values())))


def _yield(model, hand: mc.Request, production, pool) -> dict:
    """The scene's yield under the hand (module docstring, step 3): {"yield", "yield_as_shipped"}
    (None with `yield_reason` where the scene cannot be launched)."""
    from levitron.runtime.design.production import production_yield
    try:
        prep = mc.prepare(model, hand.given, production.kits, hand.seed, hand.success_time, hand.t_end,
                          hand.integrator, hand.tol, hand.workers, hand.scheduler)
    except UserError as exc:
        return {"yield": None, "yield_as_shipped": None, "yield_reason": str(exc)}
    from levitron.runtime.ui import progress
    with progress.task(f"{model.scene.name}: the yield of {production.kits} kits", total=1, log_every=10.0) as tick:
        got = production_yield(model, prep.plan, prep.success_time, ld._search_time(model, prep), production, pool,
                               scheduler=prep.scheduler)
        tick()
    return {"yield": got["yield"], "yield_as_shipped": got["as_shipped"]}


def _row(model, hand: mc.Request, pool) -> dict:
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.physics.stability.analysis import stability_of
    m = model.param("m")
    row = {"scene": model.scene.name, "mass": m, "z_s": None, "band_z": None, "band_mass": None,
           "spin_interval": None, "weight_window": None, "best_mass": None, "best_launch_odds": None}
    band = eqm.equilibria_of(model, bands=True).stable_band
    if band is not None:
        row.update(band_z=list(band.z), band_mass=list(band.mass),
                   weight_window=[band.mass[0] - m, band.mass[1] - m])
    try:
        st = stability_of(model, eigen=False)
        iv = st.spin_interval
        row.update(z_s=st.z_s, spin_interval=None if iv is None else [float(iv[0]), float(iv[1])])
    except UserError as exc:
        row["reason"] = str(exc)
    odds = hand.run(model, quiet=True, pool=pool)
    row["launch_odds"] = ld.odds_dict(odds)
    if odds.get("reason"):
        row["reason"] = odds["reason"]
    if band is not None:
        pinned = ld.Pinned(hand, {"defaulted": []})
        try:
            design = ld.maximize_launch_odds(model, [Vary("top.mass", *band.mass)], hand, pinned,
                                             where="the masses that hover (the stable band)", pool=pool)
            row.update(best_mass=design.optimum["top.mass"], best_launch_odds=design.launch_odds)
        except UserError as exc:        # no launch floats at any mass: the row says so
            row["best_reason"] = str(exc)
    return row


def window(u: Units, iv) -> str:
    """A spin window, short: in Hz in an SI scene (what a maker's tachometer reads), else rad/time."""
    if not iv:
        return "-"
    if u.si:
        return f"{sig(iv[0] / (2 * math.pi), 3)}-{sig(iv[1] / (2 * math.pi), 3)} Hz"
    return f"{sig(iv[0], 4)}-{sig(iv[1], 4)} {u.unit('rad/s')}"


def comparison_lines(r: dict, spread: str = "") -> list[str]:
    """The plain view: the hand in one line (`spread`: its inputs in words, the face's), then one
    table row a scene (the scenes' units)."""
    u = Units(si=r.get("units", "SI") == "SI")
    h = r["hand"]
    flags = [k for k, s in h["source"].items() if s == "given"]
    hand = (f"one hand for every scene: the launch spread of {h['first_scene']} (its [launch] table and defaults)"
            + (f", {', '.join(flags)} as given" if flags else "")
            + f"; {h['n']} launches (seed {h['seed']}) floating at least {u.time(h['success_time'])}"
            + (f": {spread}" if spread else ""))

    def odds(block):
        return "-" if block is None else f"{sig(100 * block['probability'], 3)} %"
    head = ("scene", "hovers at", "stable band", "masses that hover", "spin window", "weight window",
            "odds as is", "best mass: odds", "yield (shipped)")
    table = [head]
    for row in r["rows"]:
        ww = row["weight_window"]
        table.append((
            row["scene"], u.length(row["z_s"]) if row["z_s"] is not None else "-",
            u.length_span(*row["band_z"]) if row["band_z"] else "-",
            f"{u.mass(row['band_mass'][0])} to {u.mass(row['band_mass'][1])}" if row["band_mass"] else "-",
            window(u, row["spin_interval"]),
            f"{u.mass(-ww[0])} off, {u.mass(ww[1])} on" if ww else "-",
            odds(row["launch_odds"]),
            f"{u.mass(row['best_mass'])}: {odds(row['best_launch_odds'])}" if row["best_mass"] is not None
            else "none floats" if row.get("best_reason") else "-",
            f"{odds(row.get('yield'))} ({odds(row.get('yield_as_shipped'))})" if row.get("yield") else "-"))
    widths = [max(len(t[i]) for t in table) for i in range(len(head))]
    out = ["  ".join(c.ljust(w) for c, w in zip(t, widths)).rstrip() for t in table]
    notes = [f"{row['scene']}: {row['reason']}" for row in r["rows"] if row.get("reason")]
    p = h.get("production")
    run = "" if not p else (f"the yield: {p['kits']} kits, magnets and tops spread as "
                            + ", ".join(f"{k} {v}" for k, v in p["kit"].items())
                            + (f", trimmed with washers of {', '.join(u.mass(w) for w in p['washers'])}" if p["washers"]
                               else ", no washers in the box (the yield is as shipped)"))
    return [hand, *out, *notes, run, r.get("message", ""), u.note]


def comparison_view(r: dict) -> list[str]:
    """The plain view of a comparison's JSON, its hand's inputs in words (comparison_lines)."""
    from levitron.runtime.scan.launch_answer import launch_input
    u = Units(si=r.get("units", "SI") == "SI")
    return comparison_lines(r, "; ".join(launch_input(k, v, u) for k, v in r["hand"]["inputs"].items()))
