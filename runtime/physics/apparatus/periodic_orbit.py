"""The periodic steady motion of a top whose moment is off its axis (top.moment_tilt).

With the moment m = mu (cos b n + sin b e1) fixed in the body (derive/mechanics.py), the potential
depends on the spin angle zeta: the relative equilibrium of the aligned top (the top spinning at
sigma about its axis, runtime/physics/apparatus/tilted_equilibrium.py) becomes a periodic orbit of period
T = 2 pi / sigma in which zeta advances by 2 pi and every other state returns. (Over a level base
it is a rigid rotation about the plate's axis, a relative equilibrium of the rotation about z; over
a tilted one a true periodic orbit. The shooting below does not use either fact.)

Shooting: the flow phi_T of the generated `full_rhs` over one period, by CasADi's CVODES in scaled
states y = x / s (so that one absolute tolerance serves positions, angles and momenta), with its
Jacobian, the monodromy matrix dphi_T/dx0, from CasADi's forward sensitivities (the variational
equations of the generated function). Newton's method solves phi_T(x0) = x0 + 2 pi e_zeta for the
eleven states but zeta (zeta(0) = 0 fixes the phase), in least squares (twelve rows, rank eleven:
the residual is consistent), started from the aligned relative equilibrium at the same spin and
continued in the moment tilt. No sympy here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import Units

RTOL = 1e-12                 # CVODES relative and (scaled-state) absolute tolerance
NEWTON_ITER = 12
STEP_TOL = 1e-11             # a Newton step below this (scaled states) is converged
MAX_STEP = 0.3               # a Newton step above this (scaled states) is not converging
STALL = 0.7                  # two steps in a row shrinking by less than this: Newton is not converging
TILT_STEPS = 4               # continuation steps in the moment tilt from the aligned orbit
MIN_STEP = 1 / 64            # a continuation step below this fraction of the tilt: no orbit


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit: its start x0 (zeta = 0), period T = 2 pi / sigma, monodromy M = dx(T)/dx0."""

    sigma: float
    period: float
    x0: np.ndarray
    monodromy: np.ndarray
    scales: np.ndarray           # the state scales s of the shooting (y = x / s)
    residual: float              # max |phi_T(x0) - x0 - 2 pi e_zeta| / s after the last step


class Shooting:
    """The flow of the generated full model over one period, at parameters p, with its monodromy."""

    def __init__(self, model, p: np.ndarray):
        import casadi as ca
        self.model, self.p = model, np.asarray(p, float)
        self.rate_unit = Units.of(model.pvals(self.p)["g"]).named("rad/s")    # in the scene's units
        self.states = tuple(model.part("full").states)
        self.izeta = self.states.index("zeta")
        n = len(self.states)
        y, s, T, pp = ca.MX.sym("y", n), ca.MX.sym("s", n), ca.MX.sym("T"), ca.MX.sym("p", self.p.size)
        rhs = model.casadi("full_rhs")
        ode = T * rhs(y * s, pp) / s
        # a non-stiff problem: Adams with functional iteration (measured 6x faster than BDF/Newton
        # at 1e-12 on thesis_stable, and closer to symplectic: |mu| - 1 of 7e-12 against 3e-10)
        flow = ca.integrator("period", "cvodes", {"x": y, "p": ca.vertcat(s, T, pp), "ode": ode},
                             0.0, 1.0, {"abstol": RTOL, "reltol": RTOL, "max_num_steps": 10 ** 6,
                                        "linear_multistep_method": "adams",
                                        "nonlinear_solver_iteration": "functional",
                                        "disable_internal_warnings": True})
        y0 = ca.MX.sym("y0", n)
        yT = flow(x0=y0, p=ca.vertcat(s, T, pp))["xf"]
        self._flow = ca.Function("flow", [y0, s, T, pp], [yT, ca.jacobian(yT, y0)])
        self._f = rhs
        energy = model.casadi("full_energy")
        xs, ps = ca.SX.sym("x", n), ca.SX.sym("p", self.p.size)
        self._grad = ca.Function("gradH", [xs, ps], [ca.gradient(energy(xs, ps), xs)])

    def flow(self, x0: np.ndarray, period: float, scales: np.ndarray, p: np.ndarray | None = None):
        """(x(T), dx(T)/dx0) of the generated full model from x0, integrated in x / scales."""
        p = self.p if p is None else p
        yT, J = self._flow(x0 / scales, scales, period, p)
        return (np.asarray(yT, float).ravel() * scales,
                np.asarray(J, float) * scales[:, None] / scales[None, :])

    def rhs(self, x: np.ndarray, p: np.ndarray | None = None) -> np.ndarray:
        return np.asarray(self._f(x, self.p if p is None else p), float).ravel()

    def energy_gradient(self, x: np.ndarray, p: np.ndarray | None = None) -> np.ndarray:
        return np.asarray(self._grad(x, self.p if p is None else p), float).ravel()

    def solve(self, sigma: float, guess: np.ndarray, scales: np.ndarray,
              p: np.ndarray | None = None) -> PeriodicOrbit | None:
        """The periodic orbit of period 2 pi / sigma near `guess` (its zeta set to 0), by Newton's
        method in least squares (module docstring); None if it does not converge."""
        T = 2 * math.pi / sigma
        x = np.array(guess, float)
        x[self.izeta] = 0.0
        free = [i for i in range(len(x)) if i != self.izeta]
        shift = np.zeros(len(x))
        shift[self.izeta] = 2 * math.pi
        steps: list[float] = []
        for _ in range(NEWTON_ITER + 1):
            try:
                xT, M = self.flow(x, T, scales, p)
            except RuntimeError:        # CVODES gives up (a guess far off the orbit): no orbit here
                return None
            R = (xT - x - shift) / scales
            if not np.all(np.isfinite(R)):
                return None
            Js = (M - np.eye(len(x)))[:, free] * scales[free][None, :] / scales[:, None]
            dy = np.linalg.lstsq(Js, -R, rcond=None)[0]
            if not np.max(np.abs(dy)) <= MAX_STEP:    # Newton is not near an orbit: no orbit here
                return None
            if np.max(np.abs(dy)) <= STEP_TOL:
                return PeriodicOrbit(sigma, T, x, M, scales, float(np.max(np.abs(R))))
            steps.append(float(np.max(np.abs(dy))))
            if len(steps) >= 3 and steps[-1] > STALL * steps[-2] and steps[-2] > STALL * steps[-3]:
                return None     # Newton converges at least linearly by 1/2 near an orbit (even at a fold)
            x[free] += dy * scales[free]
        return None


def state_scales(states, z: float, m: float, g: float, C: float, sigma: float) -> np.ndarray:
    """The size of each state near the hovering top: heights z, angles 1, linear momenta
    m sqrt(g z), angular momenta C sigma (as runtime/physics/apparatus/tilted_equilibrium.py's scales)."""
    spin = abs(C * sigma)
    by_name = {"x": z, "y": z, "z": z, "phi": 1.0, "vartheta": 1.0, "zeta": 1.0,
               "p_x": m * math.sqrt(g * z), "p_y": m * math.sqrt(g * z), "p_z": m * math.sqrt(g * z),
               "p_phi": spin, "p_vartheta": spin, "p_zeta": spin}
    return np.array([by_name[s] for s in states])


class NoOrbit(UserError):
    """The periodic orbit is not found: Newton fails along the continuation in the moment tilt, or
    from the orbit of a spin close by (`from_spin`)."""

    def __init__(self, b: float, sigma: float, reached: float, rate_unit: str = "rad/s",
                 from_spin: float | None = None):
        self.b, self.sigma, self.reached = b, sigma, reached
        where = (f"the continuation from the aligned top ends near {reached:.6g} rad" if from_spin is None
                 else f"Newton from the orbit at {from_spin:.9g} {rate_unit} does not converge")
        super().__init__(f"no periodic orbit of the top with its moment tilted by {b:.6g} rad at spin "
                         f"{sigma:.6g} {rate_unit}: {where}")


def continued_orbit(shoot: Shooting, sigma: float, start: np.ndarray, scales: np.ndarray, b: float,
                    with_tilt, b0: float = 0.0, steps: int = TILT_STEPS) -> PeriodicOrbit:
    """The orbit at moment tilt b, continued from the orbit (or relative equilibrium) `start` at
    tilt b0: secant predictor, Newton corrector, the step halved where Newton fails (down to
    MIN_STEP of b); with_tilt(b) gives the parameter vector at moment tilt b. A NoOrbit where it ends."""
    t, h = b0, (b - b0) / steps
    prev, x = None, np.array(start, float)
    orbit = shoot.solve(sigma, x, scales, with_tilt(t))
    if orbit is None:
        raise NoOrbit(b, sigma, t, shoot.rate_unit)
    x = orbit.x0
    while abs(t - b) > 0:
        h = math.copysign(min(abs(h), abs(b - t)), b - b0)
        guess = x if prev is None else x + (x - prev[1]) * h / (t - prev[0])
        got = shoot.solve(sigma, guess, scales, with_tilt(t + h))
        if got is None:
            h /= 2
            if abs(h) < MIN_STEP * abs(b - b0):
                raise NoOrbit(b, sigma, t, shoot.rate_unit)
            continue
        prev, t, x, orbit = (t, x), t + h, got.x0, got
    return orbit
