"""The steady motion of a top whose magnet is off its axis as a relative equilibrium: the fast route.

A moment tilted by b off the symmetry axis (top.moment_tilt, m = mu (cos b n + sin b e1) fixed in
the body, derive/mechanics.py) turns with the spin, so the steady motion is no longer the thesis's
relative equilibrium (eqs. 3.3.4-3.3.5: z = z_s, zeta = sigma t, p_zeta = sigma C) but a periodic
orbit of period T = 2 pi / sigma (runtime/physics/apparatus/periodic_orbit.py). Over a LEVEL base whose field
is AXISYMMETRIC about the plate's axis, gravity and the field are invariant under the rotations about
the vertical, whose momentum L_z is conserved (Noether; the generated `full_invariants`, first
component): the orbit is then the whole body turning rigidly about the vertical, its centre of mass
on a small circle, i.e. a relative equilibrium of that rotation (as the aligned top's steady
motion is one of the rotations about the vertical and about its axis, thesis eqs. 3.3.4-3.3.5
after Dullin & Easton 1999): a fixed point in the frame turning about z at the rate Omega.

In the Tait-Bryan states of the generated full model (thesis eqs. 3.2.2-3.2.11, R = R_x(phi)
R_y(vartheta) R_z(zeta); canonical pairs q = (x, y, z, phi, vartheta, zeta), p = (p_x, ..., p_zeta)
in that order) zeta turns the body about -n (omega_3 = -phi' sin vartheta - zeta', thesis eq. 3.2.9):
at the aligned top's relative equilibrium grad H = sigma e_{p_zeta} = -sigma grad L_z, so the frame
turns at Omega = -sigma and the fixed point is a critical point of the augmented Hamiltonian

    G = H - Omega L_z = H + sigma L_z         (H the generated `full_energy`).

G is invariant under the rotations about z: grad G . xi = 0 everywhere, xi = Jsym grad L_z their
generator, Jsym = [[0, I], [-I, 0]]. One of the twelve equations grad G = 0 is therefore implied by
the others, and so is the phase along xi: zeta = 0 fixes it (as the shooting's phase condition), the
row d G / d zeta is dropped (xi's zeta component, -1 at the aligned top, stays away from 0), and the
remaining 11 x 11 system is solved by Newton's method on CasADi's gradient and Hessian of G, built
once per model and reused for every spin and moment tilt: started from the aligned top's relative
equilibrium (runtime/physics/apparatus/tilted_equilibrium.py) and continued in b (`continued`: Euler predictor
along the branch's tangent, Newton corrector, as tilted_equilibrium.py continues in the base tilt
and periodic_orbit.py the orbit in b), or continued in the spin from a spin solved before at the
same b.

Linear stability in the turning frame is that of the autonomous system A = Jsym Hess G. A xi = 0
(Hess G xi = 0 at a critical point of an invariant G) and grad L_z^T A = 0 (L_z conserved), so A
maps W = {v : grad L_z . v = 0} into itself with xi in W: the 10 x 10 matrix Q^T A Q (Q an
orthonormal basis of W orthogonal to xi, in scaled states) carries the nontrivial eigenvalues, as
runtime/physics/apparatus/multipliers.py reduces the monodromy matrix. The frame turns by 2 pi in one period, so
the orbit's Floquet multipliers are exp(T lambda): the orbit is linearly stable exactly where all
ten lie on the imaginary axis, decided by the eigen route's perturbation bound
(runtime/physics/routes/eigen_route.py `on_imaginary_axis`). At b = 0 the spectrum is the eigen route's
(the linearisation of thesis eqs. 3.3.6-3.3.9) with each transverse mode's frequency shifted by the
frame's rate (u = x + i y and v = vartheta + i phi turn with the frame; the rotation commutes with
the linear flow): the real parts and so the window are the aligned top's
(tests/runtime/physics/apparatus/test_rotating_equilibrium.py).
A spin without a relative equilibrium on the branch from the aligned top counts as unstable.

Where the symmetry is missing (a tilted base: gravity off the plate's axis; a plate with only
four- or two-fold symmetry: scene/plates/symmetry.py) `refusal` says why and route "Floquet"
shooting (runtime/physics/apparatus/moment_tilt.py) serves instead. No sympy here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.physics.apparatus import multipliers as fl
from levitron.runtime.physics.routes.eigen_route import on_imaginary_axis
from levitron.runtime.physics.apparatus.periodic_orbit import NoOrbit, state_scales
from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium, TiltedTop, newton_step
from levitron.runtime.ui.human import Units
from levitron.runtime.words import si

ROUTE = ("Floquet multipliers exp(T lambda) of the relative equilibrium in the frame turning about the "
         "vertical at the spin (the level base and the axisymmetric plate make the periodic orbit a rigid "
         "rotation): Newton on the CasADi gradient of H + sigma L_z (the generated full_energy and "
         "full_invariants), continued in the moment tilt from the aligned top; eigenvalues of "
         "Jsym Hess(H + sigma L_z) less the rotation's zero pair, stable where all lie on the "
         "imaginary axis to rounding (the eigen route's bound)")
SPIN_RTOL = 1e-9         # relative width at which a window end's bisection stops (cheap: ~1 ms a spin)
NEAR = 0.2               # a relative equilibrium known within this (log) of a spin is continued from there
CLOSE = 1e-2             # and within this, where that fails there is none on the branch (a fold in the spin)
TILT_STEPS = 4           # continuation steps in the moment tilt from the aligned top (halved as needed)
NEWTON_ITER = 12
STEP_TOL = 1e-12         # a Newton step below this (scaled states) is converged
FLOOR = 1e-10            # and one below this that no longer halves: rounding's floor (near a fold)
MAX_STEP = 1.0           # a Newton step above this (scaled states) is not converging
STALL = 0.7              # two steps in a row shrinking by less than this: Newton is not converging
MAX_MOVE = 0.05          # a continuation step predicts a move of at most this (scaled states)
MIN_FRACTION = 1e-7      # a continuation step below this fraction of the way: the branch ends
FAR_FRACTION = 1e-3      # the same for a continuation in the spin from farther than CLOSE (b's decides)


def refusal(model, p: np.ndarray) -> str | None:
    """Why the relative-equilibrium route does not apply at parameters p (None where it does): it
    needs the generated energy and L_z, a level base (base_tilt absent or 0) and a plate
    symmetric about its axis (scene/plates/symmetry.py: "axial"; a square is only four-fold)."""
    from levitron.scene.plates.symmetry import symmetry
    if not (model.has_function("full_energy") and model.has_function("full_invariants")):
        return "the model has no generated full_energy and full_invariants"
    if "p_zeta" not in model.part("full").states:
        return "the model is not in Tait-Bryan states (model.coordinates)"
    P = model.pvals(p)
    if P.get("base_tilt", 0.0) != 0:
        return (f"the base is tilted ({si(P['base_tilt'], 'rad')}): gravity is off the plate's axis and "
                "no rotation about the vertical is a symmetry")
    sym = symmetry(model.scene.data["plate"], P)
    if sym.name != "axial":
        return f"the plate has {sym.name} symmetry only: L_z is not conserved"
    return None


@dataclass(frozen=True)
class RotatingCheck:
    """The relative equilibrium at one spin, its nontrivial eigenvalues and the verdict."""

    sigma: float
    state: np.ndarray            # the full state at zeta = 0
    eigenvalues: np.ndarray      # the ten nontrivial eigenvalues of Jsym Hess G (1/s)
    tolerance: np.ndarray        # per eigenvalue: how far off the axis rounding alone can put it
    residual: float              # max |dG/dx_i| s_i / (energy scale): how well G is stationary
    kept: float                  # |A xi| / (|A| |xi|), scaled: how well the rotation's direction is kept

    @property
    def stable(self) -> bool:
        return bool(np.all(np.abs(self.eigenvalues.real) <= self.tolerance))

    @property
    def multipliers(self) -> np.ndarray:
        """The Floquet multipliers exp(T lambda), T = 2 pi / sigma."""
        return np.exp(self.eigenvalues * 2 * math.pi / self.sigma)

    @property
    def deviation(self) -> float:
        """max | |mu| - 1 | over the multipliers, as route Floquet reports it."""
        return float(np.max(np.abs(np.expm1(np.abs(self.eigenvalues.real) * 2 * math.pi / self.sigma))))

    @property
    def growth_rate(self) -> float:
        """The largest real part (1/s): the e-folding rate of the fastest growing perturbation."""
        return float(max(np.max(self.eigenvalues.real), 0.0))


class _Buffered:
    """A CasADi function called through its buffer (no conversion per call: 25 us, not 150), its
    outputs made dense and returned as numpy arrays (matrices column-major, as CasADi stores them)."""

    def __init__(self, fn):
        import casadi as ca
        ins = [ca.SX.sym(fn.name_in(i), fn.sparsity_in(i)) for i in range(fn.n_in())]
        self._fn = ca.Function(fn.name(), ins, [ca.densify(e) for e in fn(*ins)])
        self._in = [np.zeros(self._fn.nnz_in(i)) for i in range(self._fn.n_in())]
        self._out = [np.zeros(self._fn.nnz_out(i)) for i in range(self._fn.n_out())]
        self._shape = [self._fn.size_out(i) for i in range(self._fn.n_out())]
        self._buf, self._eval = self._fn.buffer()
        for i, a in enumerate(self._in):
            self._buf.set_arg(i, memoryview(a))
        for i, a in enumerate(self._out):
            self._buf.set_res(i, memoryview(a))

    def __call__(self, *args) -> list[np.ndarray]:
        for a, v in zip(self._in, args):
            a[:] = v
        self._eval()
        return [a.reshape(shape, order="F").copy() for a, shape in zip(self._out, self._shape)]


class _Functions:
    """The CasADi functions of one model, built once and reused for every spin and moment tilt:
    F (the 11 equations grad G = 0 without dG/dzeta, in the 11 states but zeta, with zeta = 0) with
    its Jacobians in those states, in the spin and in the moment tilt; and at a full state Hess G,
    grad L_z and grad G. Jsym the canonical symplectic matrix of the state order (q, then p)."""

    def __init__(self, model):
        import casadi as ca
        self.states = tuple(model.part("full").states)
        n, n_p = len(self.states), len(model.p)
        h = n // 2
        if [f"p_{q}" for q in self.states[:h]] != list(self.states[h:]):
            raise ValueError(f"the full model's states {self.states} are not (q, p_q) in that order")
        self.Jsym = np.block([[np.zeros((h, h)), np.eye(h)], [-np.eye(h), np.zeros((h, h))]])
        self.izeta = self.states.index("zeta")
        self.free = [i for i in range(n) if i != self.izeta]
        self.ib = model.param_names.index("moment_tilt")
        x, s, pp = ca.SX.sym("x", n), ca.SX.sym("sigma"), ca.SX.sym("p", n_p)
        lz = model.casadi("full_invariants")(x, pp)[0]
        G = model.casadi("full_energy")(x, pp) + s * lz          # H - Omega L_z, Omega = -sigma
        grad = ca.gradient(G, x)
        self.A = _Buffered(ca.Function("A", [x, s, pp], [ca.hessian(G, x)[0], ca.gradient(lz, x), grad]))
        u = ca.SX.sym("u", n - 1)
        F = ca.substitute(grad, x, ca.vertcat(u[:self.izeta], ca.SX(0), u[self.izeta:]))[self.free]
        self.F = _Buffered(ca.Function("F", [u, s, pp], [F, ca.jacobian(F, u), ca.jacobian(F, s),
                                                        ca.jacobian(F, pp[self.ib])]))
        self.branches: dict[tuple, dict] = {}     # (p but b, spin) -> {"points": [(b, u)], "fail": b}


class RotatingTop:
    """The relative equilibria of one model at parameters p (moment tilt b from p, level base)
    along the spin and their eigenvalues, with the interface of runtime/physics/apparatus/multipliers.py's
    FloquetTop that moment_tilt.py uses (`stable`, `check`, `b`, `top`, `tilt`, `aligned`)."""

    def __init__(self, model, p: np.ndarray, z_magnet: float, top: TiltedTop | None = None,
                 functions: _Functions | None = None, fold_rtol: float = MIN_FRACTION):
        """fold_rtol: where a continuation's steps fall below this fraction of the way, its branch
        ends (a fold): how finely the end of existence is placed (MIN_FRACTION; coarser serves
        a search for whether a window exists at all)."""
        why = refusal(model, p)
        if why is not None:
            raise ValueError(f"the relative-equilibrium route does not apply: {why}")
        self.model, self.p = model, np.asarray(p, float)
        self.P = model.pvals(self.p)
        self.fold_rtol = fold_rtol
        self.b, self.tilt = self.P["moment_tilt"], 0.0
        self.aligned = model.with_params({"moment_tilt": 0.0}, self.p)
        self.z_magnet = z_magnet
        self.top = TiltedTop(model, self.aligned, z_magnet) if top is None else top
        self.fn = _Functions(model) if functions is None else functions
        self.states = self.fn.states
        self.rate_unit = Units.of(self.P["g"]).named("rad/s")     # in the scene's units
        self._known: dict[float, np.ndarray] = {}      # spin -> the solved states (zeta dropped)

    def at_tilt(self, b: float) -> RotatingTop:
        """The same top with the moment tilted by b, sharing the CasADi functions, the aligned top
        and the branch points found in b at each spin."""
        return RotatingTop(self.model, self.with_tilt(b), self.z_magnet, self.top, self.fn, self.fold_rtol)

    def with_tilt(self, b: float) -> np.ndarray:
        q = np.array(self.p)
        q[self.fn.ib] = b
        return q

    def scales(self, sigma: float) -> np.ndarray:
        return state_scales(self.states, self.top.z_level, self.P["m"], self.P["g"], self.P["C"], sigma)

    def _spin_branch(self, s0: float, s1: float):
        """(F, dF/du, dF/dt) along the spin from s0 (t = 0) to s1 (t = 1), geometrically."""
        rate = math.log(s1 / s0)

        def at(u, t):
            sigma = s0 * math.exp(rate * t)
            F, J, Fs, _ = self.fn.F(u, sigma, self.p)
            return F.ravel(), J, Fs.ravel() * sigma * rate
        return at

    def _tilt_branch(self, sigma: float):
        """(F, dF/du, dF/dt) along the moment tilt t at spin sigma."""
        def at(u, t):
            F, J, _, Fb = self.fn.F(u, sigma, self.with_tilt(t))
            return F.ravel(), J, Fb.ravel()
        return at

    def solve(self, sigma: float) -> np.ndarray:
        """The relative equilibrium at spin sigma, the full state at zeta = 0 (module docstring):
        continued in the spin from one known within NEAR (within CLOSE, where that fails there is
        none: a fold in the spin, as floquet.FloquetTop decides), else in the moment tilt from the
        aligned top; a NoOrbit where the branch from the aligned top ends before b."""
        if sigma in self._known:
            return self._full(self._known[sigma])
        scale = self.scales(sigma)[self.fn.free]
        u = None
        if self._known:
            near = min(self._known, key=lambda k: abs(math.log(k / sigma)))
            if abs(math.log(near / sigma)) < NEAR:
                close = abs(math.log(near / sigma)) < CLOSE
                u, _, _ = continued(self._spin_branch(near, sigma), self._known[near], 0.0, 1.0, scale, 1,
                                    self.fold_rtol if close else FAR_FRACTION)
                if u is None and close:
                    raise NoOrbit(self.b, sigma, self.b, self.rate_unit, from_spin=near)
        if u is None:
            u = self._in_tilt(sigma, scale)
        self._known[sigma] = u
        return self._full(u)

    def _in_tilt(self, sigma: float, scale: np.ndarray) -> np.ndarray:
        """The branch at spin sigma continued in b from the largest tilt solved on it below b (the
        aligned top's relative equilibrium at first); a tilt where it ended before is not tried
        again above (the branch folds back there)."""
        key = (tuple(np.delete(self.p, self.fn.ib)), sigma)
        br = self.fn.branches.get(key)
        if br is None:
            br = self.fn.branches[key] = {"points": [(0.0, self.top.hamilton(0.0, sigma).state[self.fn.free])],
                                          "fail": math.inf}
        b0, u0 = max((pt for pt in br["points"] if pt[0] <= self.b), key=lambda pt: pt[0])
        if self.b >= br["fail"]:
            raise NoOrbit(self.b, sigma, b0, self.rate_unit)
        u, reached, last = continued(self._tilt_branch(sigma), u0, b0, self.b, scale, TILT_STEPS,
                                     self.fold_rtol)
        if reached > b0:
            br["points"].append((reached, last))
        if u is None:
            br["fail"] = min(br["fail"], self.b)
            raise NoOrbit(self.b, sigma, reached, self.rate_unit)
        return u

    def _full(self, u: np.ndarray) -> np.ndarray:
        return np.insert(np.asarray(u, float), self.fn.izeta, 0.0)

    def check(self, sigma: float) -> RotatingCheck:
        """The relative equilibrium at sigma and its ten nontrivial eigenvalues (module docstring),
        reduced in the states scaled by `scales` (y = x / s)."""
        x = self.solve(sigma)
        hess, gl, grad = self.fn.A(x, sigma, self.p)
        s = self.scales(sigma)
        A = (self.fn.Jsym @ hess) * s[None, :] / s[:, None]
        g = gl.ravel() * s                                           # grad L_z in y
        xi = (self.fn.Jsym @ gl.ravel()) / s                         # the rotation's generator in y
        U = np.linalg.qr(g[:, None], mode="complete")[0][:, 1:]      # W = g-perp
        V = np.linalg.qr((U.T @ xi)[:, None], mode="complete")[0][:, 1:]
        Q = U @ V                                                    # W, xi-perp
        ev = on_imaginary_axis(Q.T @ A @ Q)
        energy = max(self.P["m"] * self.P["g"] * self.top.z_level, self.P["C"] * sigma ** 2)
        return RotatingCheck(sigma, x, ev.eigenvalues, ev.tolerance,
                             float(np.max(np.abs(grad.ravel() * s)) / energy),
                             float(np.linalg.norm(A @ xi) / (np.linalg.norm(A) * np.linalg.norm(xi))))

    def stable(self, sigma: float) -> bool:
        try:
            return self.check(sigma).stable
        except (NoOrbit, NoEquilibrium):
            return False

    def windows(self, probes, rtol: float = SPIN_RTOL) -> list[tuple[float, float]]:
        """The spin windows where `stable`, from the verdicts at `probes` (moment_tilt.py's
        probes_for: a log grid around the aligned window and the aligned system's multiplier
        meetings), each change bisected to rtol (runtime/physics/apparatus/multipliers.py spin_windows)."""
        return fl.spin_windows(self.stable, probes, rtol)


def newton(FJ, u0: np.ndarray, scale: np.ndarray, reach: float = MAX_STEP) -> np.ndarray | None:
    """Newton's method on F(u) = 0 from u0 (FJ(u) = (F, dF/du)), steps measured in units of
    `scale`: converged at a step below STEP_TOL, or below FLOOR once the steps stop halving
    (rounding's floor where the Jacobian is ill conditioned, near a fold); None where a step is
    above MAX_STEP or not finite, u moves farther than `reach` from u0 (a continuation step that
    would be refused anyway), the steps stall (STALL) or NEWTON_ITER steps do not converge."""
    u = np.array(u0, float)
    steps: list[float] = []
    for _ in range(NEWTON_ITER):
        du = newton_step(*FJ(u), scale)
        if du is None:
            return None
        d = float(np.max(np.abs(du / scale)))
        if not d <= MAX_STEP:
            return None
        u = u + du
        if not np.max(np.abs((u - u0) / scale)) <= reach:
            return None
        if d <= STEP_TOL or (d <= FLOOR and steps and d > 0.5 * steps[-1]):
            return u
        steps.append(d)
        if len(steps) >= 3 and steps[-1] > STALL * steps[-2] and steps[-2] > STALL * steps[-3]:
            return None
    return None


def continued(at, u0: np.ndarray, t0: float, t1: float, scale: np.ndarray, steps: int,
              min_fraction: float = MIN_FRACTION) -> tuple[np.ndarray | None, float, np.ndarray]:
    """Follow F(u, t) = 0 (at(u, t) = (F, dF/du, dF/dt)) from t0 (u0 near its point there) up to
    t1 >= t0, as runtime/physics/apparatus/tilted_equilibrium.py's `continued`: Euler predictor along the
    tangent moving no state by more than MAX_MOVE of its scale, Newton corrector, the step accepted
    only where the correction is under half the predicted move (so Newton keeps to the branch;
    Newton stops as soon as it moves farther), else halved and not doubled on the next success,
    down to min_fraction of t1 (at a fold the tangent is unbounded and the steps shrink to
    nothing). Returns (the solution at t1 or None, the largest t reached, the solution there)."""
    u = newton(lambda v: at(v, t0)[:2], u0, scale)
    if u is None:
        return None, t0, np.array(u0, float)
    t, h, failed = t0, (t1 - t0) / steps, False
    while t < t1:
        h = min(h, t1 - t)
        _, J, Ft = at(u, t)
        try:
            rate = np.linalg.solve(J * scale[None, :], -Ft) * scale
        except np.linalg.LinAlgError:
            return None, t, u
        h = min(h, MAX_MOVE / max(float(np.max(np.abs(rate / scale))), 1e-300))
        step = rate * h
        size = float(np.max(np.abs(step / scale)))
        got = newton(lambda v, th=t + h: at(v, th)[:2], u + step, scale, 0.5 * size + FLOOR)
        if got is None:
            h, failed = h / 2, True
            if h < min_fraction * t1:
                return None, t, u
            continue
        t, u = t + h, got
        h, failed = h if failed else 2 * h, False
    return u, t, u
