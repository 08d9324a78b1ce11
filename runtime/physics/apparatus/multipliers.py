"""Linear stability of the periodic steady motion of a top whose moment is off its axis: route "Floquet".

With a moment tilt b (top.moment_tilt) the steady motion is a periodic orbit of period
T = 2 pi / sigma (runtime/physics/apparatus/periodic_orbit.py). Its linear stability is that of the
monodromy matrix M = dx(T)/dx0 (Floquet theory): the orbit is linearly stable exactly where every
multiplier that the orbit does not force to 1 lies on the unit circle.

Two multipliers are 1 on every periodic orbit of an autonomous Hamiltonian system: the flow
direction f = full_rhs(x0) (M f = f) and the energy (grad H^T M = grad H^T, H the generated
full_energy). They are reduced exactly, not picked by their value: M maps W = {v : grad H . v = 0}
into itself and f lies in W, so M induces a map on W / span(f), the 10x10 matrix
Q^T M Q with Q an orthonormal basis of W orthogonal to f (in the scaled states of the shooting).
Its eigenvalues are the nontrivial multipliers; the orbit is called stable where all have
| |mu| - 1 | <= MULT_TOL. (Over a level base the orbit is a rigid rotation about z: L_z's gradient
is then parallel to grad H there, so no further multiplier is trivial.)

At b = 0 the orbit is the aligned top's relative equilibrium and M = exp(T J) on the reduced
Jacobian J of the eigen route (runtime/physics/apparatus/tilted_stability.py): the multipliers are
exp(T lambda) and the window is the eigen route's (tests/runtime/physics/apparatus/test_floquet.py). With b != 0 the
forcing
at the spin couples modes whose multipliers meet on the unit circle at b = 0 (where
(omega_j -+ omega_k) / sigma is an integer: a parametric resonance); a narrow tongue of
instability may open there, of width growing with b. So, as for the base tilt's gaps, those meeting
points are found on the aligned system (`meetings`, cheap: eigenvalues only) and probed beside a
log grid of spins around the aligned window (inside it only: outside, the aligned top is unstable
already). A spin where the orbit cannot be continued from the aligned top counts as unstable: on
the peer's loop trap at b = 0.02 the window's lower end is such a spin, where the period 2 pi / sigma
has an extremum along the family of orbits (Newton's Jacobian turns singular while no multiplier
leaves the circle), and a simulated top 0.1 % below it is lost (tests/runtime/physics/apparatus/test_floquet.py).
Every change of the verdict is bisected to SPIN_RTOL.
No sympy here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.physics.apparatus.periodic_orbit import (NoOrbit, PeriodicOrbit, Shooting, continued_orbit,
                                                     state_scales)
from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium, TiltedTop

MULT_TOL = 1e-6          # | |mu| - 1 | on the unit circle, beside CVODES' 1e-12 (|mu| - 1 ~ 1e-11 measured)
SPIN_RTOL = 1e-7         # relative width at which a window end's bisection stops (each end 0.6 s per digit)
GRID = 16                # log-spaced spins over [SPAN[0] lo, SPAN[1] hi] of the aligned window
SPAN = (0.75, 1.5)
MEET_GRID = 400          # spins on the aligned system's grid where multipliers' meetings are looked for
MAX_MEETINGS = 30        # meetings probed at most (the nearest to the aligned window's ends first)
NEAR = 0.15              # an orbit known within this (log) of a spin is the guess there
CLOSE = 1e-3             # and within this, where Newton from it fails there is no orbit on the branch


@dataclass(frozen=True)
class FloquetCheck:
    """The nontrivial multipliers of one orbit and the verdict."""

    sigma: float
    multipliers: np.ndarray
    deviation: float             # max | |mu| - 1 |
    trivial_residual: float      # |M f - f| / |f| in scaled states: how well the flow direction is kept

    @property
    def stable(self) -> bool:
        return self.deviation <= MULT_TOL

    @property
    def growth_rate(self) -> float:
        """log max |mu| / T: the e-folding rate of the fastest growing perturbation (1/s)."""
        return float(math.log(max(np.abs(self.multipliers).max(), 1.0)) * self.sigma / (2 * math.pi))


def nontrivial_multipliers(orbit: PeriodicOrbit, flow_direction: np.ndarray,
                           energy_gradient: np.ndarray) -> tuple[np.ndarray, float]:
    """The eigenvalues of M on W / span(f) (module docstring) and |M f - f| / |f|, all in the
    orbit's scaled states y = x / s."""
    s = orbit.scales
    M = orbit.monodromy * s[None, :] / s[:, None]
    f, g = flow_direction / s, energy_gradient * s
    U = np.linalg.qr(g[:, None], mode="complete")[0][:, 1:]         # W = g-perp
    c = U.T @ f
    V = np.linalg.qr(c[:, None], mode="complete")[0][:, 1:]         # f-perp inside W
    Q = U @ V
    mu = np.linalg.eigvals(Q.T @ M @ Q)
    return mu, float(np.linalg.norm(M @ f - f) / np.linalg.norm(f))


class FloquetTop:
    """The periodic orbits of one model at parameters p (moment tilt and base tilt from p) along the
    spin, each found from the nearest one found before, else continued in the moment tilt from the
    aligned top's relative equilibrium (runtime/physics/apparatus/tilted_equilibrium.py)."""

    def __init__(self, model, p: np.ndarray, z_magnet: float, top: TiltedTop | None = None):
        self.model, self.p = model, np.asarray(p, float)
        P = model.pvals(self.p)
        self.b, self.tilt = P["moment_tilt"], P["base_tilt"]
        self.P = P
        self.aligned = model.with_params({"moment_tilt": 0.0}, self.p)
        self.top = TiltedTop(model, self.aligned, z_magnet) if top is None else top
        self.shoot = Shooting(model, self.p)
        self.states = self.shoot.states
        self._known: dict[float, PeriodicOrbit] = {}

    def with_tilt(self, b: float) -> np.ndarray:
        return self.model.with_params({"moment_tilt": b}, self.p)

    def scales(self, sigma: float) -> np.ndarray:
        return state_scales(self.states, self.top.z_level, self.P["m"], self.P["g"], self.P["C"], sigma)

    def orbit(self, sigma: float) -> PeriodicOrbit:
        """The periodic orbit at spin sigma (a NoOrbit, or the tilted equilibrium's NoEquilibrium,
        where there is none on the branch from the aligned top)."""
        if sigma in self._known:
            return self._known[sigma]
        s = self.scales(sigma)
        got = None
        if self._known:
            near = min(self._known, key=lambda k: abs(math.log(k / sigma)))
            if abs(math.log(near / sigma)) < NEAR:
                got = self.shoot.solve(sigma, self.rescaled(self._known[near], sigma), s)
                # (a bisection's step toward a window's end: within CLOSE the orbit moves little
                # but at a fold, and past one there is none; the aligned top's continuation is
                # then the dearest way, 3 s, to the same answer)
                if got is None and abs(math.log(near / sigma)) < CLOSE:
                    raise NoOrbit(self.b, sigma, self.b, self.shoot.rate_unit, from_spin=near)
        if got is None:
            eq = self.top.hamilton(self.tilt, sigma)
            got = continued_orbit(self.shoot, sigma, eq.state, s, self.b, self.with_tilt)
        self._known[sigma] = got
        return got

    def rescaled(self, orbit: PeriodicOrbit, sigma: float) -> np.ndarray:
        """A guess at spin sigma from an orbit at another: every momentum scales with the spin."""
        x = np.array(orbit.x0)
        for i, name in enumerate(self.states):
            if name.startswith("p_"):
                x[i] *= sigma / orbit.sigma
        return x

    def check(self, sigma: float) -> FloquetCheck:
        orbit = self.orbit(sigma)
        mu, kept = nontrivial_multipliers(orbit, self.shoot.rhs(orbit.x0),
                                          self.shoot.energy_gradient(orbit.x0))
        return FloquetCheck(sigma, mu, float(np.max(np.abs(np.abs(mu) - 1))), kept)

    def stable(self, sigma: float) -> bool:
        try:
            return self.check(sigma).stable
        except (NoOrbit, NoEquilibrium):
            return False


def meetings(jac0, lo: float, hi: float) -> list[float]:
    """The spins in [lo, hi] where two multipliers exp(2 pi i omega / sigma) of the aligned top
    meet on the unit circle (omega the imaginary parts of the eigenvalues of jac0(sigma), the eigen
    route's reduced Jacobian): (omega_j - omega_k) / sigma crosses an integer, by sign changes on a
    log grid refined by bisection to 1e-12 relative."""
    def ratios(sigma):
        w = np.sort(np.linalg.eigvals(jac0(sigma)).imag)
        d = (w[:, None] - w[None, :])[np.triu_indices(len(w), 1)]
        return d / sigma
    grid = np.geomspace(lo, hi, MEET_GRID)
    vals = [ratios(s) for s in grid]
    out = []
    for i in range(1, len(grid)):
        a_int, b_int = np.floor(vals[i - 1]), np.floor(vals[i])
        for k in np.nonzero(a_int != b_int)[0]:
            n = max(a_int[k], b_int[k])           # the integer crossed
            a, b, fa = grid[i - 1], grid[i], vals[i - 1][k] - n
            while b - a > 1e-12 * b:
                mid = 0.5 * (a + b)
                if np.sign(ratios(mid)[k] - n) == np.sign(fa):
                    a = mid
                else:
                    b = mid
            out.append(0.5 * (a + b))
    return sorted(set(out))


def spin_windows(stable, probes, rtol: float = SPIN_RTOL) -> list[tuple[float, float]]:
    """The spin intervals where stable(sigma), from the verdicts at the sorted probes, each change
    bisected (geometric midpoints) to rtol relative; an interval open at the first or last probe
    ends there."""
    sig = sorted(set(float(s) for s in probes if s > 0))
    verdict = [stable(s) for s in sig]
    ends = []
    for a, b, va, vb in zip(sig, sig[1:], verdict, verdict[1:]):
        if va == vb:
            continue
        while b - a > rtol * b:
            mid = math.sqrt(a * b)
            a, b = (mid, b) if stable(mid) == va else (a, mid)
        ends.append((math.sqrt(a * b), va))
    out, start = [], sig[0] if verdict and verdict[0] else None
    for at, was_stable in ends:
        if was_stable:
            out.append((start, at))
            start = None
        else:
            start = at
    if start is not None:
        out.append((start, sig[-1]))
    return out
