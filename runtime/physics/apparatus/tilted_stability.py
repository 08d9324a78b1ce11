"""Linear stability of the spinning top over a tilted base (plate.tilt): route "eigenvalues" only.

The relative equilibrium (runtime/physics/apparatus/tilted_equilibrium.py) is off the axis with the axis
tilted, so the ray polynomial of thesis 3.3.9-3.3.16 (route "discriminant", which rests on the
axial symmetry) does not apply: it serves a level apparatus only. The eigenvalue route does: the
generated Jacobian `full_jac` at the equilibrium, reduced by the top's own rotation (the cyclic
zeta and its momentum p_zeta = C sigma, the spin, are dropped: zeta's column and p_zeta's row
vanish), a 10x10 matrix whose eigenvalues all lie on the imaginary axis exactly where the top is
linearly stable (runtime/physics/routes/eigen_route.py `on_imaginary_axis`); the spin interval is scanned
and bisected to its ends as the level eigen route does (`spin_intervals_eigen`). At tilt 0 the
10x10 matrix is the level route's 8x8 transverse block beside the vertical (z, p_z) pair, so the
interval is today's.

A tilt couples what the axial symmetry keeps apart: where, on the level base, a transverse mode's
frequency crosses the vertical bounce's (sqrt(mu Phi_3 / m), thesis 3.3.3), the two may collide
once the base is tilted, and a narrow band of instability opens inside the interval, of width
about proportional to the tilt (thesis_stable: near 2727 rad/s, 1 rad/s wide at 1e-5 rad, 12 at
1e-4); the same where two transverse modes of opposite sense meet (coupled at second order). A
scan on a grid would step over it; so the crossings are found on the level system and probed
(runtime/physics/routes/mode_crossings.py), and the interval reported is the lowest of those found.
No sympy here.
"""
from __future__ import annotations

import math
import time

import numpy as np

from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.physics.routes.eigen_route import EPS, growth_rate, spin_intervals_eigen
from levitron.runtime.physics.routes.mode_crossings import level_crossings, tilted_probes
from levitron.runtime.physics.routes.ray_algebra import RayCoefficients, spin_intervals_discriminant
from levitron.runtime.physics.routes.result import StabilityResult, approximations_at_z_c, relative_gap
from levitron.runtime.ui.human import Units
from levitron.runtime.physics.apparatus.tilted_equilibrium import FIXED, MIN_FRACTION, NoEquilibrium, TiltedTop

LEVEL_ONLY = ("the discriminant route (thesis 3.3.9-3.3.16) applies to a level, aligned apparatus "
              "only: its ray polynomial rests on the axial symmetry (which the base's tilt breaks) "
              "and on the magnet at the centre of mass; the interval is the eigenvalue route's")


def reduced_jacobian(J: np.ndarray, states) -> np.ndarray:
    """The Jacobian without zeta and p_zeta, after checking that zeta's column and p_zeta's row
    vanish (zeta is cyclic) to rounding."""
    states = list(states)
    cut = [states.index(s) for s in FIXED]
    keep = [i for i in range(len(states)) if i not in cut]
    bound = len(states) * EPS * np.linalg.norm(J)
    if np.abs(J[:, cut[0]]).max() > bound or np.abs(J[cut[1], :]).max() > bound:
        raise ValueError("zeta is not cyclic in this model: the top's own rotation does not reduce")
    return J[np.ix_(keep, keep)]


CROSSING_REACH = 1e-2   # a gap is sought this far (relative) from its level crossing


def tilted_analysis(model, p: np.ndarray, top: TiltedTop | None = None) -> StabilityResult:
    """The StabilityResult at the relative equilibrium over the base tilted by p's base_tilt:
    z_s the equilibrium's height, `equilibrium` its position and axis, the interval route
    "eigenvalues" (module docstring); at tilt 0 route "discriminant" too, and routes_agree.
    top: a TiltedTop of the same model and parameters (but the tilt) to reuse its branch points."""
    timings = {}
    P = model.pvals(p)
    m, g, A, C, mu = P["m"], P["g"], P["A"], P["C"], P["mu"]
    onaxis = eqm.model_onaxis(model, p)
    t0 = time.perf_counter()
    with eqm.naming_the_formula(model):
        rep = eqm.survey(onaxis, eqm.scale_of(model, p)).report(m, g, mu)
    timings["equilibria"] = time.perf_counter() - t0
    approximations = approximations_at_z_c(onaxis, rep.z_c, rep.max_mass, g, A, C)
    tilt = P["base_tilt"]
    aligned = tilt == 0 and P.get("moment_offset", 0.0) == 0   # the discriminant route applies
    if not rep.stable:
        return StabilityResult(None, None, [], None, approximations,
                               "on the level base: " + rep.no_hover_reason(m), None, timings,
                               mass=m)
    z_level = rep.stable[0].z
    ph = np.asarray(onaxis(z_level), float)
    level = spin_intervals_discriminant(RayCoefficients.from_physics(ph[1], ph[2], ph[3], m, A, C, mu))
    sigma_scale = math.sqrt(abs(mu * ph[1]) / A) * A / C if ph[1] != 0 else 1.0
    probes = [math.sqrt(a * b) for a, b in level if 0 < a and b < math.inf]
    t0 = time.perf_counter()
    top = TiltedTop(model, p, z_level) if top is None else top
    try:
        eq = top.hamilton(tilt, probes[0] if probes else sigma_scale)
    except NoEquilibrium as exc:
        return StabilityResult(None, None, [], None, approximations, str(exc), None, timings,
                               mass=m, notes=[] if aligned else [LEVEL_ONLY])
    timings["tilted_equilibrium"] = time.perf_counter() - t0
    jfast = model.fast("full_jac", top.params_at(tilt))
    n = len(eq.states)

    def jac(sigma):
        return reduced_jacobian(jfast(eq.at_spin(sigma)).reshape(n, n), eq.states)
    t0 = time.perf_counter()
    bounce: list[float] = []
    transverse: list[float] = []
    if tilt != 0 and probes and level[0][1] < math.inf:    # level: the crossings stay harmless
        top0 = top.hamilton(0.0, probes[0])
        j0 = model.fast("full_jac", top.params_at(0.0))

        def jac0(sigma):
            return reduced_jacobian(j0(top0.at_spin(sigma)).reshape(n, n), eq.states)
        states = [s for s in eq.states if s not in FIXED]
        vert = [states.index("z"), states.index("p_z")]
        bounce, transverse = level_crossings(jac0, vert, [i for i in range(len(states)) if i not in vert],
                                             level[0][0] / 2, 2 * level[0][1])
        # each crossing, and beside each gap it may open the stretches up to the level ends
        looked = tilted_probes(jac, bounce + transverse, CROSSING_REACH)
        ends = sorted(looked + [level[0][0] * (1 + 1e-6), level[0][1] * (1 - 1e-6)])
        probes = probes + ends + [math.sqrt(a * b) for a, b in zip(ends, ends[1:])]
    eig = spin_intervals_eigen(jac, sigma_scale, probes)
    timings["eigenvalues"] = time.perf_counter() - t0
    bounded = [iv for iv in eig if iv[1] < math.inf and iv[0] > 0]
    reason = None
    if not bounded:
        where = "on the level base" if tilt == 0 else f"on the base tilted by {tilt:.6g} rad"
        reason = (f"{where} no spin rate makes the top linearly stable "
                  "at its equilibrium (eigenvalues of the generated Jacobian)")
    elif len(bounded) > 1:
        (_, a), (b, _) = bounded[0], bounded[1]
        rate = growth_rate(jac(math.sqrt(a * b)))
        def close_to(cross):
            return any(a * (1 - CROSSING_REACH) < c < b * (1 + CROSSING_REACH) for c in cross)
        why = (", where the tilt couples a transverse mode to the bounce" if close_to(bounce) else
               ", where the tilt couples two transverse modes" if close_to(transverse) else "")
        u = Units.of(g)
        reason = (f"{len(bounded)} disjoint spin intervals; spin_interval is the lowest: between it "
                  f"and the next ({a:.6g}-{b:.6g} {u.named('rad/s')}{why}) a tilt grows by e every "
                  f"{1 / rate:.3g} {u.named('s')}")
    disc = level if aligned else []
    agree = relative_gap(disc, eig) <= 1e-6 if aligned else None
    res = StabilityResult(float(eq.position[2]), bounded[0] if bounded else None, disc, eig,
                          approximations, reason, agree, timings, mass=m,
                          notes=[] if aligned else [LEVEL_ONLY])
    res.equilibrium = eq.as_dict(top.z_level)
    return res


TILT_RTOL = 1e-6        # the bisection of the largest tilt stops at this relative width


def _bisect(ok, lo: float, hi: float) -> float:
    """The largest t in [lo, hi] with ok(t), ok(lo) true and ok(hi) false, to TILT_RTOL of hi."""
    while hi - lo > TILT_RTOL * hi:
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if ok(mid) else (lo, mid)
    return lo


FOLD_NEAR = 1e-3        # max_base_tilt this close (relative) to the fold: limited by the fold


def level_tolerance(model, p: np.ndarray) -> dict:
    """How level the base must be: `max_base_tilt` (rad), the largest tilt at which a
    stable spin interval still exists, to TILT_RTOL; `fold_tilt` (rad), where the equilibrium
    itself is gone (the branch from the level one turns back; None if it reaches pi/2);
    `limited_by`: "fold" when max_base_tilt is within FOLD_NEAR of it, else "instability" (the
    equilibrium exists, but no spin stabilises it). The fold: continuing the equilibrium towards
    pi/2 stops there (runtime/physics/apparatus/tilted_equilibrium.py), then bisection of its existence; if
    the top is stable at the fold, that is the answer, else bisection of `tilted_analysis`'s
    verdict below it. All None where the level top has no interval."""
    P = model.pvals(p)
    none = {"max_base_tilt": None, "fold_tilt": None, "limited_by": None,
            "tilt_azimuth": P["base_tilt_azimuth"]}
    res0 = tilted_analysis(model, model.with_params({"base_tilt": 0.0}, p))
    if res0.spin_interval is None:
        return none
    top = TiltedTop(model, p, res0.equilibrium["z_level"] + P.get("moment_offset", 0.0))
    sigma = math.sqrt(res0.spin_interval[0] * res0.spin_interval[1])

    def exists(t):
        try:
            top.hamilton(t, sigma)
        except NoEquilibrium:
            return False
        return True

    def stable(t):
        return tilted_analysis(model, model.with_params({"base_tilt": t}, p), top).spin_interval is not None
    far = 0.999 * math.pi / 2
    try:
        top.hamilton(far, sigma)
        fold = None
    except NoEquilibrium as exc:
        hi = min(far, 1.01 * exc.reached + MIN_FRACTION * far)
        fold = _bisect(exists, exc.reached, hi) if not exists(hi) else hi
    end = far if fold is None else fold
    best = end if stable(end) else _bisect(stable, 0.0, end)
    near = fold is not None and fold - best <= FOLD_NEAR * fold
    return {**none, "max_base_tilt": float(best), "fold_tilt": None if fold is None else float(fold),
            "limited_by": "fold" if near else ("instability" if best < end else None)}
