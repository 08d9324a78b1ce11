"""The relative equilibrium of the spinning top over a tilted base (plate.tilt), by two routes.

On a tilted base (scene key plate.tilt; derive/mechanics.py) gravity g_vec = g (sin t cos a,
sin t sin a, -cos t) is no longer along the plate's axis, so the top no longer hovers on it. The
tilt keeps the top's own symmetry: the top spinning about its axis n, with n fixed in space, is a
relative equilibrium where L = C omega_3 n is constant, i.e. the torque mu n x B vanishes (n along
the local field B) and the magnetic force balances m g_vec (thesis 3.3.4-3.3.5 generalised).

Route "Hamilton" (the reported one): Hamilton's equations, the generated `full_rhs` (Tait-Bryan
states), set to zero in every row but zeta's and p_zeta's (zeta is cyclic: p_zeta = C sigma is the
spin, as in runtime/physics/routes/eigen_route.py), solved for the other ten states by Newton's method on
the CasADi Jacobian of the generated function, continued in the tilt from the level answer
(x = y = 0, z = z_s, the axis vertical; runtime/physics/equilibrium/finder.py finds z_s).

Route "adiabatic" (independent, for the check): with n = -sign(mu) B/|B| the energy is
V(r) = |mu| |B(r)| + m g h(r), h = z cos t - (x cos a + y sin a) sin t; its stationary point,
by Newton on the CasADi gradient and Hessian of the generated `field`, continued the same way.
Force balance with n along B is exactly grad V = 0 (grad |B| = (grad B)^T B/|B|), so the two routes
meet to rounding, at every spin: the position does not depend on it (the momenta scale with it).

No sympy here.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from levitron.runtime.errors import UserError

FIXED = ("zeta", "p_zeta")         # the cyclic angle and its momentum, the spin: not solved for
SPIN_MOMENTA = ("p_phi", "p_vartheta", "p_zeta")
NEWTON_ITER = 40
STEP_TOL = 1e-14                   # a Newton step below this (scaled) is converged
MIN_FRACTION = 1e-7                # continuation steps below this fraction of the tilt: no equilibrium
MAX_MOVE = 0.05                    # a continuation step moves no state by more than this of its scale


@dataclass(frozen=True)
class TiltedEquilibrium:
    """The relative equilibrium at tilt `tilt`: the full state at spin `sigma` (p_zeta = C sigma)."""

    tilt: float
    azimuth: float
    sigma: float
    state: np.ndarray
    states: tuple
    axis: np.ndarray
    residual: float                 # max |rhs| over the solved rows, relative to the rows' scales

    @property
    def position(self) -> np.ndarray:
        return np.array([self.state[self.states.index(k)] for k in "xyz"])

    def at_spin(self, sigma: float) -> np.ndarray:
        """The equilibrium state at another spin: the position and angles are the same, the angular
        momenta (components of L = C omega_3 n) scale with the spin (module docstring)."""
        x = np.array(self.state)
        for k in SPIN_MOMENTA:
            x[self.states.index(k)] *= sigma / self.sigma
        return x

    def as_dict(self, z_level: float) -> dict:
        pos = self.position
        down = np.array([math.cos(self.azimuth), math.sin(self.azimuth)])
        return {"position": [float(v) for v in pos], "axis": [float(v) for v in self.axis],
                "tilt": self.tilt, "tilt_azimuth": self.azimuth,
                "offset": float(math.hypot(pos[0], pos[1])),
                "downhill": float(pos[:2] @ down), "rise": float(pos[2] - z_level),
                "z_level": z_level, "residual": self.residual,
                "route": "Newton on the generated full_rhs (CasADi Jacobian), continued in the tilt"}


def gravity_height(xyz, tilt: float, azimuth: float):
    """h = -g_vec.r / g (derive/mechanics.py gravity_height), numpy or CasADi."""
    return (xyz[2] * math.cos(tilt)
            - (xyz[0] * math.cos(azimuth) + xyz[1] * math.sin(azimuth)) * math.sin(tilt))


def newton_step(F: np.ndarray, J: np.ndarray, scale: np.ndarray) -> np.ndarray | None:
    """One Newton step du of F + J du = 0, solved in units of `scale`; None where J is singular
    or the step is not finite."""
    try:
        du = np.linalg.solve(J * scale[None, :], -F) * scale
    except np.linalg.LinAlgError:
        return None
    return du if np.all(np.isfinite(du)) else None


def newton(FJ: Callable, u0: np.ndarray, scale: np.ndarray) -> np.ndarray | None:
    """Newton's method on F(u) = 0 from u0 (FJ(u) = (F, dF/du)), steps measured in units of
    `scale`; None if it does not converge in NEWTON_ITER steps (or a step is not finite)."""
    u = np.array(u0, dtype=float)
    for _ in range(NEWTON_ITER):
        du = newton_step(*FJ(u), scale)
        if du is None:
            return None
        u = u + du
        if np.max(np.abs(du / scale)) <= STEP_TOL:
            return u
    return None


@dataclass(frozen=True)
class Branch:
    """F(u, t) = 0 along the tilt t: at(u, t) -> (F, its Jacobian J = dF/du, dF/dt)."""

    at: Callable
    scale: np.ndarray

    def tangent(self, u: np.ndarray, t: float) -> np.ndarray:
        """du/dt along the branch: J du/dt = -dF/dt."""
        _, J, Ft = self.at(u, t)
        return np.linalg.solve(J * self.scale[None, :], -Ft) * self.scale

    def solve(self, t: float, guess: np.ndarray) -> np.ndarray | None:
        return newton(lambda u: self.at(u, t)[:2], guess, self.scale)


def continued(branch: Branch, u0: np.ndarray, tilt: float, steps: int = 4,
              t0: float = 0.0) -> tuple[np.ndarray | None, float]:
    """Follow the branch from t0 (default 0; u0 near its point there) to `tilt`: Euler predictor
    along the tangent, Newton corrector. A step predicts a move of at most MAX_MOVE of each
    state's scale, and is accepted only where the correction is under half the predicted move
    (on a smooth branch it is of second order in the step), else halved: so Newton never jumps
    to another branch, and at a fold (det J = 0, the tangent unbounded) the steps shrink to
    nothing. Returns (the solution at `tilt` or None, the largest tilt reached on the branch)."""
    u = branch.solve(t0, np.array(u0, dtype=float))
    if u is None:
        return None, t0
    t, h = t0, (tilt - t0) / steps
    while t < tilt:
        h = min(h, tilt - t)
        try:
            rate = branch.tangent(u, t)
        except np.linalg.LinAlgError:
            return None, t
        h = min(h, MAX_MOVE / max(np.max(np.abs(rate / branch.scale)), 1e-300))
        step = rate * h
        got = branch.solve(t + h, u + step)
        size = np.max(np.abs(step / branch.scale))
        if got is None or np.max(np.abs((got - u - step) / branch.scale)) > 0.5 * size:
            h /= 2
            if h < MIN_FRACTION * max(tilt, 1e-300):
                return None, t
            continue
        t, u = t + h, got
        h *= 2
    return u, t


class TiltedTop:
    """The generated full model of a tilted scene at parameters p, wrapped for the two routes."""

    def __init__(self, model, p: np.ndarray, z_magnet: float):
        """z_magnet: the level equilibrium's height of the magnet, the on-axis finder's
        (runtime/physics/equilibrium/finder.py); the centre of mass sits top.moment_offset below it."""
        import casadi as ca
        if "p_zeta" not in model.part("full").states:
            raise UserError(f"scene '{model.scene.name}': the equilibrium over a tilted base is found "
                            "in Tait-Bryan angles: set model.coordinates = \"tait-bryan\"")
        self.model, self.p = model, np.asarray(p, float)
        self.P = model.pvals(self.p)
        self.z_level = z_magnet - self.P.get("moment_offset", 0.0)
        if not self.z_level > 0:            # the centre of mass at or below the base: no such top
            from levitron.runtime.words import si
            raise UserError(f"top.moment_offset = {si(self.P['moment_offset'], 'm')} is not less than the "
                            f"magnet's hover height {si(z_magnet, 'm')}: the top's centre of mass would sit "
                            "at or below the base; give a smaller one, e.g. "
                            f"«set=top.moment_offset={0.5 * z_magnet:.3g}»")
        part = model.part("full")
        self.states = tuple(part.states)
        self.free = [i for i, s in enumerate(self.states) if s not in FIXED]
        self.rows = [i for i, s in enumerate(self.states) if s not in FIXED]
        rhs, field = model.casadi("full_rhs"), model.casadi("field")
        u, pp = ca.SX.sym("u", len(self.free)), ca.SX.sym("p", self.p.size)
        x = ca.SX.zeros(len(self.states))
        fixed = ca.SX.sym("fixed", 2)
        for k, i in enumerate(self.free):
            x[i] = u[k]
        for k, name in enumerate(FIXED):
            x[self.states.index(name)] = fixed[k]
        it = self.model.param_names.index("base_tilt")
        F = rhs(x, pp)[self.rows]
        self._F = ca.Function("F", [u, fixed, pp], [F, ca.jacobian(F, u), ca.jacobian(F, pp[it])])
        r = ca.SX.sym("r", 3)
        t, a = pp[it], pp[self.model.param_names.index("base_tilt_azimuth")]
        B = field(r, pp)
        h = r[2] * ca.cos(t) - (r[0] * ca.cos(a) + r[1] * ca.sin(a)) * ca.sin(t)
        V = abs(self.P["mu"]) * ca.sqrt(ca.dot(B, B)) + self.P["m"] * self.P["g"] * h
        grad, hess = ca.gradient(V, r), ca.hessian(V, r)[0]
        self._V = ca.Function("V", [r, pp], [V, grad, hess, ca.jacobian(grad, pp[it])])
        self._axis = model.casadi("full_axis")
        self._known: list = []          # (tilt, solved states / _per_spin) on the branch: warm starts

    def params_at(self, tilt: float) -> np.ndarray:
        return self.model.with_params({"base_tilt": tilt}, self.p)

    def _branch(self, fn, fixed, scale: np.ndarray) -> Branch:
        """The Branch of fn(u[, fixed], p) -> (F, dF/du, dF/dt) along the tilt."""
        def at(u, t):
            args = (u, self.params_at(t)) if fixed is None else (u, fixed, self.params_at(t))
            F, J, Ft = (np.asarray(v, float) for v in fn(*args))
            return F.ravel(), J, Ft.ravel()
        return Branch(at, scale)

    # ---- route "Hamilton"
    def _scales(self, sigma: float) -> np.ndarray:
        C, m, g = self.P["C"], self.P["m"], self.P["g"]
        L = self.z_level
        pos = m * math.sqrt(g * L)
        spin = max(abs(C * sigma), C * math.sqrt(g / L))
        by_name = {"x": L, "y": L, "z": L, "phi": 1.0, "vartheta": 1.0, "p_x": pos, "p_y": pos,
                   "p_z": pos, "p_phi": spin, "p_vartheta": spin}
        return np.array([by_name[self.states[i]] for i in self.free])

    def hamilton(self, tilt: float, sigma: float) -> TiltedEquilibrium:
        """The relative equilibrium at `tilt` and spin sigma (route "Hamilton", module docstring);
        a UserError naming the largest tilt reached when the branch ends before `tilt`."""
        fixed = [0.0, self.P["C"] * sigma]
        level = np.zeros(len(self.states))
        level[self.states.index("z")] = self.z_level
        level[self.states.index("p_zeta")] = fixed[1]
        t0, u0 = max(((t, u) for t, u in self._known if t <= tilt), key=lambda tu: tu[0],
                     default=(0.0, level[self.free] / self._per_spin(sigma)))
        u, reached = continued(self._branch(self._F, fixed, self._scales(sigma)), u0 * self._per_spin(sigma),
                               tilt, t0=t0)
        if u is None:
            raise NoEquilibrium(tilt, reached)
        self._known.append((tilt, u / self._per_spin(sigma)))
        x = level.copy()
        x[self.free] = u
        pt = self.params_at(tilt)
        res = np.asarray(self._F(u, fixed, pt)[0], float).ravel()
        rhs_scale = self._rhs_scales(sigma)
        axis = np.asarray(self._axis(x, pt), float).ravel()
        return TiltedEquilibrium(tilt, self.P["base_tilt_azimuth"], sigma, x, self.states, axis,
                                 float(np.max(np.abs(res) / rhs_scale)))

    def _per_spin(self, sigma: float) -> np.ndarray:
        """The factor of each solved state in sigma: the angular momenta scale with it, the rest
        not (TiltedEquilibrium.at_spin); the branch points found are kept divided by it."""
        return np.array([sigma if self.states[i] in SPIN_MOMENTA else 1.0 for i in self.free])

    def _rhs_scales(self, sigma: float) -> np.ndarray:
        """The size of each solved row's terms: velocities L/T, forces m g, torques C sigma / T."""
        m, g, L = self.P["m"], self.P["g"], self.z_level
        T = math.sqrt(L / g)
        spin = max(abs(self.P["C"] * sigma), self.P["C"] / T)
        by_name = {"x": L / T, "y": L / T, "z": L / T, "phi": 1 / T, "vartheta": 1 / T,
                   "p_x": m * g, "p_y": m * g, "p_z": m * g, "p_phi": spin / T, "p_vartheta": spin / T}
        return np.array([by_name[self.states[i]] for i in self.rows])

    # ---- route "adiabatic"
    def adiabatic(self, tilt: float) -> np.ndarray:
        """The stationary point of V(r) = |mu| |B| + m g h (module docstring), continued from the
        level answer; a NoEquilibrium where the branch ends."""
        V = lambda r, pt: self._V(r, pt)[1:]        # noqa: E731  (gradient, Hessian, d grad/dt)
        r, reached = continued(self._branch(V, None, np.full(3, self.z_level)),
                               np.array([0.0, 0.0, self.z_level]), tilt)
        if r is None:
            raise NoEquilibrium(tilt, reached)
        return r

    def lateral_stiffness(self) -> float:
        """k_r = d^2 V / dx^2 at the level equilibrium (0, 0, z_s): the linear estimate of the
        sideways shift is m g sin(t) / k_r."""
        return float(np.asarray(self._V([0.0, 0.0, self.z_level], self.params_at(0.0))[2])[0, 0])


class NoEquilibrium(UserError):
    """The branch of relative equilibria ends (a fold) before the requested tilt."""

    def __init__(self, tilt: float, reached: float):
        self.tilt, self.reached = tilt, reached
        super().__init__(f"the top has no equilibrium on a base tilted by {tilt:.6g} rad: the "
                         f"branch from the level one ends near {reached:.6g} rad "
                         f"({math.degrees(reached):.4g} deg); level the base better than that")
