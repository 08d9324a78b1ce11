"""Design optimisation: the widest range of spins that hold the top, by CasADi and IPOPT (thesis 3.3).

    maximise   spin-range  sigma_hi - sigma_lo (rad/s)   or   spin-ratio  sigma_hi / sigma_lo
    over       scene keys x in a box (runtime/design/scene_keys.py: p = p(x), exact)
    subject to m g + mu Phi_2(z_s) = 0                          (thesis 3.3.2)
               Q(1/sigma_lo^2; z_s) = Q(1/sigma_hi^2; z_s) = 0  (the ray cubic, thesis 3.3.13-3.3.16)
               the cubic's third root outside [1/sigma_hi^2, 1/sigma_lo^2] by a margin (the slopes
               of Q at the two ends have opposite signs),
               sigma_hi >= sigma_lo, and N(t) (thesis 3.3.11) with four real roots at the
               middle s = 1/(sigma_lo sigma_hi): G > 0, P < 0, D < 0 (the quartic's invariants)
               the user's constraints (runtime/design/constraints.py), e.g. stiffness >= 1 N/m

The NLP is over the keys only: z_s, sigma_lo and sigma_hi are the rootfinder Function `spin` of
runtime/physics/stability/differentiable.py, so IPOPT works on exact derivatives (implicit function theorem).
IPOPT's iterates may step across a critical spin, so the NLP does not rely on tracking: at its
answer the interval's ends are critical spins with no third one between them, and N(t) has four real
roots in the middle, so the whole interval is one of linear stability and no larger one contains it.
The margin keeps both edges simple critical spins: where the third root merges with an edge the
float route's verdict degenerates (the supremum of the objective can sit there, unattainable), so
the grid and the verification apply the same margin (`third_root_margin`, from the exact ray cubic).
No stiffness constraint is required: as z_s approaches z_c (mu Phi_3 -> 0) one root of the ray
cubic grows without bound, but on the scenes the stable interval stays bounded (thesis
3.3.22-3.3.23); an optimum at vanishing stiffness is reported with a warning, and refused only
where the interval at z_c is unbounded (runtime/design/edge.py). An optimum on a --vary bound is
reported with a warning too ("at the bound: widen --vary"): the box, not the physics, stopped it.

Every answer is verified before it is reported: (1) a brute-force grid of the box (>= 20 points a
key) by the exact float routes (re-resolved scene, runtime/physics/equilibrium/finder.py,
runtime/physics/routes/ray_algebra.py);
IPOPT starts from its best point and searches the grid cells around it (the objective has cliffs
where a critical spin enters the interval: a local search from the best cell is what a grid can
certify); (2) the float routes at the optimum (the re-validated scene)
must reproduce z_s, sigma_lo and sigma_hi to VERIFY_RTOL and satisfy the constraints; (3) the
grid's best must not beat the optimum by more than VERIFY_RTOL relative. A failure of IPOPT or of
a check is a UserError naming IPOPT's status or the check.
"""
from __future__ import annotations

import contextlib
import io
import math
import os
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass

import casadi as ca
import numpy as np

from levitron.runtime.design import edge as design_edge, sharpness
from levitron.runtime.design.design_notes import barely_moves_note, mass_window_note
from levitron.runtime.physics.stability import differentiable as diffable
from levitron.runtime.design.constraints import Constraint
from levitron.runtime.design.design_answer import OBJECTIVES, Design, DesignResult  # noqa: F401 (DesignResult: its old name)
from levitron.runtime.errors import UserError
from levitron.runtime.physics.routes.ray_algebra import RayCoefficients, ray_cubic
from levitron.runtime.design.scene_keys import bounds_hit, grid_points, KeyMap, Vary, key_value
from levitron.runtime.ui.validate import count

BAND_CONSTRAINTS = ("z_s", "stiffness")   # the constraints mass-window takes (the scene's top)
VERIFY_RTOL = 1e-8
THIRD_ROOT_MARGIN = 1e-3   # differentiable.simple_neighbours >= this: the ends are neighbouring simple roots
MARGIN_SLACK = 1e-8        # the float check's allowance on that normalised margin (IPOPT's tolerance)
FOUR_REAL_MARGIN = 1e-9    # G > 0, P < 0, D < 0 at the interval's middle, normalised
GRID_MIN = 20
MAX_GRID_POINTS = 20_000      # points of the whole verification grid (n^k): ~100 s of float routes
IPOPT = {"print_time": False, "ipopt.print_level": 0, "ipopt.sb": "yes", "ipopt.tol": 1e-12,
         "ipopt.constr_viol_tol": 1e-10, "ipopt.acceptable_constr_viol_tol": 1e-10,
         "ipopt.max_iter": 300, "show_eval_warnings": False}


def objective_of(name: str, lo: float, hi: float) -> float:
    """spin-range, spin-ratio of the spin interval (lo, hi); mass-window of the masses (lo, hi)."""
    return hi - lo if name == "spin-range" else hi / lo if name == "spin-ratio" else (hi - lo) / hi


def check_objective(name: str, constraints: Sequence[Constraint]) -> None:
    if name not in OBJECTIVES:
        raise UserError(f"«maximize» {name!r}: use one of {', '.join(OBJECTIVES)}")
    if name == "mass-window":
        bad = [str(c) for c in constraints if c.name not in BAND_CONSTRAINTS]
        if bad:
            raise UserError(f"«maximize» mass-window takes constraints on {' and '.join(BAND_CONSTRAINTS)}"
                            f" (the scene's top) only, not {', '.join(bad)}")


@dataclass(frozen=True)
class Point:
    """The float routes at one x: z_s (m), stiffness (N/m), the chosen spin interval (rad/s) and
    the objective; interval None where no bounded interval satisfies the constraints."""

    x: tuple[float, ...]
    z_s: float | None
    stiffness: float | None
    interval: tuple[float, float] | None
    value: float | None
    band: tuple[tuple[float, float], tuple[float, float]] | None = None   # mass-window: (z, mass)


def evaluate(model, keymap: KeyMap, x, objective: str, constraints: Sequence[Constraint],
             near: tuple[float, float] | None = None) -> Point:
    """The exact float routes at x: the best feasible interval, or the one containing the
    midpoint of `near` when given (verification of an NLP answer)."""
    if objective == "mass-window":
        return evaluate_band(model, keymap, x, constraints, near)
    _, p = keymap.exact(x)
    st = diffable.starts(model, p)
    x = tuple(float(v) for v in x)
    if st.z_s is None:
        return Point(x, None, None, None, None)
    vals = {"z_s": st.z_s, "stiffness": st.stiffness}
    best = None
    for lo, hi in st.intervals:
        if near is not None and not lo <= math.sqrt(near[0] * near[1]) <= hi:
            continue
        if third_root_margin(model, p, st.z_s, lo, hi) < THIRD_ROOT_MARGIN - MARGIN_SLACK:
            continue
        vals.update(sigma_lo=lo, sigma_hi=hi)
        if all(c.margin(vals[c.name]) >= -VERIFY_RTOL * max(abs(c.bound), abs(vals[c.name]))
               for c in constraints):
            v = objective_of(objective, lo, hi)
            if best is None or v > best[0]:
                best = (v, (lo, hi))
    return Point(x, st.z_s, st.stiffness, None if best is None else best[1],
                 None if best is None else best[0])


def evaluate_band(model, keymap: KeyMap, x, constraints: Sequence[Constraint],
                  near: tuple[float, float] | None = None) -> Point:
    """mass-window by the exact float route (runtime/physics/equilibrium/bands.py): the widest stable band, or the one
    containing the middle of the heights `near`; the constraints on the scene's top (z_s,
    stiffness, thesis 3.3.2-3.3.3)."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    _, p = keymap.exact(x)
    x = tuple(float(v) for v in x)
    rep = eqm.equilibria_of(model, p, bands=True)
    z_s, k = (rep.stable[0].z, rep.stable[0].stiffness) if rep.stable else (None, None)
    bands = rep.stable_bands if near is None else [
        b for b in rep.stable_bands if b.z[0] <= 0.5 * (near[0] + near[1]) <= b.z[1]]
    band = max(bands, key=lambda b: b.z[1] - b.z[0]) if bands else None
    vals = {"z_s": z_s, "stiffness": k}
    ok = band is not None and all(
        vals[c.name] is not None
        and c.margin(vals[c.name]) >= -VERIFY_RTOL * max(abs(c.bound), abs(vals[c.name]))
        for c in constraints)
    if not ok:
        return Point(x, z_s, k, None, None)
    return Point(x, z_s, k, None, objective_of("mass-window", *band.mass), (band.z, band.mass))


def third_root_margin(model, p, z_s: float, lo: float, hi: float) -> float:
    """differentiable.simple_neighbours of the exact ray cubic (runtime/physics/routes/ray_algebra.py, thesis
    3.3.13) at z_s with s1 = 1/hi^2, s2 = 1/lo^2: the float twin of the NLP's constraint."""
    P = model.pvals(p)
    ph = model.onaxis(z_s, p)
    c = RayCoefficients.from_physics(ph[1], ph[2], ph[3], P["m"], P["A"], P["C"], P["mu"])
    a = [float(v) for v in ray_cubic(c)]
    return diffable.simple_neighbours(a, 1 / hi ** 2, 1 / lo ** 2)


@contextlib.contextmanager
def _quiet_stderr():
    """Silence file descriptor 2 for the solve: CasADi prints every failed Newton evaluation (an
    evaluation error IPOPT recovers from) there, and stderr carries one line per error
    (docs/contract.md); IPOPT's outcome is reported through its status instead. CasADi's Python
    module writes through sys.stderr, which a notebook or a test replaces: that is silenced too."""
    sys.stderr.flush()
    saved = os.dup(2)
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, 2)
        with contextlib.redirect_stderr(io.StringIO()):
            yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)
        os.close(devnull)


class _Nlp:
    """The NLP (module docstring) over the keys u in [0, 1] of their box: z_s, sigma_lo and
    sigma_hi are the rootfinder Function `spin` of runtime/physics/stability/differentiable.py at p(x), started
    from the grid point's float values (a Newton failure is an evaluation error, after which IPOPT
    shortens its step); their exact derivatives come through the implicit function theorem."""

    def __init__(self, model, keymap: KeyMap, objective: str, constraints: Sequence[Constraint],
                 start: Point):
        sy = diffable.symbols(model)
        n = len(keymap.varies)
        lo = np.array([v.lo for v in keymap.varies])
        span = np.array([v.hi - v.lo for v in keymap.varies])
        u = ca.SX.sym("u", n)
        p = keymap.p_casadi(lo + span * u)
        z, slo, shi = diffable.spin_function(sy, strict=True)(start.z_s, *start.interval, p)
        w = ca.SX.sym("w", 3)
        g_of = ca.Function("g", [w, sy.p], [ca.vertcat(
            sy.simple_neighbours(1 / w[2] ** 2, 1 / w[1] ** 2, w[0]), (w[2] - w[1]) / w[2],
            *sy.four_real(1 / (w[1] * w[2]), w[0]), sy.stiffness(w[0]))])
        g = g_of(ca.vertcat(z, slo, shi), p)
        quantity = {"z_s": z, "stiffness": g[5], "sigma_lo": slo, "sigma_hi": shi}
        rows = [g[0], g[1], g[2], g[3], g[4]]
        lbg = [THIRD_ROOT_MARGIN, 0, FOUR_REAL_MARGIN, -ca.inf, -ca.inf]
        ubg = [ca.inf, ca.inf, ca.inf, -FOUR_REAL_MARGIN, -FOUR_REAL_MARGIN]
        for c in constraints:
            rows.append(c.margin(quantity[c.name]) / max(abs(c.bound), 1e-300))
            lbg.append(0)
            ubg.append(ca.inf)
        f = -objective_of(objective, slo, shi) / objective_of(objective, *start.interval)
        self.solver = ca.nlpsol("design", "ipopt", {"x": u, "f": f, "g": ca.vertcat(*rows)}, IPOPT)
        # the answer, checked against the float routes afterwards, by the lenient Newton: a root whose
        # residual stalls just above the strict tolerance (rounding in a scene's formula) is reported
        # and verified rather than raised as an evaluation error
        self.answer = ca.Function("answer", [u], [*diffable.spin_function(sy)(start.z_s, *start.interval, p)])
        self.lbg, self.ubg, self.lo, self.span, self.n = lbg, ubg, lo, span, n
        self.sy, self.keymap = sy, keymap

    def failure_hint(self, start: Point) -> str:
        """How to fix a failed solve: where Newton's strict tolerance lies below the rounding floor of
        the scene's functions at the start (the float routes' roots), no bound or constraint helps."""
        floor = diffable.residual_at(self.sy, "spin", (start.z_s, *start.interval), self.keymap.exact(start.x)[1])
        tol = diffable.NEWTON_STRICT["abstol"]
        if floor > tol:
            return (f"the hover height and critical spins cannot be solved to Newton's tolerance "
                    f"{tol:g} there: the scene's functions carry rounding errors of {floor:.1g} "
                    "(relative), e.g. a formula that subtracts nearly equal terms; rewrite it without "
                    "the cancellation")
        return "change the bounds or constraints"

    def solve(self, start: Point, cell: float):
        """IPOPT from the start within the grid cells around it (cell: one grid step in u)."""
        u0 = (np.array(start.x) - self.lo) / self.span
        with _quiet_stderr():
            sol = self.solver(x0=u0, lbx=np.maximum(u0 - cell, 0), ubx=np.minimum(u0 + cell, 1),
                              lbg=self.lbg, ubg=self.ubg)
        st = self.solver.stats()
        u = np.clip(np.asarray(sol["x"], float).reshape(-1), 0, 1)
        return st, self.lo + self.span * u, tuple(float(v) for v in self.answer(u))


class _BandNlp(_Nlp):
    """mass-window: maximise (m_hi - m_lo) / m_hi with the band's edges the rootfinder Function
    `band` of runtime/physics/stability/differentiable.py (z_c: Phi_3 = 0; z_hi: N(t) with a triple root, thesis
    3.3.3, 3.3.11), started from the float band at the grid point; z_s and the stiffness of the
    scene's top (Function `z_s`) for the user's constraints; z_hi >= z_lo."""

    def __init__(self, model, keymap: KeyMap, constraints: Sequence[Constraint], start: Point):
        sy = diffable.symbols(model)
        n = len(keymap.varies)
        lo = np.array([v.lo for v in keymap.varies])
        span = np.array([v.hi - v.lo for v in keymap.varies])
        _, p0 = keymap.exact(start.x)
        st = diffable.starts(model, p0, band=True)
        if st.band is None or st.z_c is None:
            raise UserError(f"no start for the band's edges at {keymap.describe(start.x)}: the float "
                            "band has no upper edge where two critical spins merge")
        u = ca.SX.sym("u", n)
        p = keymap.p_casadi(lo + span * u)
        z_lo, z_hi, m_hi, m_lo, window = diffable.band_function(sy, strict=True)(st.z_c, *st.band, p)
        rows, lbg, ubg = [(z_hi - z_lo) / z_hi], [0], [ca.inf]
        if constraints:
            z, k = diffable.z_s_function(sy)(start.z_s, p)
            quantity = {"z_s": z, "stiffness": k}
            for c in constraints:
                rows.append(c.margin(quantity[c.name]) / max(abs(c.bound), 1e-300))
                lbg.append(0)
                ubg.append(ca.inf)
        f = -window / start.value
        self.solver = ca.nlpsol("design", "ipopt", {"x": u, "f": f, "g": ca.vertcat(*rows)}, IPOPT)
        z_lo, z_hi, m_hi, m_lo, _ = diffable.band_function(sy)(st.z_c, *st.band, p)    # lenient: as _Nlp's
        self.answer = ca.Function("answer", [u], [z_lo, z_hi, m_lo, m_hi])
        self.lbg, self.ubg, self.lo, self.span, self.n = lbg, ubg, lo, span, n

    def failure_hint(self, start: Point) -> str:
        return "change the bounds or constraints"


def optimize(model, varies: Sequence[Vary], objective: str, constraints: Sequence[Constraint] = (),
             n_grid: int = GRID_MIN, tolerance: dict | None = None) -> DesignResult:
    """Maximise `objective` over the varied scene keys (module docstring); verified; then its
    sharpness at +- `tolerance` {key: value} of each key (runtime/design/sharpness.py)."""
    t0 = time.perf_counter()
    check_objective(objective, constraints)
    if objective == "mass-window" and any(v.key == "top.mass" for v in varies):
        raise UserError("«maximize» mass-window «vary» top.mass: the masses that hover are the plate's, the "
                        "top's moment, A and C (the band's rule, thesis 3.3.2), not the top's mass; vary a plate "
                        "key such as plate.hole, or use `«levitron=trim»` to choose the mass")
    if not 1 <= len(varies) <= 3:
        raise UserError("«vary»: give one to three keys (the verification grid has n^k points)")
    n_grid = count(n_grid, "«grid»", low=GRID_MIN)
    if n_grid ** len(varies) > MAX_GRID_POINTS:
        most = int(MAX_GRID_POINTS ** (1 / len(varies)) + 1e-9)
        keys = f"{len(varies)} key{'s' if len(varies) > 1 else ''}"
        raise UserError(f"«grid={n_grid}» with {keys} is {n_grid ** len(varies)} points, more than "
                        f"the {MAX_GRID_POINTS} of a verification grid (about 5 ms each): give «grid={most}» "
                        "or fewer")
    keymap = KeyMap(model.scene, model.param_names, varies)
    sharpness.tolerances(model.scene, {v.key: v.lo for v in varies}, tolerance)     # checked before the solve
    pts = [evaluate(model, keymap, x, objective, constraints) for x in grid_points(varies, n_grid)]
    feasible = [pt for pt in pts if pt.value is not None]
    if not feasible:
        what = "a stable band" if objective == "mass-window" else "a stable spin interval"
        fix = (f"widen the bounds or relax {', '.join(map(str, constraints))}" if constraints
               else "move or widen the «vary» bounds (`«levitron=equilibrium»` gives the band of masses)")
        raise UserError(f"no point of the {len(pts)}-point grid over the box has {what}"
                        f"{' that meets the constraints' if constraints else ''}: {fix}")
    start = max(feasible, key=lambda pt: pt.value)
    band = objective == "mass-window"
    nlp = _BandNlp(model, keymap, constraints, start) if band else \
        _Nlp(model, keymap, objective, constraints, start)
    stats, x, ans = nlp.solve(start, 1 / (n_grid - 1))
    status = str(stats.get("return_status"))
    fallback = None
    if not stats.get("success"):
        failed = (f"IPOPT failed (status {status}, {stats.get('iter_count')} iterations) from "
                  f"{keymap.describe(start.x)}")
        if band or len(varies) != 1 or status != "Maximum_Iterations_Exceeded":   # a corner: IPOPT circles it
            raise UserError(f"{failed}: {nlp.failure_hint(start)}")
        x, fallback = _bounded_search(model, keymap, varies[0], start, objective, constraints, n_grid), failed
        status = "bounded search of the float route (IPOPT failed)"
    keys = [v.key for v in varies]
    if fallback is not None:
        check = evaluate(model, keymap, x, objective, constraints)
        ans = (check.z_s, *check.interval) if check.interval is not None else None
    else:
        check = evaluate(model, keymap, x, objective, constraints, near=ans[:2] if band else ans[1:])
    if check.value is None:
        raise UserError(f"verification failed: at the IPOPT optimum {keymap.describe(x)} the float "
                        f"routes find no {'stable band' if band else 'stable spin interval'} "
                        "meeting the constraints there")
    what = "z_lo, z_hi, m_lo, m_hi" if band else "z_s, sigma_lo, sigma_hi"
    ref = (*check.band[0], *check.band[1]) if band else (check.z_s, *check.interval)
    gap = max(abs(a - b) / abs(b) for a, b in zip(ans, ref))
    if gap > VERIFY_RTOL:
        raise UserError(f"verification failed: at {keymap.describe(x)} the NLP's {what} differ "
                        f"from the float routes by {gap:.2g} (relative)")
    if start.value > check.value * (1 + VERIFY_RTOL):
        raise UserError(f"verification failed: the grid point {keymap.describe(start.x)} gives "
                        f"{start.value:.10g}, more than the IPOPT optimum {check.value:.10g}")
    interval = check.interval
    if band:    # the scene's top at the optimum: its spin interval, for the record (None if none)
        interval = diffable.starts(model, keymap.exact(x)[1]).spin
    at_bound = bounds_hit(varies, x)
    warnings = [] if fallback is None else [
        f"{fallback}: the objective has a corner there (the spin limits switch branch), so the optimum is "
        "a bounded scalar search (Brent) of the exact float route over the best grid cell; the NLP does not "
        "verify it"]
    warnings += [f"{k} = {x[i]:.6g} is at the {at_bound[k]} bound of «vary» {k}={varies[i].lo:.10g}:"
                f"{varies[i].hi:.10g}: the box stopped the optimum, not the physics; at the bound: widen «vary»"
                for i, k in enumerate(keys) if k in at_bound]
    if not band and check.stiffness is not None:
        p_opt = keymap.exact(x)[1]
        P = model.pvals(p_opt)
        from levitron.runtime.physics.equilibrium import finder as eqm
        edge = design_edge.warning(check.stiffness, P["m"], P["g"], check.z_s,
                                   eqm.equilibria_of(model, p_opt).max_mass)
        if edge is not None:
            design_edge.check_bounded(model, p_opt, check.interval, keymap.describe(x))
            warnings.append(edge)
    scene_x = [key_value(model.scene.data, k) for k in keys]
    inside = all(v.lo <= s <= v.hi for v, s in zip(varies, scene_x))
    scene_pt = evaluate(model, keymap, scene_x, objective, constraints) if inside else None
    warnings += [n for n in (mass_window_note(check.band and check.band[1], model.param("m")),
                             barely_moves_note(objective, check.value, scene_pt and scene_pt.value)) if n]
    sharp = sharpness.sharpness(lambda y: evaluate(model, keymap, y, objective, constraints).value, model,
                                varies, dict(zip(keys, map(float, x))), check.value, tolerance, launch=False)
    return Design(
        objective=objective, value=check.value, optimum=dict(zip(keys, map(float, x))),
        start=dict(zip(keys, start.x)), start_value=start.value,
        scene_value=None if scene_pt is None else scene_pt.value,
        solver_status=status, iterations=int(stats.get("iter_count", -1)) if fallback is None else 0,
        z_s=check.z_s,
        stiffness=check.stiffness, spin_interval=interval,
        band=None if check.band is None else {"z": list(check.band[0]), "mass": list(check.band[1])},
        constraints=[str(c) for c in constraints],
        verification={"float_route": check.value,
                      "nlp": None if fallback else objective_of(objective, *(ans[2:] if band else ans[1:])),
                      "max_relative_gap": None if fallback else gap, "grid_best": start.value, "grid_points": len(pts),
                      "grid_feasible": len(feasible), "grid_per_key": n_grid,
                      "tolerance": VERIFY_RTOL},
        scene=keymap.resolve(x), wall_s=time.perf_counter() - t0, at_bound=at_bound,
        warnings=warnings, sharpness=sharp)


def _bounded_search(model, keymap, vary: Vary, start: Point, objective: str, constraints, n_grid: int) -> tuple:
    """One key where IPOPT fails (a corner of the objective: the maximum of the spin window sits where
    sigma_lo(m) switches branch, thesis 3.3.15-3.3.19): Brent's bounded search of the float route's
    objective over the grid cell either side of the best grid point (no value: -inf)."""
    from scipy.optimize import minimize_scalar
    cell = (vary.hi - vary.lo) / (n_grid - 1)
    lo, hi = max(vary.lo, start.x[0] - cell), min(vary.hi, start.x[0] + cell)

    def minus(v: float) -> float:
        pt = evaluate(model, keymap, (float(v),), objective, constraints)
        return math.inf if pt.value is None else -pt.value
    res = minimize_scalar(minus, bounds=(lo, hi), method="bounded",
                          options={"xatol": VERIFY_RTOL * (vary.hi - vary.lo)})
    best = float(res.x) if -res.fun >= start.value else float(start.x[0])
    return (best,)
