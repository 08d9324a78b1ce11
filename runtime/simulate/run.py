"""One trajectory of the top from its stable hover height (docs/contract.md `simulate`; thesis 3.1-3.3).

The initial state: the centre of mass at (offset, 0, z_s), where z_s is the vertically stable root
of m g + mu Phi_2(z) = 0 (thesis eqs. 3.3.2-3.3.3, from levitron.runtime.physics.equilibrium.finder); the symmetry axis
n tilted by `tilt` rad towards the azimuth `azimuth` (rad from +x towards +y; default pi/2, i.e.
towards +y), n = (sin tilt cos az, sin tilt sin az, cos tilt) (Tait-Bryan angles of thesis 3.2.2:
vartheta = asin(sin tilt cos az), phi = atan2(sin tilt sin az, cos tilt); z-x-z Euler angles of
2.1.9: phi = az + pi/2, theta = tilt); at rest except
for the spin: angular velocity omega = spin * n, i.e. a right-handed spin of `spin` rad/s about n
(zeta_dot = -spin in Tait-Bryan angles, where omega_3 = -(zeta_dot + phi_dot sin vartheta),
thesis 3.2.9; psi_dot = +spin in z-x-z angles, 2.1.10). The momenta are built from these
velocities through the model's own Legendre map: the coordinate rows of the generated rhs are
dq/dt = M(q)^-1 p (thesis eq. 2.3.8), linear in p, so p = M(q) qdot is solved from that map.
With Tait-Bryan angles this gives p_zeta = C (zeta_dot + phi_dot sin vartheta) = -C omega_3.

The default launch is perturbed: a launch with tilt 0 and offset 0 lies exactly on the invariant
set I (thesis 3.2.1), where the ideal top stays at any spin, so it tests no stability. Without a
given tilt the axis starts DEFAULT_TILT rad from the vertical (Gans et al. perturb by 0.001-0.005
rad); a launch given exactly on I is run but answers `levitating: null` with the reason.

With air friction (a scene with decay times, derive/friction.py) the run goes on until the top
falls or t_end (default FRICTION_T_END_TAUS spin decay times), and the answer carries a `flight`
block (runtime/physics/apparatus/friction.py): the flight time, the spin at which the top fell and the adiabatic
prediction tau ln(omega_0 / sigma_lo).

The run stops when the top leaves a box that scales with the hover height (default half-width
z_s / 2 in z and radially; scenes may be dimensionless, so never a fixed length).

Conserved quantities (Noether): the energy H (thesis 2.3.9 / 3.2.11), p_zeta (zeta is cyclic) and
the z-component of the total angular momentum L_z = x p_y - y p_x + sum_a p_a d a/d alpha, where
d a/d alpha is the change of the angles under a rotation of the whole top by alpha about the lab z
axis (R_bs -> Q_z(alpha) R_bs), computed here from the rotation matrices of derive/kinematics.py.
"""
from __future__ import annotations

import math

import numpy as np

from levitron.runtime.physics.equilibrium.finder import hover_height
from levitron.runtime.errors import UserError
from levitron.runtime.words import si
from levitron.runtime.ui.validate import count, real, run_length, tolerance
from levitron.runtime.integrate.budget import MAX_N_OUT
from levitron.runtime.integrate.run import Box, Result, integrate
from levitron.runtime.integrate.methods import AUTO, DEFAULT, Choice, auto_note, default_step, resolve
from levitron.runtime.integrate.verdict import no_verdict_reason, past_window, verdict

from levitron.runtime.physics.apparatus import friction as flight
from levitron.runtime.physics.stability.analysis import onaxis_refusal, stability_of
from levitron.runtime.simulate.simulation import Simulation
from levitron.runtime.simulate.invariants import Samples, deviations, spin_rate
from levitron.runtime.simulate.rotations import DEFAULT_AZIMUTH, coordinates_of
from levitron.runtime.simulate.start import (DEFAULT_TILT, PERIODS, default_box, initial_state, on_invariant_set,
                                             outside_box, slow_period, state_scales, tilted_start, time_scale,
                                             untested_reason)

FRICTION_T_END_TAUS = 5.0        # default run length with friction: 5 tau, the spin falls by e^5


def default_t_end(model, part: str, p) -> float:
    """FRICTION_T_END_TAUS spin decay times for a full model in air; else PERIODS slow periods of
    the top at its hover height (slow_period, thesis 3.3.3/3.3.5; the scan's default run length),
    at the geometric mean of its linear spin interval (the bounce alone where it has none, or for
    the reduced model). Never a fixed time: one time unit is half a bounce of a large plate's top
    and many of a small one's, and a short run calls a falling top levitating."""
    pv = model.pvals(p)
    if part == "full" and flight.has_friction(model) and pv["k_spin"] > 0:
        return FRICTION_T_END_TAUS / pv["k_spin"]
    z_s = hover_height(model, p)
    iv = (stability_of(model, p=p, z_s=z_s, eigen=False).spin_interval
          if part == "full" and onaxis_refusal(model, p) is None else None)
    return PERIODS * slow_period(model, pv["m"], z_s, None if iv is None else math.sqrt(iv[0] * iv[1]), p)


def simulate(model, spin: float, tilt: float | None = None, offset: float = 0.0,
             t_end: float | None = None,
             integrator: str = DEFAULT, tol: float | None = 1e-9, box: float | None = None,
             part: str = "full", h: float | None = None,
             n_out: int = 2000, params: dict | None = None,
             azimuth: float = DEFAULT_AZIMUTH) -> Simulation:
    """Run one trajectory: the answer (runtime/simulate/simulation.py) holds docs/contract.md's
    `simulate` keys (its as_json()) and the samples; plot(path), save(path), animate(path) draw,
    write and animate them.

    box: the half-width of the box (m), default z_s / 2. params: parameter values overriding the
    scene's for this run (names of manifest.json `parameters`). integrator: a name of
    runtime/integrate/methods.py or "auto" (resolved from tol: the answer's `integrator` is the
    method that ran, `integrator_requested` the name asked for, `integrator_choice` auto's reason).
    tilt None: DEFAULT_TILT for the full model, 0 for the reduced one; t_end None: default_t_end."""
    spin = real(spin, "«spin»", unit="rad/s")
    tilt = None if tilt is None else real(tilt, "«tilt»", max_abs=math.pi, unit="rad")
    offset = real(offset, "«offset»", unit="m")
    azimuth = real(azimuth, "«tilt_azimuth»", unit="rad")
    t_end = None if t_end is None else run_length(t_end)
    n_out = count(n_out, "«n_out»", high=MAX_N_OUT)
    tol = None if tol is None else tolerance(tol)
    box = None if box is None else real(box, "«box»", positive=True, unit="m")
    h = None if h is None else real(h, "«step»", positive=True, unit="s")
    if part == "full" and "full" not in model.parts and "reduced" in model.parts:
        raise UserError(f"scene '{model.scene.name}' has no full model (model.needs = {model.scene.needs}): "
                        "pass «part=reduced» for the vertical motion on the invariant set (no tilt, so "
                        "no stability verdict), or add \"full\" to model.needs for the whole top")
    pt = model.part(part)
    p = model.with_params(params or {})
    pvals = model.pvals(p)
    tilt_default = tilt is None
    if tilt is None:
        tilt = DEFAULT_TILT if coordinates_of(pt) is not None else 0.0
    if t_end is None:
        t_end = default_t_end(model, part, p)
    choice = resolve(integrator, tol, h)        # once: "auto" is dop853 or vern9 from here on
    z_s = hover_height(model, p)
    T, what = time_scale(model, p, z_s, spin, pvals)
    bx = default_box(pt, z_s, box)
    if choice.fixed_step and choice.h is None:
        choice = choice.with_step(default_step(T))
    x0 = initial_state(pt, z_s, spin, tilt, offset, p, azimuth)
    tilted_note = None
    if part == "full" and "base_tilt" in model.param_names:      # plate.tilt: start off the axis
        x0, tilted_note = tilted_start(model, pt, z_s, spin, x0, p)
    if bx.excess(x0) > 0:
        z0 = float(x0[pt.states.index("z")]) if "z" in pt.states else z_s
        if not bx.z_lo <= z0 <= bx.z_hi:            # not the offset: the top's own height (moment_offset)
            raise UserError(f"the top's centre of mass starts at z = {si(z0, 'm')}, outside the box's heights "
                            f"{si(bx.z_lo, 'm')} to {si(bx.z_hi, 'm')} about the hover height (top.moment_offset "
                            f"= {si(pvals.get('moment_offset', 0.0), 'm')}); give a top.moment_offset nearer 0 or "
                            "a larger «box»")
        raise outside_box(offset, bx.z_hi - z_s)
    scale = state_scales(pt, z_s, spin, pvals)
    air = part == "full" and flight.has_friction(model)
    # in air the work of friction is integrated inside the run (the energy balance's W)
    work = (("dissipation", flight.energy_scale(pvals, z_s, spin, pt.energy(x0, p)))
            if air else None)
    res = integrate(pt, x0, t_end, method=choice.name, tol=choice.tol, h=choice.h, p=p, box=bx,
                    n_out=n_out, scale=scale, monitor_energy=choice.entry.monitors_energy, time_scale=T,
                    time_scale_what=what, quadrature=work)
    fl = None
    if air:
        # the ideal top's interval at z_s (rates set to 0); none where the plate's symmetry refuses it
        iv = stability_of(model, p=p, z_s=z_s).spin_interval if onaxis_refusal(model, p) is None else None
        fl = flight.flight(model, pt, p, res, x0, spin, z_s, t_end, iv,
                           lambda X: spin_rate(pt, X, pvals["C"], p))
    ps = Samples.of(pt, res, x0, p)
    out = summarize(pt, res, x0, p, z_s, bx, spin, tilt, offset, t_end, choice, fl, ps)
    out["tilt_azimuth"] = azimuth
    if tilted_note is not None:
        out["note"] = tilted_note
    out["tilt_default"] = tilt_default and coordinates_of(pt) is not None
    if on_invariant_set(pt, tilt, offset):
        out["levitating"], out["untested"] = None, untested_reason(pt)
    elif verdict(res.status) is None:        # the step budget, ...: neither up nor down
        out["levitating"], out["untested"] = None, no_verdict_reason(res.status, res.message)
    elif fl is not None and (past := past_window(res.status, t_end, iv[0] if iv else None,
                                                 fl["spin_final"], fl["t_cross"])):
        out["levitating"], out["untested"] = None, past   # up at the end, its spin below the window
    out["integrator_requested"] = choice.requested
    if choice.requested == AUTO:
        out["integrator_choice"] = auto_note(choice.tol)
    names, table = trajectory_table(pt, res, p, ps)
    return Simulation.of(out, {n: table[:, i] for i, n in enumerate(names)}, model, p)


def trajectory_table(pt, res: Result, p, ps: Samples | None = None) -> tuple[list[str], np.ndarray]:
    """The samples of a run as columns (runtime/simulate/trajectory_file.py): t, the states, energy, L_z,
    L_n, tilt and the spin omega_3 = L_n / C, each derived column from a generated function in one
    C call (ps: Samples.of, if the summary already computed them)."""
    X = np.atleast_2d(res.X)
    ps = Samples.of(pt, res, X[0], p) if ps is None else ps
    C = dict(zip(pt.model.param_names, p))["C"]
    cols = [np.asarray(res.t, float)[:, None], X, ps.energy[:, None], ps.invariants[1:-1],
            ps.tilt[:, None], ps.invariants[1:-1, 1:2] / C]
    return ["t", *pt.states, "energy", "L_z", "L_n", "tilt", "spin"], np.hstack(cols)


def summarize(pt, res: Result, x0, p, z_s, bx: Box, spin, tilt, offset, t_end, choice: Choice,
              fl: dict | None = None, ps: Samples | None = None) -> dict:
    """simulate's keys (docs/contract.md); choice: the integrator as resolved (its method, tol, h).
    fl: the flight block of a run in air
    (runtime/physics/apparatus/friction.py); there the energy drift is the residual of the energy balance
    and L.n is compared with its exponential decay. ps: the run's Samples (Samples.of), if computed already."""
    s = list(pt.states)
    X = res.X
    ps = Samples.of(pt, res, x0, p) if ps is None else ps
    H = ps.energy
    H0 = pt.energy(x0, p)
    names = pt.model.param_names if hasattr(pt, "model") else []
    pv = dict(zip(names, p))
    terms = flight.energy_scale(pv, z_s, spin, H0) if names else abs(H0)
    drift = np.abs(H - H0) / terms
    z = X[:, s.index("z")]
    r = np.hypot(X[:, s.index("x")], X[:, s.index("y")]) if "x" in s else np.zeros(len(X))
    exc = np.sqrt(r ** 2 + (z - z_s) ** 2)
    tilt_t = ps.tilt
    lz0, lz1 = float(ps.invariants[0, 0]), float(ps.invariants[-1, 0])
    pz = ([float(x0[s.index("p_zeta")]), float(res.x_final[s.index("p_zeta")])]
          if "p_zeta" in s else None)
    out = {
        "levitating": res.status == "completed",
        "t_survived": res.t_final,
        "max_excursion": float(exc.max()),
        "energy_drift": float(drift.max()),
        "rhs_evals": res.rhs_evals,
        "wall_s": res.wall_s,
        "final_state": {k: float(v) for k, v in zip(s, res.x_final)},
        "status": res.status,
        "message": res.message,
        "z_s": z_s,
        "spin": {"rad_s": spin, "hz": spin / (2 * math.pi), "rpm": spin * 60 / (2 * math.pi)},
        "tilt": tilt, "offset": offset, "t_end": t_end,
        "integrator": choice.name, "backend": res.backend, "tol": choice.tol, "step": choice.h,
        "box": {"z": [bx.z_lo, bx.z_hi], "r_max": bx.r_max if math.isfinite(bx.r_max) else None},
        "max_height_deviation": float(np.abs(z - z_s).max()),
        "max_radial_offset": float(r.max()),
        "max_tilt": float(tilt_t.max()),
        "energy_drift_final": float((H[-1] - H0) / terms) if len(H) else None,
        "energy_scale": terms,
        "conserved": {
            "energy": [float(H0), float(pt.energy(res.x_final, p))],
            "L_z": [lz0, lz1],
            "p_zeta": pz,
        },
        "conserved_max_deviation": deviations(pt, X, x0, p, pv, spin, float(drift.max()),
                                              ps.invariants[:-1]),
        "part": pt.name if hasattr(pt, "name") else None,
        "coordinates": coordinates_of(pt),
    }
    if fl is not None:
        out["flight"] = fl
        out["fall_spin"], out["t_cross"] = fl["fall_spin"], fl["t_cross"]
        out["energy_drift"] = fl["energy_balance"]
        out["energy_drift_final"] = None
        out["conserved_max_deviation"] = {"energy_balance": fl["energy_balance"], "L_z": None,
                                          "L_n_decay": fl["spin_decay_deviation"]}
    return out


