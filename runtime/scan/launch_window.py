"""No verdict without the physics to support it, for the launches (docs/contract.md `launch`).

In air the spin decays by omega_3(t) = omega_3(0) exp(-k t) (exact: runtime/physics/apparatus/friction.py).
A launch still up at the end of its run whose spin has by then decayed below the lower critical
spin of its own top (thesis 3.3.9-3.3.16 at its own mass, magnet and hover height) is past its
stable window: the adiabatic prediction puts its fall before the run's end, and the run ended
before the fall showed, so it says nothing of whether the top stays up. Its status becomes
PAST_WINDOW (runtime/integrate/verdict.py past_window: the test simulate and the stability map
make too) and the odds leave it out, as they leave out a run that stopped early.

The lower critical spin depends on the launch's own top (its mass, strength and temperature), so
it is computed per launch by the exact route (discriminant, thesis 3.3.9-3.3.16), a few ms each;
only for the launches up at the end whose final spin lies below WINDOW_MARGIN times the largest
lower critical spin at the corners of the launches' (mass, moment) box, the others being clear of
their window's edge by far more than the edge moves across the box.
"""
from __future__ import annotations

import math

import numpy as np

from levitron.runtime.integrate.verdict import PAST_WINDOW, UP, past_window, stopped_early
from levitron.runtime.physics.apparatus.friction import crossing_time, has_friction
from levitron.runtime.words import si

WINDOW_MARGIN = 1.5


class WindowJudge:
    """Marks the launches of one model past their window (module docstring); keeps the lower
    critical spins at the corners of the launches' (mass, moment) box between calls (a design's
    batches of one Monte Carlo share them)."""

    def __init__(self, model):
        self.model = model
        self.k = model.pvals().get("k_spin", 0.0) if has_friction(model) else 0.0
        self.box, self.reach = None, None

    def _reach(self, up: list[dict]) -> float | None:
        (m0, m1), (u0, u1) = _span(up, "m"), _span(up, "mu")
        b = self.box
        if b is None or not (b[0] <= m0 and m1 <= b[1] and b[2] <= u0 and u1 <= b[3]):
            corners = [_lower(self.model, m, mu, None) for m in (m0, m1) for mu in (u0, u1)]
            self.box = (m0, m1, u0, u1)
            self.reach = max((c for c in corners if c is not None), default=None)
        return self.reach

    def mark(self, spins: np.ndarray, t_end: float, results: list[dict]) -> dict:
        """Mark the launches past their window at t_end, the success time: their point's status
        becomes PAST_WINDOW, in place. spins: the launches' spins by launch index; results: the
        chunks'. Returns the answer's `past_window`: {"launches": how many, "reason": the first
        one's or None}."""
        up = [p for r in results for p in r["points"] if p["status"] == UP and "m" in p]
        if not (self.k > 0 and up):
            return {"launches": 0, "reason": None}
        decay = math.exp(-self.k * t_end)
        reach = self._reach(up)
        n, reason = 0, None
        for p in up:
            spin = spins[p["i"]]
            end = abs(spin) * decay
            if reach is not None and end >= WINDOW_MARGIN * reach:
                continue
            lower = _lower(self.model, p["m"], p["mu"], p.get("z_s"))
            why = past_window(p["status"], t_end, lower, end, crossing_time(spin, lower, self.k) if lower else None)
            if why:
                p["status"], n = PAST_WINDOW, n + 1
                reason = reason or (f"launch {p['i']} (spin {si(abs(spin), 'rad/s')}, judged at the success "
                                    f"time): {why}")
        return {"launches": n, "reason": reason}


def _span(points: list[dict], key: str) -> tuple[float, float]:
    values = [p[key] for p in points]
    return min(values), max(values)


def _lower(model, m: float, mu: float, z_s: float | None) -> float | None:
    """The lower critical spin of the top of mass m and moment mu over the model's plate, by the
    exact route (thesis 3.3.9-3.3.16); None where it has no interval or cannot hover."""
    from levitron.runtime.errors import UserError
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.physics.stability.analysis import analyse
    p = model.with_params({"m": m, "mu": mu})
    P = model.pvals(p)
    try:
        z = eqm.hover_height(model, p) if z_s is None or not math.isfinite(z_s) else z_s
        res = analyse(eqm.model_onaxis(model, p), m, P["g"], P["A"], P["C"], mu, eqm.scale_of(model, p),
                      z_s=z, eigen=False)
    except UserError:
        return None
    return res.spin_interval[0] if res.spin_interval else None


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
