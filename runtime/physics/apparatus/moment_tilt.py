"""The spin window of a top whose moment is off its axis (route "Floquet"), and how crooked it may be.

`floquet_analysis`: the aligned top first (moment tilt 0: the relative equilibrium and its eigen
route, runtime/physics/apparatus/tilted_stability.py), then the steady motion at the scene's moment tilt and
its Floquet multipliers on a log grid around the aligned window, the aligned system's meetings of
multipliers, and bisection of every change of verdict. Two routes give the multipliers:
- over a level base and a plate symmetric about its axis the periodic orbit is a rigid rotation
  about the vertical, a relative equilibrium: its eigenvalues lambda in the turning frame give the
  multipliers exp(T lambda) (runtime/physics/apparatus/rotating_equilibrium.py; about 1 ms a spin);
- elsewhere (a tilted base, a four- or two-fold plate) the orbit by shooting and its monodromy
  matrix (runtime/physics/apparatus/multipliers.py; 0.3-3 s a spin).
`moment_tolerance`: max_moment_tilt, the largest moment tilt at which a stable spin interval
exists, by bisection in the tilt of that existence, each window found from the last one's spins.
No sympy here.
"""
from __future__ import annotations

import math
import time

import numpy as np

from levitron.runtime.physics.apparatus import multipliers as fl
from levitron.runtime.physics.apparatus import rotating_equilibrium as req
from levitron.runtime.physics.apparatus.periodic_orbit import NoOrbit
from levitron.runtime.physics.routes.result import StabilityResult
from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium
from levitron.runtime.ui.human import Units
from levitron.runtime.physics.apparatus.tilted_stability import LEVEL_ONLY, reduced_jacobian, tilted_analysis

ROUTE = ("Floquet: periodic orbit by shooting on the generated full_rhs (CVODES, CasADi "
         "sensitivities), multipliers of its monodromy matrix less the two trivial ones "
         f"(flow, energy), stable where all lie on the unit circle to {fl.MULT_TOL:g}")
TILT_RTOL = 1e-2         # max_moment_tilt is bisected to this relative width (shooting)
WINDOW_RTOL = 1e-3       # and the windows along it to this (their existence is what counts)
RE_TILT_RTOL = 1e-3      # the same by the relative equilibrium's eigenvalues
FOLD_RTOL = 1e-4         # the end of a branch placed to this of b there: enough to tell whether a window exists
LOCAL = 16               # spins probed over each window kept when none of its kept spins is stable


def probes_for(ft: fl.FloquetTop, aligned: tuple[float, float], extra=()) -> list[float]:
    """The spins probed: GRID log-spaced over [SPAN[0] lo, SPAN[1] hi] of the aligned window, the
    aligned system's multiplier meetings inside it (for a moment tilt != 0), and `extra`."""
    lo0, hi0 = aligned
    out = list(np.geomspace(fl.SPAN[0] * lo0, fl.SPAN[1] * hi0, fl.GRID)) + list(extra)
    if ft.b != 0:
        out += meeting_probes(ft, aligned)
    return sorted(out)


def meeting_probes(ft, aligned: tuple[float, float]) -> list[float]:
    """The aligned system's multiplier meetings inside the aligned window, at most MAX_MEETINGS,
    the nearest to its ends first (they do not depend on the moment tilt)."""
    lo0, hi0 = aligned
    eq0 = ft.top.hamilton(ft.tilt, lo0)
    n = len(eq0.states)
    jf = ft.model.fast("full_jac", ft.aligned)
    found = fl.meetings(lambda s: reduced_jacobian(jf(eq0.at_spin(s)).reshape(n, n), eq0.states), lo0, hi0)
    near = sorted(found, key=lambda s: min(abs(math.log(s / lo0)), abs(math.log(s / hi0))))
    return near[:fl.MAX_MEETINGS]


def steady_top(model, p: np.ndarray, z_magnet: float):
    """(the top's steady motions at p, the route's text, its spin_rtol): the relative equilibrium
    in the turning frame where the symmetry allows it (rotating_equilibrium.refusal), else the
    periodic orbit by shooting, the route's text saying why."""
    why = req.refusal(model, p)
    if why is None:
        return req.RotatingTop(model, p, z_magnet), req.ROUTE, req.SPIN_RTOL
    return (fl.FloquetTop(model, p, z_magnet),
            f"{ROUTE} (the relative-equilibrium route does not apply: {why})", fl.SPIN_RTOL)


def floquet_analysis(model, p: np.ndarray) -> StabilityResult:
    """The StabilityResult of the scene's top with its moment tilted (p's moment_tilt, any base
    tilt): spin_interval the lowest bounded Floquet window, by the relative equilibrium where
    `steady_top` allows it, else by shooting; `floquet` the route's text (which of the two ran),
    windows, tolerance and the multipliers' deviation at the window's middle; the aligned top's
    interval (eigen route) beside it; `equilibrium` the orbit's start at that middle."""
    t0 = time.perf_counter()
    P = model.pvals(p)
    res0 = tilted_analysis(model, model.with_params({"moment_tilt": 0.0}, p))
    if res0.spin_interval is None:
        res0.reason = f"the aligned top (moment tilt 0): {res0.reason}"
        return res0
    ft, route, rtol = steady_top(model, p, res0.equilibrium["z_level"] + P.get("moment_offset", 0.0))
    windows = fl.spin_windows(ft.stable, probes_for(ft, res0.spin_interval), rtol)
    timings = {**res0.timings, "floquet": time.perf_counter() - t0}
    bounded = [w for w in windows if w[0] > 0]
    rotating = isinstance(ft, req.RotatingTop)
    floq = {"route": route, "windows": [list(w) for w in windows], "moment_tilt": P["moment_tilt"],
            "multiplier_tolerance": None if rotating else fl.MULT_TOL, "spin_rtol": rtol,
            "aligned_interval": list(res0.spin_interval), "probed": "a log grid of "
            f"{fl.GRID} spins over [{fl.SPAN[0]:g} lo, {fl.SPAN[1]:g} hi] of the aligned interval and "
            "the aligned system's multiplier meetings inside it; a spin without an orbit on the "
            "branch from the aligned top counts as unstable"}
    reason, eq = None, None
    if not bounded:
        reason = (f"with the moment tilted by {P['moment_tilt']:.6g} rad from the axis no spin rate "
                  "makes the top's periodic motion linearly stable (Floquet multipliers)")
    else:
        mid = math.sqrt(bounded[0][0] * bounded[0][1])
        c = ft.check(mid)
        if rotating:      # | |mu| - 1 | that rounding alone allows: exp(T tol) - 1 (the eigen route's bound)
            floq["multiplier_tolerance"] = float(np.max(np.expm1(c.tolerance * 2 * math.pi / mid)))
            floq["at_middle"] = {"spin": mid, "deviation": c.deviation, "trivial_residual": c.kept,
                                 "orbit_residual": c.residual}
            eq = _orbit_dict(model, ft, c.state, 2 * math.pi / mid, c.residual, res0.equilibrium["z_level"],
                             "the relative equilibrium in the frame turning about the vertical (zeta = 0) "
                             "at the window's middle spin: Newton on the gradient of H + sigma L_z, "
                             "continued in the moment tilt")
        else:
            orbit = ft.orbit(mid)
            floq["at_middle"] = {"spin": mid, "deviation": c.deviation, "trivial_residual": c.trivial_residual,
                                 "orbit_residual": orbit.residual}
            eq = _orbit_dict(model, ft, orbit.x0, orbit.period, orbit.residual, res0.equilibrium["z_level"],
                             "the periodic orbit's start (zeta = 0) at the window's middle spin: shooting "
                             "on the generated full_rhs, continued in the moment tilt")
        if len(bounded) > 1:
            (_, a), (b, _) = bounded[0], bounded[1]
            u = Units.of(P["g"])
            try:
                rate = ft.check(math.sqrt(a * b)).growth_rate
                grows = f"a perturbation grows by e every {1 / rate:.3g} {u.named('s')}"
            except (NoOrbit, NoEquilibrium):
                grows = "the steady motion on the branch from the aligned top is gone"
            reason = (f"{len(bounded)} disjoint spin intervals; spin_interval is the lowest: between it "
                      f"and the next ({a:.6g}-{b:.6g} {u.named('rad/s')}) {grows} (Floquet multipliers)")
    res = StabilityResult(None if eq is None else eq["position"][2], bounded[0] if bounded else None,
                          [], res0.eigenvalues, res0.approximations, reason, None, timings,
                          mass=P["m"], notes=[LEVEL_ONLY, "the eigenvalue route's interval is the "
                                              "aligned top's (moment tilt 0)"])
    res.equilibrium = eq if eq is not None else res0.equilibrium
    res.floquet = floq
    return res


def _orbit_dict(model, ft, x: np.ndarray, period: float, residual: float, z_level: float,
                route: str) -> dict:
    """The orbit's start x (zeta = 0) as `equilibrium` reports a point: position, axis, the offset
    from the plate's axis and the rise over the level height, and the period."""
    pos = [float(x[ft.states.index(k)]) for k in "xyz"]
    axis = np.asarray(model.call("full_axis", x, ft.p), float).ravel()
    return {"position": pos, "axis": [float(v) for v in axis], "tilt": ft.tilt,
            "tilt_azimuth": ft.P["base_tilt_azimuth"], "offset": float(math.hypot(pos[0], pos[1])),
            "downhill": float(pos[0] * math.cos(ft.P["base_tilt_azimuth"])
                              + pos[1] * math.sin(ft.P["base_tilt_azimuth"])),
            "rise": pos[2] - z_level, "z_level": z_level, "residual": residual,
            "period": period, "periodic": True, "route": route}


def moment_tolerance(model, p: np.ndarray, tick=None) -> dict:
    """max_moment_tilt (rad): the largest moment tilt b at which a stable spin window exists, by
    bisection in b (its upper bracket found by doubling from 1e-3 rad) of that existence. Where the
    relative-equilibrium route applies (level base, axisymmetric plate) each b's windows come from
    its eigenvalues (`_rotating_exists`) and b is bisected to RE_TILT_RTOL; else by shooting, to
    TILT_RTOL: the windows from the probes of `probes_for` and the middles of the windows found at
    the largest stable b so far. tick: called (no arguments) once per existence decided, doubling
    and bisection steps alike (a progress bar's step). None where the aligned top has no interval."""
    P = model.pvals(p)
    res0 = tilted_analysis(model, model.with_params({"moment_tilt": 0.0}, p))
    if res0.spin_interval is None:
        return {"max_moment_tilt": None}
    z_mag = res0.equilibrium["z_level"] + P.get("moment_offset", 0.0)
    why = req.refusal(model, p)
    if why is None:
        exists = _rotating_exists(model, p, z_mag, res0.spin_interval)
        how = ("bisection in the moment tilt of the existence of a stable Floquet window, each window "
               "by the eigenvalues of the relative equilibrium in the frame turning about the vertical")
        rtol = RE_TILT_RTOL
    else:
        exists = _shooting_exists(model, p, z_mag, res0.spin_interval)
        how = ("bisection in the moment tilt of the existence of a stable Floquet window, each window "
               f"by shooting (the relative-equilibrium route does not apply: {why})")
        rtol = TILT_RTOL

    def decided(b):
        got = exists(b)
        if tick is not None:
            tick()
        return got
    lo, hi = 0.0, 1e-3
    while decided(hi):
        lo, hi = hi, 2 * hi
        if hi >= math.pi / 2:
            return {"max_moment_tilt": float(lo), "bracket": [lo, None], "how": how}
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if decided(mid) else (lo, mid)
    return {"max_moment_tilt": float(lo), "bracket": [float(lo), float(hi)], "how": how}


def _shooting_exists(model, p: np.ndarray, z_mag: float, aligned: tuple[float, float]):
    """exists(b) by shooting: a window found before still holds, else the probes' windows."""
    keep = [math.sqrt(aligned[0] * aligned[1])]

    def exists(b):
        ft = fl.FloquetTop(model, model.with_params({"moment_tilt": b}, p), z_mag)
        if any(ft.stable(s) for s in keep):         # a window found before holds: it exists
            return True
        try:
            got = fl.spin_windows(ft.stable, probes_for(ft, aligned, keep), WINDOW_RTOL)
        except (NoOrbit, NoEquilibrium):
            return False
        got = [w for w in got if w[0] > 0]
        if got:
            keep[:] = [math.sqrt(a * c) for a, c in got]
        return bool(got)
    return exists


def _rotating_exists(model, p: np.ndarray, z_mag: float, aligned: tuple[float, float]):
    """exists(b) by the relative equilibrium's eigenvalues. The windows found last are kept with a
    spin inside each: where one of those spins is stable at b, its window is followed (bisected
    to WINDOW_RTOL between that spin and the old window's ends, so its middle tracks a window that
    shrinks to a point at max_moment_tilt); else the windows are searched afresh from the probes
    (the meetings computed once: they are the aligned system's) and LOCAL spins over each old
    window (a window near max_moment_tilt is narrower than the probes' spacing)."""
    base = req.RotatingTop(model, model.with_params({"moment_tilt": 0.0}, p), z_mag, fold_rtol=FOLD_RTOL)
    probes = sorted(probes_for(base, aligned) + meeting_probes(base, aligned))
    spans = [(probes[0], probes[-1])]
    keep = [math.sqrt(aligned[0] * aligned[1])]

    def exists(b):
        rt = base.at_tilt(b)
        for s, (a, c) in zip(keep, spans):
            if rt.stable(s):
                w = [w for w in fl.spin_windows(rt.stable, [a, s, c], WINDOW_RTOL) if w[0] <= s <= w[1]][0]
                found = [w]
                break
        else:       # near the old windows first (where a shrinking one still is), then everywhere
            local = [float(v) for a, c in spans for v in np.geomspace(a, c, LOCAL)]
            found = [w for w in fl.spin_windows(rt.stable, probes + keep + local, WINDOW_RTOL) if w[0] > 0]
        if found:
            keep[:] = [math.sqrt(a * c) for a, c in found]
            spans[:] = [(a * (1 - 2 * WINDOW_RTOL), c * (1 + 2 * WINDOW_RTOL)) for a, c in found]
        return bool(found)
    return exists
