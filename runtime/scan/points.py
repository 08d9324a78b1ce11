"""One point of a map, set up and run: runtime.simulate's pieces (initial state, box, time scale,
scales; thesis 3.1-3.3) shared by the Python path (`point_run`) and the C chunk driver
(runtime/scan/chunk_c.py), so that both integrate the same problem. Over a tilted base (plate.tilt)
a point starts where `simulate` starts: its perturbation (tilt, height) applied at the relative
equilibrium off the axis (runtime/simulate/start.py tilted_start)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from levitron.runtime.integrate.methods import DEFAULT, default_step

N_OUT = 100            # dense-output samples per run: only the survival matters here


@dataclass(frozen=True)
class PointSetup:
    """Everything one run of a grid point needs (runtime.simulate.run's pieces, thesis 3.1-3.3)."""
    part: object
    p: np.ndarray
    z_s: float
    box: object                 # runtime.integrate.trajectory.Box
    time_scale: float
    time_scale_what: str
    h: float | None             # fixed-step integrators: the step; adaptive: None
    x0: np.ndarray
    scale: np.ndarray           # state magnitudes: atol = tol * scale


def point_setup(model, spin: float, tilt: float = 0.0, height: float = 0.0,
                integrator: str = DEFAULT, h: float | None = None, p: np.ndarray | None = None,
                z_s: float | None = None, memo: dict | None = None) -> PointSetup:
    """The initial state (runtime.simulate.run.initial_state: the Legendre map of the generated rhs),
    box, fastest time scale and state scales of one grid point, started at z_0 = z_s (1 + height)
    (thesis 3.3.2); shared by `point_run` and the C chunk driver (runtime/scan/chunk_c.py), so that both
    integrate the same problem. memo: a dict shared by the points of a chunk, which keeps the
    spin-free inputs (hover height, vertical stiffness, box, the simulate.Launch with its Legendre
    map) per parameters, hover height, tilt and height: the same numbers, computed once."""
    from levitron.runtime.simulate import start
    from levitron.runtime.integrate.methods import lookup
    p = model.p if p is None else p
    memo = {} if memo is None else memo
    site_key = (np.asarray(p).tobytes(), z_s)
    site = memo.get(site_key)
    if site is None:
        pt, pvals = model.part("full"), model.pvals(p)
        if z_s is None:
            from levitron.runtime.physics.equilibrium.finder import hover_height
            z_s = hover_height(model, p)
        site = memo[site_key] = (pt, pvals, z_s, start.vertical_stiffness(model, p, z_s, pvals),
                                 start.default_box(pt, z_s))
    pt, pvals, z_s, stiffness, box = site
    launch_key = (site_key, tilt, height)
    la = memo.get(launch_key)
    if la is None:
        la = memo[launch_key] = start.launch(pt, z_s * (1.0 + height), tilt, 0.0, p)
    T, what = start.fastest_period(spin, pvals, stiffness)
    if lookup(integrator).fixed_step and h is None:
        h = default_step(T)
    x0 = start.launch_state(la, spin)
    if "base_tilt" in model.param_names:
        x0 = off_axis(model, memo, site_key, pt, p, z_s, spin, x0)
    return PointSetup(pt, p, z_s, box, T, what, h, x0, start.state_scales(pt, z_s, spin, pvals))


def tilted_top(model, p: np.ndarray, z_s: float, memo: dict, site_key):
    """The site's runtime.physics.apparatus.tilted_equilibrium.TiltedTop, once per chunk and site (it keeps
    the branch it found: the other spins' equilibria start from it)."""
    from levitron.runtime.physics.apparatus.tilted_equilibrium import TiltedTop
    key = (site_key, "tilted")
    if key not in memo:
        memo[key] = TiltedTop(model, p, z_s)
    return memo[key]


def off_axis(model, memo: dict, site_key, pt, p: np.ndarray, z_s: float, spin: float,
             x0: np.ndarray) -> np.ndarray:
    """Over a tilted base: x0 less the unperturbed launch on the axis, at the relative equilibrium
    at this spin (simulate's tilted_start); a NoEquilibrium (a one-line UserError) where the tilt
    leaves the top none (`scan` checks every site before it runs)."""
    from levitron.runtime.simulate import start
    key = (site_key, 0.0, 0.0)
    if key not in memo:
        memo[key] = start.launch(pt, z_s, 0.0, 0.0, p)
    level = start.launch_state(memo[key], spin)
    sigma = level[pt.states.index("p_zeta")] / model.pvals(p)["C"]
    eq = tilted_top(model, p, z_s, memo, site_key).hamilton(model.pvals(p)["base_tilt"],
                                                           sigma if sigma != 0 else 1.0)
    return eq.at_spin(sigma) + (x0 - level)


def point_run(model, spin: float, tilt: float = 0.0, height: float = 0.0, t_end: float = 1.0,
              integrator: str = DEFAULT, tol: float | None = 1e-9, h: float | None = None,
              p: np.ndarray | None = None, z_s: float | None = None, n_out: int = N_OUT) -> dict:
    """levitron.runtime.simulate.run.simulate from the same pieces (initial state, box, scales, integrator,
    summary), with two differences: the hover height z_s may be given (a scan finds it once per
    mass, not once per point: it costs more than a short run), and the top may start displaced to
    z_0 = z_s (1 + height), at rest vertically; box and checks stay centred on z_s (thesis 3.3.2).
    With height = 0 the result is simulate()'s, number for number (tests/runtime/scan/test_scan.py)."""
    from levitron.runtime.simulate import run as sim
    from levitron.runtime.integrate.run import integrate
    from levitron.runtime.integrate.methods import resolve
    choice = resolve(integrator, tol, h)     # "auto": the method simulate() would run
    su = point_setup(model, spin, tilt, height, choice.name, h, p, z_s)
    choice = choice.with_step(su.h) if choice.fixed_step else choice
    res = integrate(su.part, su.x0, t_end, method=choice.name, tol=choice.tol, h=choice.h, p=su.p,
                    box=su.box, n_out=n_out, scale=su.scale, monitor_energy=choice.entry.monitors_energy,
                    time_scale=su.time_scale, time_scale_what=su.time_scale_what)
    return sim.summarize(su.part, res, su.x0, su.p, su.z_s, su.box, spin, tilt, 0.0, t_end, choice, None)
