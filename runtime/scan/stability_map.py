"""Stability maps: which (spin, tilt | mass | height) starts keep the top up (docs/contract.md `scan`).

The thesis's fig. 3.8 (after Gans, Jones & Nelson / Gans et al.) shows the stable trajectories as a
function of spin and tilt. Here every grid point is one nonlinear run of the full model
(`point_run`: runtime.simulate.run.simulate from the same pieces, thesis 3.1-3.2: the C integrators
over the generated Hamilton equations 2.3.10-2.3.16), started at the vertically stable hover height
z_s (thesis 3.3.2-3.3.3, found once per mass rather than once per point), and a point
"levitates" when the top stays inside the box of runtime.simulate.run (|z - z_s| and the radial offset
at most z_s / 2) for the whole run. (A top started exactly upright on the axis, tilt 0, stays on
the invariant set of thesis 3.2.1 by symmetry and "levitates" at any spin: the tilt-0 row of a tilt
map is that symmetric solution, not a stability statement.) The second axis is one of

* ``tilt``:   the initial tilt of the symmetry axis (rad), as in `levitron simulate --tilt`;
* ``mass``:   the top's mass (kg). m is a runtime parameter of the generated model (no new
  derivation); each mass starts at its own hover height z_s(m) (the lowest vertically stable root of
  m g + mu Phi_2(z) = 0, thesis 3.3.2). Masses the plate cannot hold stably are marked not levitating
  without a run (status "no_hover_height");
* ``height``: the initial vertical displacement as a FRACTION of z_s: the top starts at rest (apart
  from its spin) at z_0 = z_s (1 + height). A fraction, not a length, because scenes may be
  dimensionless (docs/contract.md); |height| < 1/2 keeps the start inside the box.

For the mass and height axes the runs start with the small tilt ``base_tilt`` (default 0.01 rad):
an upright top on the axis stays there by symmetry, whatever its linear stability, so a seed is
needed for an unstable transverse mode to grow.

Default run length: ``PERIODS`` (3) periods of the slowest motion at the relative equilibrium, i.e.
the slowest transverse (precession/wobble) mode of the 8-D linearisation after thesis 3.3.5
(runtime.physics.routes.eigen_route.transverse_matrix) at a spin inside the linear interval, or the vertical bounce
2 pi sqrt(m / (mu Phi_3)) (thesis 3.3.3) if that is slower. For the thesis plate with a 51.5 g top
the slow mode is ~1.8 rad/s (3.5 s), so the default is ~10.5 s; a top that is linearly unstable
typically leaves the box within a few e-folding times, and over three slow periods even weak
instabilities near the ends of the interval (growth ~0.5/s from a 0.01 rad seed) show. A mass
scan takes the median slow period over the masses that some spin stabilises (near the critical
height z_c the vertical bounce period diverges, so the longest would be unbounded).

The linear stability interval (thesis 3.3, runtime.physics.stability.analysis.analyse: exact discriminant route) is
reported beside the map, per value of the second axis (it changes only with the mass), together
with the fraction of grid points where the nonlinear run agrees with it.

This module orchestrates the map (`scan`); its answer is runtime/scan/scan_answer.py's `Scan`. The
pieces, one idea each:
runtime/scan/grid.py (the axes and their ranges), runtime/scan/runners.py (one grid point, the
chunks of the grid, and the serial, process and dask runners), runtime/scan/chunk_c.py (a chunk in one
C call: runtime/csrc/scan_driver.c), runtime/scan/physics.py (the linear interval and the slow
period), runtime/scan/plot.py (the picture).

cpu_s is the CPU time of the chunks (the threads that ran them: inputs and integration, not the
start of worker processes), to compare with rhs_evals times the cost of one right-hand side.
"""
from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.methods import DEFAULT, default_step, refuse_on_full_model
from levitron.runtime.integrate.verdict import NO_HOVER, PAST_WINDOW, past_window
from levitron.runtime.scan.grid import AXES, MAX_POINTS, check_axis
from levitron.runtime.scan.scan_answer import Scan
from levitron.runtime.scan.physics import linear_interval, reference_spin, slow_period
from levitron.runtime.scan.points import N_OUT
from levitron.runtime.simulate.start import PERIODS   # default run length in slow periods (docstring)
from levitron.runtime.scan.runners import (
    Common,
    dask_client,
    dask_threads,
    remember,
    run_dask,
    run_processes,
    run_serial,
    split,
    usable_cores,
)
from levitron.runtime.ui.human import Units
from levitron.runtime.words import si
from levitron.runtime.ui import validate
from levitron.runtime.ui.validate import axis_values, real
from levitron.runtime.scan.workers import auto_workers, dask_errors_as_ours

BASE_TILT = 0.01       # rad, the seed tilt of mass and height scans
MIN_POINTS = 4         # a map of fewer points runs serially by default (runtime/scan/workers.py)
CHUNKS_PER_WORKER = 8  # chunks per worker (process or dask thread): the last ones balance the load
ENGINES = ("c", "python")


def check_run_options(model, axis: str, spins: np.ndarray, others: np.ndarray, hover: Sequence,
                      t_end: float, integrator: str, tol: float | None, h: float | None) -> None:
    """Refuse, before any run, options that no run of the grid can honour
    (runtime.integrate.budget.check_options at the fastest time scale of the grid: the largest |spin|,
    each hover height; fixed-step runs without --step take 1/100 of their own fastest period)."""
    from levitron.runtime.integrate.methods import lookup
    from levitron.runtime.simulate.start import time_scale
    from levitron.runtime.integrate.budget import check_options
    spin = float(np.abs(spins).max())
    fastest = None
    for j, z_s in enumerate(hover):
        if z_s is None:
            continue
        p = model.with_params({"m": others[j]}) if axis == "mass" else model.p
        T = time_scale(model, p, z_s, spin, model.pvals(p))
        fastest = T if fastest is None or T[0] < fastest[0] else fastest
    if fastest is None:
        return
    T, what = fastest
    refuse_on_full_model(integrator, "a scan")
    fixed = lookup(integrator).fixed_step
    check_options(integrator, t_end, None if fixed else tol, (h or default_step(T)) if fixed else h,
                  N_OUT, T, what)


def scan(model, spins: np.ndarray, axis: str, others: np.ndarray, t_end: float | None = None,
         integrator: str = DEFAULT, tol: float | None = 1e-9, workers: int | None = None,
         scheduler: str | None = None,
         base_tilt: float = BASE_TILT, h: float | None = None, quiet: bool = False,
         engine: str = "c", scheduler_timeout: float | None = None) -> Scan:
    """Run the map (module docstring); the workers load the same model from model.ref.
    engine "c": chunks of points through the C chunk driver (runtime/scan/chunk_c.py) when the integrator
    is a C one; "python": one runtime.simulate.run-style run per point (the reference path).
    workers None: every usable core (runtime/scan/workers.py), serial with a scheduler."""
    spins, others, workers, t_end, base_tilt = _checked(axis, spins, others, workers, scheduler,
                                                        t_end, engine, base_tilt)
    if scheduler_timeout is not None:       # the wait for a dask scheduler: up to an hour
        scheduler_timeout = real(scheduler_timeout, "«scheduler_timeout»", positive=True, max_abs=3600, unit="s")
    t_wall = time.perf_counter()
    lin, hover, scene_lin, status_pre = _hover_and_linear(model, axis, others)
    tilted = tilted_sites(model, axis, others, hover, status_pre)
    if t_end is None:
        t_end, basis = _default_t_end(model, axis, spins, lin, status_pre)
    else:
        basis = {"given": True}
    from levitron.runtime.integrate.methods import resolve
    choice = resolve(integrator, tol, h)        # once: "auto" is the method it picks from here on
    integrator = choice.name
    check_run_options(model, axis, spins, others, hover, float(t_end), integrator, tol, h)
    common = Common(*model.ref, axis, float(t_end), integrator, tol,
                    float(base_tilt), tuple(hover), h, engine)
    tasks = [(i, j, float(s), float(o)) for i, s in enumerate(spins) for j, o in enumerate(others)
             if j not in status_pre]
    chunk_results, runner = _run_tasks(model, common, tasks, workers, scheduler, scheduler_timeout,
                                       quiet)
    lev, ts, status, rhs = _assemble(spins, others, status_pre,
                                     [r for c in chunk_results for r in c["points"]])
    past = past_its_window(model, spins, lin, float(t_end), lev, status)
    return Scan(axis, spins, others, lev, ts, status, lin, float(t_end), basis,
                      time.perf_counter() - t_wall, runner, rhs,
                      sum(c["cpu_s"] for c in chunk_results),
                      extra={"scene_linear": scene_lin,
                             "public": {"integrator": integrator, "integrator_requested": choice.requested,
                                        "tol": tol,
                                        "base_tilt": base_tilt if axis != "tilt" else None,
                                        "past_window": past,
                                        **({"equilibrium": tilted} if tilted else {})}},
                      units=Units.of_scene(model.scene), scene=model.scene.name)


def _checked(axis: str, spins, others, workers, scheduler, t_end, engine: str, base_tilt):
    """The scan's inputs checked (one-line UserErrors) and normalised: (spins, others, workers,
    t_end, base_tilt)."""
    if axis not in AXES:
        raise UserError(f"unknown axis {axis!r}; scan over one of «tilt», «mass», «height»")
    spins = axis_values(spins, "spin", MAX_POINTS)
    others = axis_values(others, axis, MAX_POINTS)
    check_axis(axis, others)
    if workers is None:
        workers = 1 if scheduler is not None else auto_workers(spins.size * others.size, MIN_POINTS)
    workers = validate.workers(workers)
    if spins.size * others.size > MAX_POINTS:
        raise UserError(f"{spins.size * others.size} grid points is too many (at most {MAX_POINTS}); "
                        "use fewer points per axis")
    if scheduler is not None and workers != 1:
        raise UserError("pass either «workers» N (local processes) or «scheduler» ADDRESS (dask), not both")
    if t_end is not None:
        t_end = validate.run_length(t_end)
    if engine not in ENGINES:
        raise UserError(f"unknown engine {engine!r}; choose one of: {', '.join(ENGINES)}")
    base_tilt = real(base_tilt, "«base_tilt»", max_abs=math.pi, unit="rad")
    if axis != "tilt" and base_tilt == 0:
        raise UserError("«base_tilt=0» launches every point on the invariant set (thesis 3.2.1), "
                        f"where the ideal top stays at any spin: the map would test nothing; give a "
                        f"small tilt, e.g. «base_tilt={BASE_TILT}»")
    return spins, others, workers, t_end, base_tilt


def _hover_and_linear(model, axis: str, others: np.ndarray):
    """The hover heights (runtime.physics.equilibrium.finder.hover_height, thesis 3.3.2-3.3.3) and the
    linear picture per value of the other axis: (linear, hover, the scene's linear, the statuses
    of the columns that are not run: {j: "no_hover_height"})."""
    from levitron.runtime.physics.equilibrium.finder import hover_height
    status_pre: dict[int, str] = {}
    if axis != "mass":
        lin = linear_interval(model)
        return [lin] * len(others), [hover_height(model)] * len(others), lin, status_pre
    lin, hover = [], []
    for j, m in enumerate(others):
        p = model.with_params({"m": m})
        try:
            hover.append(hover_height(model, p))
        except UserError:
            hover.append(None)
            status_pre[j] = NO_HOVER
        lin.append(linear_interval(model, m))
    return lin, hover, linear_interval(model), status_pre


START = ("every run starts at the top's relative equilibrium over the tilted base (as `simulate` "
         "does), perturbed by the map's tilt (or height)")


def tilted_sites(model, axis: str, others: np.ndarray, hover: list, status_pre: dict) -> dict | None:
    """Over a tilted base (plate.tilt) every run starts at the top's relative equilibrium there
    (runtime/scan/points.py off_axis): each site's is found here first. A mass without one is
    marked as one that cannot hover (status_pre); a tilt or height map whose top has none is
    refused in one line. Returns the scene's top's equilibrium (as stability --json's
    `equilibrium`, with `start`), None over a level base."""
    if "base_tilt" not in model.param_names:
        return None
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium, TiltedTop
    tilt = model.pvals()["base_tilt"]
    for j, z in enumerate(hover):
        if j in status_pre or z is None:
            continue
        p = model.with_params({"m": float(others[j])}) if axis == "mass" else model.p
        try:
            TiltedTop(model, p, z).hamilton(tilt, 1.0)
        except NoEquilibrium as exc:
            if axis != "mass":
                raise UserError(f"a map over a tilted base starts at the top's equilibrium there, "
                                f"and {exc}") from None
            status_pre[j] = NO_HOVER
    try:
        z = hover_height(model)
        eq = TiltedTop(model, model.p, z).hamilton(tilt, 1.0)
    except UserError:          # (a mass map) the scene's own top has no hover height or equilibrium
        return {"tilt": tilt, "position": None, "start": START}
    return {**eq.as_dict(z - model.pvals().get("moment_offset", 0.0)), "start": START}


def _default_t_end(model, axis: str, spins: np.ndarray, lin: list, status_pre: dict):
    """The default run length and its basis: PERIODS slow periods of the scene's top (mass scan:
    the median over the masses that some spin stabilises, else over those that hover)."""
    cands = [li for j, li in enumerate(lin) if j not in status_pre and li["z_s"] is not None]
    good = [li for li in cands if li["spin_interval"] is not None]
    pool = cands if axis != "mass" else (good or cands)
    if not pool:
        raise UserError("no value of the scan has a stable hover height to set a run length "
                        "from; pass «t_end» T or change the «mass» range (see `«levitron=equilibrium»`)")
    rows = sorted((slow_period(model, li["mass"], li["z_s"], reference_spin(li["spin_interval"], spins)),
                   reference_spin(li["spin_interval"], spins), li["mass"]) for li in pool)
    T, ref, m_ref = rows[(len(rows) - 1) // 2]
    return PERIODS * T, {"periods": PERIODS, "slow_period_s": T, "reference_spin": ref, "mass": m_ref,
                         "note": "default: periods of the slowest motion at the relative equilibrium "
                                 "(transverse modes, thesis 3.3.5, or the vertical bounce, 3.3.3)"}


def _run_tasks(model, common: Common, tasks: list, workers: int, scheduler: str | None,
               scheduler_timeout: float | None, quiet: bool) -> tuple[list[dict], dict]:
    """The tasks dealt into chunks and run on dask, local processes or serially here: (the chunks'
    results, the runner's description)."""
    if scheduler is not None:
        with dask_errors_as_ours():
            client = dask_client(scheduler, scheduler_timeout)
            try:
                threads = dask_threads(client)
                chunks = split(tasks, CHUNKS_PER_WORKER * threads)
                runner = {"kind": "dask", "scheduler": scheduler, "threads": threads}
                chunk_results = run_dask(common, chunks, client, quiet, timeout=scheduler_timeout)
            finally:
                client.close()
    elif workers > 1 and len(tasks) > 1:
        n = min(workers, len(tasks), usable_cores())
        if n < min(workers, len(tasks)):
            print(f"levitron: {workers} worker processes capped at the {n} cores this process may use (the "
                  "runs are CPU-bound: more processes than cores only add switching)", file=sys.stderr)
        chunks = split(tasks, CHUNKS_PER_WORKER * n)
        runner = {"kind": "processes", "workers": n}
        chunk_results = run_processes(common, chunks, n, quiet)
    else:
        chunks = split(tasks, CHUNKS_PER_WORKER)
        runner = {"kind": "serial", "workers": 1}
        remember(common, model)
        chunk_results = run_serial(common, chunks, quiet)
    runner["chunks"] = len(chunks)
    runner["engine"] = "+".join(sorted({c["engine"] for c in chunk_results})) or None
    return chunk_results, runner


def _assemble(spins: np.ndarray, others: np.ndarray, status_pre: dict, results: list[dict]):
    """The points' results as the map's arrays: (levitating, t_survived, status, rhs_evals)."""
    shape = (spins.size, others.size)
    lev = np.zeros(shape, bool)
    ts = np.zeros(shape)
    status = [["" for _ in others] for _ in spins]
    for i in range(spins.size):
        for j, why in status_pre.items():
            status[i][j] = why
    rhs = 0
    for r in results:
        lev[r["i"], r["j"]] = r["levitating"]
        ts[r["i"], r["j"]] = r["t_survived"]
        status[r["i"]][r["j"]] = r["status"]
        rhs += int(r["rhs_evals"] or 0)
    return lev, ts, status, rhs


def past_its_window(model, spins: np.ndarray, lin: list, t_end: float, lev: np.ndarray, status: list) -> dict:
    """No verdict without the physics to support it: a point up at t_end whose spin, by the decay law
    omega_3(t) = omega_3(0) exp(-t / tau) (exact in air: runtime/physics/apparatus/friction.py), ends the run
    below its column's lower critical spin is past its stable window, the run ended before the fall
    the adiabatic prediction puts before t_end (runtime/integrate/verdict.py past_window, simulate's
    own test): its status becomes PAST_WINDOW and it is not levitating (lev and status changed in
    place). Returns the JSON's `past_window`: {"points": how many, "reason": the first one's, with
    its spin, or None}."""
    from levitron.runtime.physics.apparatus.friction import crossing_time, has_friction
    k = model.pvals().get("k_spin", 0.0) if has_friction(model) else 0.0
    n, reason = 0, None
    if not k > 0:
        return {"points": 0, "reason": None}
    for i, spin in enumerate(spins):
        for j, li in enumerate(lin):
            iv = li.get("spin_interval")
            lower = iv[0] if iv else None
            why = past_window(status[i][j], t_end, lower, abs(spin) * math.exp(-k * t_end),
                              crossing_time(spin, lower, k) if lower else None)
            if why:
                status[i][j], lev[i, j], n = PAST_WINDOW, False, n + 1
                reason = reason or f"spin {si(abs(spin), 'rad/s')} at launch: {why}"
    return {"points": n, "reason": reason}
