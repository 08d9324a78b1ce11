"""A kit off the line with its own scene keys (runtime/design/production.py): the spread of a scene
key, each kit's parameter vector, its stable band and its launches at its own parameters.

**A scene key's spread** is a deviation from the design, and says which: "rel:normal:0,0.02" (the
key's value times 1 + d; also "rel:2%"), "abs:normal:0,0.0002" (the value plus d, in the key's SI
unit); "uniform:LO,HI" and a number as for a launch (runtime/scan/spreads.py). The key must be a
number of the scene that enters the model's parameter vector (runtime/design/scene_keys.py: the
scene re-resolved with the key changed), not structure ([field], [model]); every draw (the
support of the launches' check, spreads.check_support) stays inside the key's bound (scene/keys.py
KEY_BOUNDS) and keeps its sign, and each kit re-resolves to a valid scene with the plate's
structural decisions (scene/plates): else a one-line UserError.

**A kit's band** (`kit_bands`): the masses its own plate and magnet hold in the stable band
(runtime/physics/equilibrium/bands.py: vertically stable and transversely stable for some spin),
whose position the owner trims for. The magnets' strength enters by the hover law: a top of mass m
hovers under moment mu where one of m / s hovers under mu / s (m g = -mu Phi_2, thesis 3.3.1), so
the band's masses are those of the kit's plate and inertia at the design's moment, times
mu_kit s / mu (the light edge also moves with mu beyond that: on reports/maker/myring.toml by
1e-5 of the mass for 2 % of strength, which the owner's curve cannot resolve). The plate's part
is a quadratic in each key's deviation, with a bilinear term for each pair of keys, through
2 k + 1 + k (k - 1) / 2 exact bands (k keys; `band_model`: at the spreads' centre, at +- NODE_SDS sd
of each key alone and at + NODE_SDS sd of each pair together): on myring.toml within 3e-5 of the
band's width for a 0.2 mm thickness spread, 4e-3 for 1 mm (against each kit's own scan, from -3 to
+3 sd), where the owner's curve has 9 points across the band. Two keys at once (thesis_stable, a
0.3 mm bore and a 0.5 mm radius spread): within 9e-4 of the width on the kits whose deviations
multiply most, 1.9e-2 without the pair's term; a 1 % radius and a 2 % remanence (plate.murho)
spread, 2.7e-4 against 1.7e-2 (one key changes what the other does: the remanence scales the shift
the radius gives the band). Where a node has no band (a
spread that wide) every kit's band is computed. An exact band opens at z_c, the heaviest hovering
mass (thesis 3.3.3; bands.py), so it is the plate's max_mass and its light edge, found by bisection
of bands.spin_stabilisable between z_c + half the design's band width and EDGE_BRACKET widths above
the design's light edge, after checking that the design's band opens at z_c and the plate's is
stable at EDGE_CHECKS heights from its z_c to the bracket (about 0.1 s); where a check fails, the
full band scan (equilibria_of(bands=True), about 0.5 s).

**A kit's launch** (`kit_points`): the launch of runtime/scan/launch_chunk.py run_chunk, each at
the kit's own parameter vector (its mass with the washers on, its moment times its strength) with
the hand's deviations on top, through the same C chunk driver and workers.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.scan.spreads import REL, Dist, check_support, parse_dist
from levitron.runtime.ui.validate import number_text
from levitron.scene.keys import KEY_BOUNDS, Bound

ABS = "abs:"
EDGE_BRACKET = 1.0       # the kit's light edge is sought up to this many of the design's band widths above it
EDGE_CHECKS = 4          # heights between z_c and the bracket where the kit's band must be stable
EDGE_RTOL = 1e-9         # the light edge's bisection, relative in z
NOT_KEYS = ("field", "model", "launch", "production", "reference")     # tables whose numbers are no parameter


@dataclass(frozen=True)
class KeySpread:
    """The spread of one scene key: a deviation d (relative or absolute) drawn from dist."""
    key: str
    relative: bool
    dist: Dist
    text: str

    def values(self, value: float, d: np.ndarray) -> np.ndarray:
        return value * (1 + d) if self.relative else value + d

    def value_dist(self, value: float) -> Dist:
        """The key's values as one Dist (for the support check)."""
        d = self.dist
        if not self.relative:
            return Dist(d.kind, value + d.a, d.b if d.kind == "normal" else value + d.b)
        if d.kind == "normal":
            return Dist("normal", value * (1 + d.a), abs(value) * d.b)
        ends = sorted((value * (1 + d.a), value * (1 + d.b)))
        return Dist(d.kind, ends[0], ends[1] if d.kind == "uniform" else 0.0)


def parse_spread(key: str, spec) -> KeySpread:
    """A scene key's kit spread (module docstring) -> KeySpread; one-line UserError otherwise."""
    said = f"«kit» {key}={spec}"
    how = "write a deviation from the design, e.g. rel:normal:0,0.02 (relative) or abs:normal:0,0.0002 (SI)"
    text = spec.strip() if isinstance(spec, str) else None
    if text is None or not text.lower().startswith((REL, ABS)):
        raise UserError(f"{said}: {how}")
    relative = text.lower().startswith(REL)
    body = text[len(REL):].strip()
    try:
        if relative and body.endswith("%"):
            sd = number_text(body[:-1].strip()) / 100
            if not (math.isfinite(sd) and sd >= 0):
                raise ValueError
            dist = Dist("normal", 0.0, sd + 0.0)
        else:
            dist = parse_dist(key, body, spec)
    except (UserError, ValueError):
        raise UserError(f"{said} is not a spread: {how}") from None
    return KeySpread(key, relative, dist, text)


def check_spreads(scene, names, spreads) -> None:
    """Each key a number of `scene` that enters the parameter vector (names: the model's), its
    draws inside its bound and sign (module docstring); one-line UserError otherwise."""
    from levitron.runtime.design.scene_keys import key_value, pvector, with_values
    from levitron.runtime.ui.frames import key_unit
    for s in spreads:
        if s.key.split(".")[0] in NOT_KEYS:
            raise UserError(f"«kit» {s.key}: [{s.key.split('.')[0]}] holds no parameter of the model: spread "
                            "a key of [top] or [plate] (docs/scenes.md)")
        v = key_value(scene.data, s.key)
        if v == 0:
            raise UserError(f"«kit» {s.key}: the scene's value is 0; a kit's spread is about a nonzero value")
        moved = pvector(names, with_values(scene, {s.key: v * (1 + 1e-6)}))
        if np.array_equal(moved, pvector(names, scene)):
            raise UserError(f"«kit» {s.key}: its value does not enter the model's parameters, so a spread of "
                            "it changes no kit: spread a key of [top] or [plate] (docs/scenes.md)")
        sign = (Bound(0.0, math.inf, lo_open=True, text="the key's sign (> 0)") if v > 0 else
                Bound(-math.inf, 0.0, hi_open=True, text="the key's sign (< 0)"))
        for bound in (sign, KEY_BOUNDS.get(s.key)):
            if bound is not None:
                check_support("kit", s.value_dist(v), f"{s.key}={s.text}", bound, key_unit(s.key))


def kit_vectors(model, spreads, deviations: dict) -> np.ndarray:
    """Each kit's parameter vector (n, P) at the model's scene with its keys' deviations {key: (n,)}."""
    from levitron.runtime.design.scene_keys import key_value, pvector, with_values
    from levitron.scene import plates
    scene, names = model.scene, model.param_names
    values = {s.key: s.values(key_value(scene.data, s.key), deviations[s.key]) for s in spreads}
    decided = plates.decisions(scene.data["plate"])
    n = len(next(iter(values.values())))
    out = np.empty((n, len(names)))
    for i in range(n):
        at = {k: float(v[i]) for k, v in values.items()}
        where = ", ".join(f"{k} = {v:.6g}" for k, v in at.items())
        try:
            sc = with_values(scene, at)
        except UserError as exc:
            raise UserError(f"«kit»: a kit at {where} is not a valid scene ({exc}): give a narrower spread") \
                from None
        if plates.decisions(sc.data["plate"]) != decided:
            raise UserError(f"«kit»: a kit at {where} changes the plate's structure: give a narrower spread")
        out[i] = pvector(names, sc)
    return out


def kit_bands(model, spreads, deviations: dict, p: np.ndarray, strength: np.ndarray, band) -> np.ndarray:
    """(n, 2) the stable band's masses [lightest, heaviest] of each kit (module docstring): spreads
    and deviations {key: (n,)} as kit_vectors takes them, p (n, P) the kits' vectors, strength (n,)
    their factors on mu, band the design's stable Band; nan where a kit has none. The plate's part
    by the quadratic through NODES exact bands a key (`band_model`), else kit by kit."""
    imu = model.param_names.index("mu")
    plates = band_model(model, spreads, deviations, band)
    if plates is None:
        plates = np.array([_band_at(model, q, band) for q in _at_design_top(model, p)])
    return plates * (p[:, imu] * strength / model.param("mu"))[:, None]


NODE_SDS = 2.0       # the nodes of a key's band model: its spread's centre and +- 2 sd (a uniform's ends)


def band_model(model, spreads, deviations: dict, band) -> np.ndarray | None:
    """(n, 2) the kits' plate bands at the design's moment from 2 k + 1 + k (k - 1) / 2 exact bands
    (k keys): at the spreads' centre, at +- NODE_SDS sd of each key alone and at + NODE_SDS sd of
    each pair of keys together: a quadratic in each key's deviation and a bilinear term for each
    pair; None where a node has no band (then every kit's is computed)."""
    centre = {s.key: (0.5 * (s.dist.a + s.dist.b) if s.dist.kind == "uniform" else s.dist.a) for s in spreads}
    half = {s.key: (0.5 * (s.dist.b - s.dist.a) if s.dist.kind == "uniform" else
                    NODE_SDS * s.dist.b if s.dist.kind == "normal" else 0.0) for s in spreads}
    pairs = list(itertools.combinations(range(len(spreads)), 2))
    nodes = [dict(centre)] + [{**centre, s.key: centre[s.key] + sign * half[s.key]}
                              for s in spreads for sign in (-1, 1)]
    nodes += [{**centre, spreads[i].key: centre[spreads[i].key] + half[spreads[i].key],
               spreads[j].key: centre[spreads[j].key] + half[spreads[j].key]} for i, j in pairs]
    rows = kit_vectors(model, spreads, {s.key: np.array([nd[s.key] for nd in nodes]) for s in spreads})
    got = [_band_at(model, q, band) for q in _at_design_top(model, rows)]
    if any(np.isnan(g).any() for g in got):
        return None
    n = len(deviations[spreads[0].key])
    out = np.tile(got[0], (n, 1))
    t, slope, curve = [], [], []
    for j, s in enumerate(spreads):
        lo, hi = got[1 + 2 * j], got[2 + 2 * j]
        t.append((deviations[s.key] - centre[s.key]) / half[s.key] if half[s.key] > 0 else np.zeros(n))
        slope.append(0.5 * (hi - lo))
        curve.append(0.5 * (hi + lo) - got[0])
        out += t[j][:, None] * slope[j] + (t[j] * t[j])[:, None] * curve[j]
    for k, (i, j) in enumerate(pairs):      # the corner (+h_i, +h_j) less what the keys alone give there
        cross = got[1 + 2 * len(spreads) + k] - got[0] - slope[i] - curve[i] - slope[j] - curve[j]
        out += (t[i] * t[j])[:, None] * cross
    return out


def _at_design_top(model, p: np.ndarray) -> np.ndarray:
    """The vectors p with the design's m and mu (a band is the plate's and the inertia's; mu scales it)."""
    q = np.array(p, float)
    q[:, model.param_names.index("mu")] = model.param("mu")
    q[:, model.param_names.index("m")] = model.param("m")
    return q


def _band_at(model, q, band) -> np.ndarray:
    """[lightest, heaviest] of the band at q (nan, nan where none): by the light edge where the
    design's band opens at z_c, else by the full scan."""
    got = (_edge_band(model, q, band) if _opens_at_zc(model, band) else None) or _full_band(model, q)
    return np.array(got if got is not None else (np.nan, np.nan), float)


def _full_band(model, q) -> tuple[float, float] | None:
    from levitron.runtime.physics.equilibrium import finder as eqm
    b = eqm.equilibria_of(model, q, bands=True).stable_band
    return None if b is None else (float(b.mass[0]), float(b.mass[1]))


def _opens_at_zc(model, band) -> bool:
    """The design's band runs from z_c (its heaviest mass is max_mass) up to its light edge."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    rep = eqm.equilibria_of(model)
    return (band is not None and rep.z_c is not None and abs(band.z[0] / rep.z_c - 1) < 1e-6
            and not any(band.at_search_end))


def _edge_band(model, q, band) -> tuple[float, float] | None:
    """The kit's band by its light edge's bisection (module docstring), or None where a check fails."""
    from levitron.runtime.physics.equilibrium import bands as bd
    from levitron.runtime.physics.equilibrium import finder as eqm
    rep = eqm.equilibria_of(model, q)
    z_c = rep.z_c
    if z_c is None or not rep.max_mass or rep.max_mass <= 0:
        return None
    P = model.pvals(q)
    onaxis = eqm.model_onaxis(model, q)
    phis = lambda z: [float(v) for v in np.asarray(onaxis(z), float)[:4]]
    stable = lambda z: bd.spin_stabilisable(phis(z), P["g"], P["A"], P["C"], P["mu"])
    width = band.z[1] - band.z[0]
    a, b = z_c + 0.5 * width, band.z[1] + EDGE_BRACKET * width
    if not (a < b and stable(a) and not stable(b)):
        return None
    if not all(stable(z) for z in np.geomspace(z_c * (1 + 1e-6), a, EDGE_CHECKS)):
        return None
    while b - a > EDGE_RTOL * b:
        mid = 0.5 * (a + b)
        a, b = (mid, b) if stable(mid) else (a, mid)
    light = -P["mu"] * phis(0.5 * (a + b))[2] / P["g"]
    return (light, float(rep.max_mass)) if 0 < light < rep.max_mass else None


@dataclass(frozen=True)
class KitPlan:
    """A Monte Carlo's plan (launch_odds.Plan: the hand's draws launch by launch) and each launch's
    parameter vector (rows: its kit's, mass and moment as the hand deviates from them)."""
    plan: object
    rows: tuple

    @property
    def scene(self) -> str:
        return self.plan.scene

    @property
    def overrides(self) -> tuple:
        return self.plan.overrides


def run_kit_chunk(kp: KitPlan, indices) -> dict:
    """launch_chunk.run_chunk with launch i at the parameter vector kp.rows[i] (module docstring)."""
    from levitron.runtime.scan.launch_chunk import run_chunk
    return run_chunk(kp.plan, indices, base=lambda i: kp.rows[i])


def kit_points(model, plan, rows: np.ndarray, pool, workers: int, scheduler: str | None = None) -> list[dict]:
    """The launches of `plan` (its dists each launch's draws) at the parameter vectors rows (n, P),
    run to plan.t_end: their points by launch (production._verdicts judges them), on `workers`
    local workers in pool, or on the dask scheduler at `scheduler` (as launch_odds.execute)."""
    from levitron.runtime.scan import runners
    kp = KitPlan(plan, tuple(tuple(float(v) for v in r) for r in rows))
    n = len(rows)
    chunks = runners.split(list(range(n)), workers * 4 if workers > 1 else max(1, min(50, n // 20)))
    runners.remember(kp, model)
    if scheduler:
        from levitron.runtime.scan.workers import dask_errors_as_ours
        with dask_errors_as_ours():
            client = runners.dask_client(scheduler)
            try:
                got = runners.run_dask(kp, chunks, client, True, fn=run_kit_chunk, what="launch")
            finally:
                client.close()
    elif workers > 1:
        got = runners.run_processes(kp, chunks, workers, True, fn=run_kit_chunk, what="launch", pool=pool)
    else:
        got = runners.run_serial(kp, chunks, True, fn=run_kit_chunk, what="launch")
    pts = sorted((p for r in got for p in r["points"]), key=lambda p: p["i"])
    return pts
