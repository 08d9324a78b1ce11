"""A chunk of a launch Monte Carlo (runtime/scan/launch_odds.py) through the C chunk driver
(runtime/scan/chunk_c.py): each launch's own top (its mass and strength as the hand's draws deviate
them, its temperature, the apparatus' draws), its hover height (runtime/scan/launch_hover.py,
thesis 3.3.2-3.3.3), its initial state through the Legendre map (runtime/simulate/start.py, thesis
eq. 2.3.8), its box and step budget; then every launch of the chunk in one C call. A production
run (runtime/design/kits.py) launches each kit at its own parameter vector: `base`."""
from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from levitron.runtime.scan.launch_inputs import apparatus_of, temperature_factor


def samples(plan) -> dict[str, np.ndarray]:
    """All n samples of every input of a launch_odds.Plan, drawn in ALL_INPUTS order from
    PCG64(seed): the same everywhere (the apparatus inputs come last, so a level scene's draws are
    those of before)."""
    rng = np.random.Generator(np.random.PCG64(plan.seed))
    return {name: d.sample(rng, plan.n) for name, d in plan.dists}


def run_chunk(plan, indices, base: Callable[[int], np.ndarray] | None = None) -> dict:
    """The launches `indices` of a launch_odds.Plan: {"points": [{i, t, status, z_s, m, mu}]};
    base(i): launch i's parameter vector before the hand's draws (None: the scene's)."""
    from levitron.runtime.integrate.budget import check_options, default_budget
    from levitron.runtime.scan.chunk_c import drive_runs
    from levitron.runtime.scan.launch_hover import hover_heights
    from levitron.runtime.scan.runners import model_for
    from levitron.runtime.simulate import start
    model = model_for(plan.scene, plan.overrides)
    S = samples(plan)
    pt = model.part("full")
    iy = pt.states.index("p_y")
    im, imu = model.param_names.index("m"), model.param_names.index("mu")
    method = plan.integrator
    rows, points, tops = [], [], []
    for i in indices:
        q = model.p if base is None else np.asarray(base(i), float)
        mu = q[imu] * (1 + S["strength"][i]) * temperature_factor(model, S["temperature"][i])
        m = q[im] * (1 + S["mass"][i])
        used = {"m": float(m), "mu": float(mu)}      # the launch's own top, as run (launches table)
        if not (m > 0 and math.isfinite(mu)):
            points.append({"i": int(i), "t": 0.0, "status": "invalid", "z_s": math.nan, **used})
            continue
        tops.append((i, m, used, model.with_params(
            {"m": m, "mu": mu, **{a.param: float(S[a.name][i]) for a in apparatus_of(model)}}, q)))
    heights = hover_heights(model, np.array([t[3] for t in tops])) if tops else []
    for (i, m, used, p), z_s in zip(tops, heights):
        if math.isnan(z_s):
            points.append({"i": int(i), "t": 0.0, "status": "cannot_hover", "z_s": math.nan, **used})
            continue
        spin = float(S["spin"][i])
        pv = model.pvals(p)
        la = start.launch(pt, z_s, float(S["tilt"][i]), float(S["offset"][i]), p, float(S["tilt_azimuth"][i]))
        x0 = start.launch_state(la, spin)
        x0[iy] += m * float(S["velocity"][i])
        T, what = start.fastest_period(spin, pv, start.vertical_stiffness(model, p, z_s, pv))
        check_options(method, plan.t_end, plan.tol, None, 2, T, what)
        box = start.default_box(pt, z_s)
        if box.excess(x0) > 0:
            points.append({"i": int(i), "t": 0.0, "status": "left_box", "z_s": float(z_s), **used})
            continue
        rows.append((int(i), x0, p, start.state_scales(pt, z_s, spin, pv),
                     (box.z_lo, box.z_hi, box.r_max), default_budget(method, plan.t_end, None, T),
                     {"z_s": float(z_s), **used}))
    if rows:
        x0, ps, scales, boxes, budgets = (np.array([r[k] for r in rows]) for k in range(1, 6))
        res = drive_runs(model, pt, method, plan.t_end, plan.tol, x0, ps, scales, np.zeros(len(rows)), boxes, budgets)
        points += [{"i": r[0], "t": float(res["t_final"][k]), "status": res["status"][k], **r[6]}
                   for k, r in enumerate(rows)]
    return {"points": points}
