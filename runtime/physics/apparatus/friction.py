"""A flight in air: how long the top floats, the spin at which it falls, and the adiabatic prediction.

With air friction (derive/friction.py: Rayleigh dissipation, rates k = 1/tau of the scene's decay
times) the spin decays exactly as omega_3(t) = omega_3(0) exp(-k_spin t): the magnetic torque
mu n x B is perpendicular to the axis. The top floats while its spin lies inside the spin interval
of linear stability at the hover height, sigma_lo < omega_3 < sigma_hi (thesis 3.3.22-3.3.23, the
ideal top's: friction rates set to 0), and the adiabatic picture predicts that it falls when the
decaying spin crosses sigma_lo, at

    t_cross = tau ln(omega_0 / sigma_lo),

and that a launch above sigma_hi floats if it survives until the spin has decayed below sigma_hi,
at t_enter = tau ln(omega_0 / sigma_hi). The simulated flight (the full nonlinear model) is
reported beside these, with two checks of the run itself: the energy balance
E(t) - E(0) + W(t) = 0, W(t) = integral of 2F dt (2F the generated `full_dissipation`) integrated
inside the run as one more state by the integrator's own stages and error control
(runtime/integrate/run.py's `quadrature`), so that its residual measures the integration, not the
output sampling; and L.n against its exact exponential decay.
"""
from __future__ import annotations

import math

import numpy as np

from levitron.scene.keys import FRICTION_KEYS

RATES = tuple(FRICTION_KEYS.values())   # k_spin, k_tilt, k_trans: parameter names of a model in air


def has_friction(model) -> bool:
    """The model was derived with air friction (its parameters include the rates)."""
    return all(r in model.param_names for r in RATES)


def without_friction(model, p: np.ndarray) -> np.ndarray:
    """p with the friction rates set to 0: the ideal top, whose relative equilibrium the linear
    analysis needs (thesis 3.3; with friction there is none, the spin decays)."""
    if not has_friction(model):
        return p
    return model.with_params({r: 0.0 for r in RATES}, p)


# the decay times by what decays: the scene's keys [top] spin_decay_time, ... without "_decay_time"
DECAYS = {key.removesuffix("_decay_time"): rate for key, rate in FRICTION_KEYS.items()}


def decay_times(pvals: dict) -> dict:
    """{what decays (spin, tilt, translation): its decay time tau = 1/k in the scene's time unit (s),
    or None where it has no friction}: the scene's [top] *_decay_time as the model resolved them."""
    return {name: (1.0 / pvals[k] if pvals.get(k, 0.0) > 0 else None) for name, k in DECAYS.items()}


def friction_rates(pvals: dict) -> dict:
    """{rate name (k_spin, k_tilt, k_trans): the rate k = 1/tau in 1/(the scene's time unit), 0 for
    no friction}: the model's parameters (derive/friction.py)."""
    return {k: float(pvals.get(k, 0.0)) for k in RATES}


def crossing_time(spin: float, limit: float | None, k: float) -> float | None:
    """tau ln(|spin| / limit): when exp(-k t) |spin| reaches `limit` (None if it never does)."""
    if limit is None or not limit > 0 or not k > 0 or abs(spin) <= limit:
        return 0.0 if limit is not None and k > 0 and abs(spin) <= limit else None
    return math.log(abs(spin) / limit) / k


def energy_scale(pv: dict, z_s: float, spin: float, H0: float) -> float:
    """The size of a run's energy terms, |H(0)| or m g z_s + C omega^2 / 2 if larger: what the
    energy drift of a run (runtime/simulate/run.py) and the energy balance are relative to."""
    return max(abs(H0), pv["m"] * abs(pv["g"]) * z_s + 0.5 * pv["C"] * spin ** 2)


def energy_balance(H, work, scale: float = 0.0) -> float | None:
    """max_t |E(t) - E(0) + W(t)| / max(max |E - E(0)|, scale) over the samples: the energy balance
    of a dissipative run, W the work of friction integrated inside the run (module docstring),
    relative to the energy lost or, where little is lost (a decay time of 1e12 s), to the energy's
    own terms (`energy_scale`), so that a run equal to the friction-free one shows that run's
    drift, not a ratio of two round-offs. Each sample's W and E come from the same state of the
    integration, so the residual does not depend on how many samples there are."""
    H, work = np.asarray(H, float), np.asarray(work, float)
    if len(H) < 2 or work.shape != H.shape or not np.all(np.isfinite(H)) or not np.all(np.isfinite(work)):
        return None
    scale = max(float(np.abs(H - H[0]).max()), scale, 1e-300)
    return float(np.abs(H - H[0] + work).max() / scale)


def flight(model, pt, p, res, x0, spin: float, z_s: float, t_end: float, interval, spin_of) -> dict:
    """The `flight` block of simulate's answer (module docstring). interval: the ideal top's linear
    spin interval at z_s, (sigma_lo, sigma_hi) or None; spin_of(X) -> omega_3 along the samples."""
    pv = model.pvals(p)
    k = pv["k_spin"]
    lo, hi = (interval if interval is not None else (None, None))
    fell = res.status == "left_box"
    w = spin_of(res.X)
    t_cross = crossing_time(spin, lo, k) if lo is not None else None
    t_enter = crossing_time(spin, hi, k) if hi is not None and abs(spin) > hi else None
    H = res.energy if res.energy is not None else model.rows("full_energy", res.X, p)[:, 0]
    ln = np.abs(w) * pv["C"]
    ln_exact = abs(spin) * pv["C"] * np.exp(-k * np.asarray(res.t))
    return {
        "decay_times": decay_times(pv),
        "friction_rates": friction_rates(pv),
        "flight_time": res.t_final if fell else None,
        "fell": fell,
        "fall_spin": float(abs(w[-1])) if fell else None,
        "spin_final": float(abs(w[-1])),
        "spin_interval": list(interval) if interval is not None else None,
        "t_cross": t_cross,
        "t_enter": t_enter,
        "launched_above": bool(hi is not None and abs(spin) > hi),
        "fell_before_interval": bool(fell and t_enter is not None and res.t_final < t_enter),
        "after_cross": (res.t_final - t_cross) if fell and t_cross is not None else None,
        "energy_balance": (energy_balance(H, res.work, energy_scale(pv, z_s, spin, float(H[0])))
                           if res.work is not None else None),
        "spin_decay_deviation": float(np.abs(ln - ln_exact).max() / (abs(spin) * pv["C"]))
        if spin else None,
        "t_end": t_end,
    }
