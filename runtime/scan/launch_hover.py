"""The hover heights of a batch of launches (thesis 3.3.2-3.3.3): each launch's top has its own mass
and magnet strength (the Monte Carlo's spreads), so each starts at its own z_s, the lowest vertically
stable root of F(z) = m g + mu Phi_2(z).

The plate's on-axis functions Phi_k do not depend on the top (U = m g z + mu Phi_1, thesis 3.3.1), so
the launches of one plate share one survey (runtime/physics/equilibrium/root_survey.py): its knots include every
zero of Phi_3, the extrema of F for every top, so between two knots F is monotone and a sign change
brackets exactly one root, vertically stable where F rises through zero (dF/dz = mu Phi_3 > 0). A
launch's root is its first rising sign change at the knots, refined by Newton's method on
(Phi_2, Phi_3) and then bisected to adjacent doubles as the survey's own search does: a handful of
evaluations of the generated onaxis where the survey's full search takes one bisection to adjacent
doubles per root. A plate with singular stretches, a root on a knot and a double root (a top at the
band's edge) take the full search (runtime.physics.equilibrium.finder.hover_height), whose answer this
equals: tests/runtime/scan/test_launch_hover.py holds the two equal launch by launch.
"""
from __future__ import annotations

import math

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium.finder import TOP_PARAMS, hover_height, params_of, plate_survey
from levitron.runtime.physics.equilibrium.root_survey import EPS, MARGINAL_ULPS

NEWTON_STEPS = 30          # Newton's iterations before the full search takes over
SURE = 1e-12               # F's sign is taken as known farther than this (relative) from Newton's root ...
ROUNDING = 64              # ... where |F| there exceeds this many eps of F's terms (|m g| + |mu Phi_2|)


def hover_heights(model, ps: np.ndarray) -> np.ndarray:
    """z_s for each parameter vector (row of ps, manifest order); NaN where the top cannot hover
    (where hover_height raises its one-line UserError)."""
    ps = np.atleast_2d(np.asarray(ps, float))
    out = np.full(len(ps), math.nan)
    top = [model.param_names.index(n) for n in TOP_PARAMS if n in model.param_names]
    plates: dict[bytes, list[int]] = {}
    for j, p in enumerate(ps):
        q = p.copy()
        q[top] = 0.0
        plates.setdefault(q.tobytes(), []).append(j)
    for rows in plates.values():
        sv = plate_survey(model, ps[rows[0]])
        phi2 = sv.column(2)
        for j in rows:
            z = None if sv.singularities else _fast(sv, phi2, params_of(model, ps[j]))
            out[j] = z if z is not None else _full(model, ps[j])
    return out


def _full(model, p: np.ndarray) -> float:
    try:
        return hover_height(model, p)
    except UserError:                 # NoHover, or a formula not finite there: a launch that cannot hover
        return math.nan


def _fast(sv, phi2: np.ndarray, P: dict) -> float | None:
    """The lowest vertically stable root of one top over the survey sv (phi2: Phi_2 at its knots;
    module docstring), or None
    where the full search must decide (a root on a knot, a double root, Newton leaving its bracket)."""
    mg, mu = P["m"] * P["g"], P["mu"]
    zs = sv.zs
    F = mg + mu * phi2
    if not np.all(np.isfinite(F)) or np.any(F == 0):
        return None
    for z in sv.extrema:                          # a double root: the survey flags it marginal
        mp2 = mu * sv.row(z)[2]
        if abs(mg + mp2) <= 4 * MARGINAL_ULPS * EPS * (abs(mg) + abs(mp2)):
            return None
    rising = np.flatnonzero((F[:-1] < 0) & (F[1:] > 0))
    if rising.size == 0:                          # no root, or only unstable ones: it cannot hover
        return math.nan
    i = int(rising[0])
    a, b = zs[i], zs[i + 1]

    def f(z: float) -> float:
        return mg + mu * float(sv.row(z)[2])

    z = a - F[i] * (b - a) / (F[i + 1] - F[i])   # the secant's first guess
    for _ in range(NEWTON_STEPS):
        r = sv.row(z)
        slope = mu * float(r[3])
        if not slope > 0:
            return None
        step = (mg + mu * float(r[2])) / slope
        z -= step
        if not a < z < b:
            return None
        if abs(step) <= 0.1 * SURE * z:          # well inside the zone the bisection ends in
            break
    else:
        return None
    zlo, zhi = z * (1 - SURE), z * (1 + SURE)
    if not a < zlo < zhi < b:
        return None
    flo, fhi, noise = f(zlo), f(zhi), ROUNDING * EPS * 2 * abs(mg)    # |mu Phi_2| = |m g| at the root
    if not (flo < -noise and fhi > noise):        # too flat to trust the sides' signs: the full search
        return None
    lo, hi, flo, fhi = _bisect_as_survey(f, a, b, float(F[i]), float(F[i + 1]), zlo, zhi)
    if lo == hi:
        return lo if flo == 0 else None
    best, fbest = (lo, flo) if abs(flo) <= abs(fhi) else (hi, fhi)
    return best if abs(fbest) <= max(abs(F[i]), abs(F[i + 1])) else None   # else a pole: the full search


def _bisect_as_survey(f, a: float, b: float, fa: float, fb: float, zlo: float, zhi: float):
    """The survey's bisection of a rising bracket [a, b] (fa < 0 < fb) to adjacent doubles
    (root_survey._bisect), midpoint for midpoint, evaluating f only inside [zlo, zhi], where
    f(zlo) < 0 < f(zhi) were checked to exceed F's rounding: outside it F is monotone between
    knots and farther from zero, so its sign is its side's. The same midpoints and signs give the
    same doubles as the full search, in a few dozen evaluations instead of one per step."""
    while True:
        mid = 0.5 * (a + b)
        if not a < mid < b:
            return a, b, (f(a) if math.isnan(fa) else fa), (f(b) if math.isnan(fb) else fb)
        if mid <= zlo:
            a, fa = mid, math.nan                 # negative, not evaluated
            continue
        if mid >= zhi:
            b, fb = mid, math.nan                 # positive, not evaluated
            continue
        fm = f(mid)
        if fm == 0 or not math.isfinite(fm):
            return mid, mid, fm, fm
        if fm < 0:
            a, fa = mid, fm
        else:
            b, fb = mid, fm
