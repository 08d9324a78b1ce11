"""No verdict without the physics to support it, for the launches (docs/contract.md `launch`).

In air the spin decays by omega_3(t) = omega_3(0) exp(-k t) (exact: runtime/physics/apparatus/friction.py).
A launch still up at the end of its run whose spin has by then decayed below the lower critical
spin of its own top (thesis 3.3.9-3.3.16 at its own mass, magnet and hover height) is past its
stable window: the adiabatic prediction puts its fall before the run's end, and the run ended
before the fall showed, so it says nothing of whether the top stays up. Its status becomes
PAST_WINDOW (runtime/integrate/verdict.py past_window: the test simulate and the stability map
make too) and the odds leave it out, as they leave out a run that stopped early.

The lower critical spin depends on the launch's own top (its mass, strength and temperature): it is
computed per launch by the exact route (the discriminant, thesis 3.3.9-3.3.16, at the launch's own
hover height; about 0.4 ms), for the launches up at the end whose final spin lies below
WINDOW_MARGIN times the lower critical spin of the scene's top. The spreads of a hand move it by
about 1 % (thesis_air: 0.5-1.6 % at 3 sd of mass or strength) except near the band's edges, where
the window closes and a launch's own edge may lie farther: there a launch whose spin ends more than
WINDOW_MARGIN above the scene's edge and yet below its own keeps its verdict.
"""
from __future__ import annotations

import math

import numpy as np

from levitron.runtime.integrate.verdict import PAST_WINDOW, UP, past_window, stopped_early
from levitron.runtime.physics.apparatus.friction import crossing_time, has_friction
from levitron.runtime.words import si

WINDOW_MARGIN = 1.05


class WindowJudge:
    """Marks the launches of one Monte Carlo past their window (module docstring). interval: the
    scene's top's spin interval (launch_odds.prepare's), None where it has none; base(i): launch i's
    parameter vector where it has its own plate (a production run's kit, runtime/design/kits.py)."""

    def __init__(self, model, interval, base=None):
        self.model, self.base = model, base
        self.k = model.pvals().get("k_spin", 0.0) if has_friction(model) else 0.0
        self.near = WINDOW_MARGIN * interval[0] if interval else math.inf

    def mark(self, spins: np.ndarray, t_end: float, results: list[dict]) -> dict:
        """Mark the launches past their window at t_end, the success time: their point's status
        becomes PAST_WINDOW, in place. spins: the launches' spins by launch index; results: the
        chunks'. Returns the answer's `past_window`: {"launches": how many, "reason": the first
        one's or None}."""
        decay = math.exp(-self.k * t_end) if self.k > 0 else 1.0
        up = [p for r in results for p in r["points"]
              if p["status"] == UP and "m" in p and abs(spins[p["i"]]) * decay < self.near]
        n, reason = 0, None
        for p in up if self.k > 0 else ():
            spin = spins[p["i"]]
            lower = _lower(self.model, p["m"], p["mu"], p["z_s"], None if self.base is None else self.base(p["i"]))
            why = past_window(p["status"], t_end, lower, abs(spin) * decay,
                              crossing_time(spin, lower, self.k) if lower else None)
            if why:
                p["status"], n = PAST_WINDOW, n + 1
                reason = reason or (f"launch {p['i']} (spin {si(abs(spin), 'rad/s')}, judged at the success "
                                    f"time): {why}")
        return {"launches": n, "reason": reason}


def _lower(model, m: float, mu: float, z_s: float, base=None) -> float | None:
    """The lower critical spin of the top of mass m and moment mu hovering at z_s over the model's
    plate (base: the parameter vector of its own plate, if not the scene's), by the exact route
    (thesis 3.3.9-3.3.16); None where it has no bounded interval."""
    from levitron.runtime.physics.equilibrium.finder import model_onaxis
    from levitron.runtime.physics.routes.ray_algebra import RayCoefficients, spin_intervals_discriminant
    P = model.pvals()
    ph = np.asarray(model_onaxis(model, base)(z_s), float)       # the plate's Phi_k: not the top's
    bounded = [iv for iv in spin_intervals_discriminant(RayCoefficients.from_physics(
        ph[1], ph[2], ph[3], m, P["A"], P["C"], mu)) if iv[1] < math.inf and iv[0] > 0]
    return bounded[0][0] if bounded else None


def no_verdicts(status: list[str], up: np.ndarray) -> np.ndarray:
    """The launches without a verdict, left out of the odds: a run that stopped early (step budget,
    ...) short of the success time (up False), or one up past its window (PAST_WINDOW)."""
    return np.array([s == PAST_WINDOW or (not u and stopped_early(s) and s != "cannot_hover")
                     for s, u in zip(status, up)], bool)


def none_decided(n: int, status: list[str]) -> str:
    """The refusal when no launch has a verdict, with what would give them one."""
    how, hint = (("ended", "run longer («t_end») or launch faster («spin»): the spin decays past the window "
                  "before the run ends") if PAST_WINDOW in status else
                 ("stopped early", "try a looser «tol» or a shorter «t_end»"))
    return f"every one of the {n} runs {how} without a verdict ({', '.join(sorted(set(status)))}): no odds; {hint}"
