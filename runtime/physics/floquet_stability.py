"""The spin window of a top whose moment is off its axis (route "Floquet"), and how crooked it may be.

`floquet_analysis`: the aligned top first (moment tilt 0: the relative equilibrium and its eigen
route, runtime/physics/tilted_stability.py), then the periodic orbits at the scene's moment tilt
and their multipliers (runtime/physics/floquet.py) on a log grid around the aligned window, the
aligned system's meetings of multipliers, and bisection of every change of verdict.
`moment_tolerance`: max_moment_tilt, the largest moment tilt at which a stable spin interval
exists, by bisection in the tilt of that existence, each window found from the last one's spins.
No sympy here.
"""
from __future__ import annotations

import math
import time

import numpy as np

from levitron.runtime.physics import floquet as fl
from levitron.runtime.physics.periodic_orbit import NoOrbit
from levitron.runtime.physics.stability_result import StabilityResult
from levitron.runtime.physics.tilted_equilibrium import NoEquilibrium
from levitron.runtime.ui.human import Units
from levitron.runtime.physics.tilted_stability import LEVEL_ONLY, reduced_jacobian, tilted_analysis

ROUTE = ("Floquet: periodic orbit by shooting on the generated full_rhs (CVODES, CasADi "
         "sensitivities), multipliers of its monodromy matrix less the two trivial ones "
         f"(flow, energy), stable where all lie on the unit circle to {fl.MULT_TOL:g}")
TILT_RTOL = 1e-2         # max_moment_tilt is bisected to this relative width
WINDOW_RTOL = 1e-3       # and the windows along it to this (their existence is what counts)


def probes_for(ft: fl.FloquetTop, aligned: tuple[float, float], extra=()) -> list[float]:
    """The spins probed: GRID log-spaced over [SPAN[0] lo, SPAN[1] hi] of the aligned window, the
    aligned system's multiplier meetings inside it (for a moment tilt != 0), and `extra`."""
    lo0, hi0 = aligned
    out = list(np.geomspace(fl.SPAN[0] * lo0, fl.SPAN[1] * hi0, fl.GRID)) + list(extra)
    if ft.b != 0:
        eq0 = ft.top.hamilton(ft.tilt, lo0)
        n = len(eq0.states)
        jf = ft.model.fast("full_jac", ft.aligned)
        found = fl.meetings(lambda s: reduced_jacobian(jf(eq0.at_spin(s)).reshape(n, n), eq0.states),
                            lo0, hi0)
        near = sorted(found, key=lambda s: min(abs(math.log(s / lo0)), abs(math.log(s / hi0))))
        out += near[:fl.MAX_MEETINGS]
    return sorted(out)


def floquet_analysis(model, p: np.ndarray) -> StabilityResult:
    """The StabilityResult of the scene's top with its moment tilted (p's moment_tilt, any base
    tilt): spin_interval the lowest bounded Floquet window; `floquet` the route's windows, its
    tolerance and the multipliers' deviation at the window's middle; the aligned top's interval
    (eigen route) beside it; `equilibrium` the orbit's start at that middle."""
    t0 = time.perf_counter()
    P = model.pvals(p)
    res0 = tilted_analysis(model, model.with_params({"moment_tilt": 0.0}, p))
    if res0.spin_interval is None:
        res0.reason = f"the aligned top (moment tilt 0): {res0.reason}"
        return res0
    ft = fl.FloquetTop(model, p, res0.equilibrium["z_level"] + P.get("moment_offset", 0.0))
    windows = fl.spin_windows(ft.stable, probes_for(ft, res0.spin_interval))
    timings = {**res0.timings, "floquet": time.perf_counter() - t0}
    bounded = [w for w in windows if w[0] > 0]
    floq = {"route": ROUTE, "windows": [list(w) for w in windows], "moment_tilt": P["moment_tilt"],
            "multiplier_tolerance": fl.MULT_TOL, "spin_rtol": fl.SPIN_RTOL,
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
        orbit = ft.orbit(mid)
        floq["at_middle"] = {"spin": mid, "deviation": c.deviation, "trivial_residual": c.trivial_residual,
                             "orbit_residual": orbit.residual}
        eq = _orbit_dict(model, ft, orbit, res0.equilibrium["z_level"])
        if len(bounded) > 1:
            (_, a), (b, _) = bounded[0], bounded[1]
            rate = ft.check(math.sqrt(a * b)).growth_rate
            u = Units.of(P["g"])
            reason = (f"{len(bounded)} disjoint spin intervals; spin_interval is the lowest: between it "
                      f"and the next ({a:.6g}-{b:.6g} {u.named('rad/s')}) a perturbation grows by e every "
                      f"{1 / rate:.3g} {u.named('s')} (Floquet multipliers)")
    res = StabilityResult(None if eq is None else eq["position"][2], bounded[0] if bounded else None,
                          [], res0.eigenvalues, res0.approximations, reason, None, timings,
                          mass=P["m"], notes=[LEVEL_ONLY, "the eigenvalue route's interval is the "
                                              "aligned top's (moment tilt 0)"])
    res.equilibrium = eq if eq is not None else res0.equilibrium
    res.floquet = floq
    return res


def _orbit_dict(model, ft: fl.FloquetTop, orbit, z_level: float) -> dict:
    """The orbit's start (zeta = 0) as `equilibrium` reports a point: position, axis, the offset
    from the plate's axis and the rise over the level height, and the period."""
    x = orbit.x0
    pos = [float(x[ft.states.index(k)]) for k in "xyz"]
    axis = np.asarray(model.call("full_axis", x, ft.p), float).ravel()
    return {"position": pos, "axis": [float(v) for v in axis], "tilt": ft.tilt,
            "tilt_azimuth": ft.P["base_tilt_azimuth"], "offset": float(math.hypot(pos[0], pos[1])),
            "downhill": float(pos[0] * math.cos(ft.P["base_tilt_azimuth"])
                              + pos[1] * math.sin(ft.P["base_tilt_azimuth"])),
            "rise": pos[2] - z_level, "z_level": z_level, "residual": orbit.residual,
            "period": orbit.period, "periodic": True,
            "route": "the periodic orbit's start (zeta = 0) at the window's middle spin: shooting on "
                     "the generated full_rhs, continued in the moment tilt"}


def moment_tolerance(model, p: np.ndarray) -> dict:
    """max_moment_tilt (rad): the largest moment tilt b at which a stable spin window exists, by
    bisection in b to TILT_RTOL (its upper bracket found by doubling from 1e-3 rad); at each b the
    windows are found from the probes of `probes_for` and the middles of the windows found at
    the largest stable b so far. None where the aligned top has no interval."""
    P = model.pvals(p)
    res0 = tilted_analysis(model, model.with_params({"moment_tilt": 0.0}, p))
    if res0.spin_interval is None:
        return {"max_moment_tilt": None}
    z_mag = res0.equilibrium["z_level"] + P.get("moment_offset", 0.0)
    keep = [math.sqrt(res0.spin_interval[0] * res0.spin_interval[1])]

    def exists(b):
        ft = fl.FloquetTop(model, model.with_params({"moment_tilt": b}, p), z_mag)
        if any(ft.stable(s) for s in keep):         # a window found before holds: it exists
            return True
        try:
            got = fl.spin_windows(ft.stable, probes_for(ft, res0.spin_interval, keep), WINDOW_RTOL)
        except (NoOrbit, NoEquilibrium):
            return False
        got = [w for w in got if w[0] > 0]
        if got:
            keep[:] = [math.sqrt(a * c) for a, c in got]
        return bool(got)
    lo, hi = 0.0, 1e-3
    while exists(hi):
        lo, hi = hi, 2 * hi
        if hi >= math.pi / 2:
            return {"max_moment_tilt": float(lo), "bracket": [lo, None]}
    while hi - lo > TILT_RTOL * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if exists(mid) else (lo, mid)
    return {"max_moment_tilt": float(lo), "bracket": [float(lo), float(hi)],
            "how": "bisection in the moment tilt of the existence of a stable Floquet window"}
