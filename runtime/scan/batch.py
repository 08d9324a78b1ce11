"""Many launches of runtime.simulate.run.simulate in one call of the C chunk driver (thesis 3.1-3.3).

`simulate_many(model, spin, tilt, offset, azimuth, params=...)` takes numbers or 1-D arrays,
broadcast to one length k, and sets up each launch from simulate()'s own pieces
(runtime/simulate/start.py): the hover height z_s of its parameters (thesis eqs. 3.3.2-3.3.3), the
initial state through the Legendre map of the generated rhs (thesis eq. 2.3.8), the box, the
fastest time scale, the state scales and the default step budget. The spin-free pieces are
computed once per parameter vector and launch position (a spin sweep builds one Legendre map).
Then all k runs are one lev_scan_chunk call (runtime/scan/chunk_c.py drive_runs), LEV_LANES at a
time on the lane variant of the rhs where it verifies: no Python per run or per step.

Each run is the one simulate() makes with the same options, without its samples and energy
monitor (neither changes a step), so the status, survival time, rhs count and final state are
simulate()'s, bit for bit (tests/runtime/scan/test_batch.py). A launch whose top cannot hover (its parameters
give no stable hover height) is a result with its reason, the others run as before. In air the
run stops when the top leaves the box, as simulate()'s; the flight block (fall spin, adiabatic
prediction) needs the samples and is simulate()'s alone.
"""
from __future__ import annotations

import math
import time
from collections.abc import Mapping

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.integrate.budget import check_options, default_budget
from levitron.runtime.integrate.methods import DEFAULT, default_step, refuse_on_full_model, resolve
from levitron.runtime.integrate.verdict import NO_HOVER, stopped_early
from levitron.runtime.ui.validate import real

MAX_LAUNCHES = 10**6
CHECK_N_OUT = 2            # check_options' sample count: the driver keeps no samples


def _column(value, label: str, max_abs: float | None = None) -> np.ndarray:
    """A number or a 1-D sequence of finite numbers as a 1-D float array."""
    if isinstance(value, (str, bytes)):
        raise UserError(f"{label} must be a number or a list of numbers, not {value!r}")
    try:
        a = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise UserError(f"{label} must be a number or a list of numbers, not {value!r}") from None
    if a.ndim != 1 or a.size == 0:
        raise UserError(f"{label} must be a number or a non-empty 1-D list of numbers (got shape {a.shape})")
    if not np.all(np.isfinite(a)):
        raise UserError(f"{label}: every value must be finite (got {a[~np.isfinite(a)][0]})")
    if max_abs is not None and np.any(np.abs(a) > max_abs):
        raise UserError(f"{label}: {a[np.abs(a) > max_abs][0]:g} is beyond +-{max_abs:g}: give smaller values")
    return a


def launch_columns(columns: Mapping[str, object]) -> dict[str, np.ndarray]:
    """The columns broadcast to one length (a number repeats); a one-line UserError when two
    lengths differ and neither is 1."""
    arrays = {k: _column(v, k, math.pi if k == "tilt" else None) for k, v in columns.items()}
    sizes = sorted({a.size for a in arrays.values()} - {1})
    if len(sizes) > 1:
        given = ", ".join(f"{k} {a.size}" for k, a in arrays.items() if a.size > 1)
        raise UserError(f"the launch columns have different lengths ({given}): give arrays of one "
                        "length, or single numbers")
    k = sizes[0] if sizes else 1
    if k > MAX_LAUNCHES:
        raise UserError(f"{k} launches is too many for one call (at most {MAX_LAUNCHES})")
    return {name: np.broadcast_to(a, (k,)).copy() for name, a in arrays.items()}


def simulate_many(model, spin, tilt=None, offset=0.0, azimuth=None, t_end: float | None = None,
                  integrator: str = DEFAULT, tol: float | None = 1e-9, box: float | None = None,
                  h: float | None = None, params: Mapping[str, object] | None = None,
                  p=None, part: str = "full") -> dict:
    """k runs of simulate() (module docstring) in one C call. spin (rad/s), tilt (rad; None: as
    simulate(), DEFAULT_TILT for the full model, 0 for the reduced one), offset (m), azimuth (rad;
    None: DEFAULT_AZIMUTH) and the values of `params` (manifest parameter names -> numbers or
    arrays: a parameter vector per launch, each with its own hover height) broadcast to length k;
    p: parameter vectors (k, n_p) or one (n_p,) that `params` then changes (default the scene's).
    t_end, integrator (a C one), tol, box, h: one for all runs, as simulate()'s. Returns arrays
    of length k: levitating, untested (a launch on the invariant set, or a run that stopped early
    without a verdict, runtime/integrate/verdict.py: simulate()'s levitating None), status,
    t_survived, rhs_evals, steps, z_s, final_state (k, n), reason; plus states, inputs,
    t_end (None if no launch ran and none was given), integrator, integrator_requested, tol, step,
    lanes and wall_s. A launch whose parameters give no stable hover height is a result, not an
    error of the call: it is not run, status NO_HOVER ("no_hover_height", the maps' word), reason
    the one line that says why (else None), levitating False, untested False, t_survived 0, z_s and
    final_state NaN."""
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.scan.chunk_c import drive_runs
    from levitron.runtime.simulate import run as sim, rotations, start
    t_wall = time.perf_counter()
    t_end = None if t_end is None else real(t_end, "t_end (run length)", unit="s")
    tol = None if tol is None else real(tol, "tol (tolerance)")
    box = None if box is None else real(box, "box", positive=True, unit="m")
    h = None if h is None else real(h, "step", positive=True, unit="s")
    pt = model.part(part)
    if tilt is None:
        tilt = start.DEFAULT_TILT if rotations.coordinates_of(pt) is not None else 0.0
    names = list(params or {})
    unknown = [n for n in names if n not in model.param_names]
    if unknown:
        raise UserError(f"unknown parameter {unknown[0]!r}: use one of {', '.join(model.param_names)}")
    cols = launch_columns({"spin": spin, "tilt": tilt, "offset": offset,
                           "azimuth": rotations.DEFAULT_AZIMUTH if azimuth is None else azimuth,
                           **{n: params[n] for n in names}})
    rows = None if p is None else np.atleast_2d(np.asarray(p, dtype=float))
    if rows is not None:
        if rows.ndim != 2 or rows.shape[1] != len(model.param_names) or not np.all(np.isfinite(rows)):
            raise UserError(f"p must be finite parameter vectors of {len(model.param_names)} numbers "
                            f"({', '.join(model.param_names)}), one row per launch or one for all")
        cols["p"] = _column(np.arange(rows.shape[0]), "p")
        cols = launch_columns(cols)
    choice = resolve(integrator, tol, h)         # once: "auto" is dop853 or vern9 from here on
    integrator, entry, tol = choice.name, choice.entry, choice.tol
    refuse_on_full_model(integrator, "simulate_many")
    if entry.backend != "c":
        raise UserError(f"batched runs use the C integrators (dop853, vern9, auto, rk4, gauss4, ...), "
                        f"not {integrator!r}: run that one through simulate")
    k = cols["spin"].size
    sites: dict = {}        # per parameter vector: p, pvals, z_s, stiffness, box, t_end
    x0 = np.zeros((k, len(pt.states)))
    P, scale, hs, boxes = [], np.zeros_like(x0), np.zeros(k), np.zeros((k, 3))
    budget, z_s = np.zeros(k, np.int64), np.zeros(k)
    run_t_end = t_end
    groups: dict = {}       # launch position -> (its Launch, the indices of its launches)
    at = []                 # per launch: its site
    reason = np.full(k, None, dtype=object)       # why a launch's top cannot hover (else None)
    for i in range(k):
        row = None if rows is None else rows[int(cols["p"][i])]
        key = (None if row is None else row.tobytes(), *(float(cols[n][i]) for n in names))
        site = sites.get(key)
        if site is None:
            pk = model.with_params(dict(zip(names, key[1:])), row)
            pv = model.pvals(pk)
            try:
                zs = hover_height(model, pk)
            except UserError as exc:      # this launch's top cannot hover: its result says why
                site = sites[key] = str(exc)
            else:
                te = sim.default_t_end(model, part, pk) if t_end is None else t_end
                site = sites[key] = (pk, pv, zs, start.vertical_stiffness(model, pk, zs, pv),
                                     start.default_box(pt, zs, box), te)
        if isinstance(site, str):
            reason[i] = site
            at.append(None)
            continue
        if run_t_end is None:
            run_t_end = site[5]
        elif site[5] != run_t_end:
            raise UserError("the launches' parameters give different default run lengths: pass t_end")
        at.append(site)
        lkey = (key, float(cols["tilt"][i]), float(cols["offset"][i]), float(cols["azimuth"][i]))
        if lkey not in groups:
            groups[lkey] = (start.launch(pt, site[2], *lkey[1:3], site[0], lkey[3]), [])
        groups[lkey][1].append(i)
    for la, idx in groups.values():          # every spin of a launch position in one solve
        x0[idx] = start.launch_states(la, cols["spin"][idx])
    hovers = np.array([a is not None for a in at])
    run = np.flatnonzero(hovers)                           # the launches whose top hovers
    for i in run:
        pk, pv, zs, stiffness, bx, _ = at[i]
        spin_i = float(cols["spin"][i])
        if bx.excess(x0[i]) > 0:
            raise start.outside_box(float(cols["offset"][i]), bx.z_hi - zs, f"launch {i}: ",
                                    "pass a smaller offset or a larger box")
        T, what = start.fastest_period(spin_i, pv, stiffness)
        hi = (default_step(T) if h is None else h) if entry.fixed_step else None
        check_options(integrator, run_t_end, tol, hi, CHECK_N_OUT, T, what)
        P.append(pk)
        scale[i] = start.state_scales(pt, zs, spin_i, pv)
        hs[i] = hi or 0.0
        boxes[i] = (bx.z_lo, bx.z_hi, bx.r_max)
        budget[i] = default_budget(integrator, run_t_end, hi, T)
        z_s[i] = zs
    # a launch that cannot hover is not run: status NO_HOVER (the maps' word), t 0, its state NaN
    status = np.full(k, NO_HOVER, dtype=object)
    t_final, x_final = np.zeros(k), np.full((k, len(pt.states)), np.nan)
    rhs_evals, steps = np.zeros(k, np.int64), np.zeros(k, np.int64)
    z_s[~hovers] = np.nan
    lanes = False
    if run.size:
        res = drive_runs(model, pt, integrator, run_t_end, tol, x0[run],
                         np.array(P), scale[run], hs[run], boxes[run], budget[run])
        status[run], t_final[run], x_final[run] = res["status"], res["t_final"], res["x_final"]
        rhs_evals[run], steps[run], lanes = res["rhs_evals"], res["steps"], bool(res["lanes"])
    status = status.astype(str)
    untested = np.array([start.on_invariant_set(pt, float(t), float(o)) or stopped_early(st)
                         for t, o, st in zip(cols["tilt"], cols["offset"], status)])
    untested[~hovers] = False          # a top that cannot hover is a verdict: it does not
    return {"levitating": status == "completed", "untested": untested, "status": status,
            "reason": reason, "t_survived": t_final, "rhs_evals": rhs_evals, "steps": steps,
            "z_s": z_s, "final_state": x_final, "states": list(pt.states),
            "inputs": {c: v for c, v in cols.items() if c != "p"},
            "t_end": None if run_t_end is None else float(run_t_end),
            "integrator": integrator, "integrator_requested": choice.requested, "tol": tol,
            "step": hs if entry.fixed_step else None, "lanes": lanes,
            "wall_s": time.perf_counter() - t_wall}
