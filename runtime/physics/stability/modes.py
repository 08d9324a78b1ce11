"""The linear modes of the top at its relative equilibrium on the axis: frequencies, names, sense of
rotation and energy (Krein) sign (thesis 3.3.4-3.3.11).

The relative equilibrium (thesis 3.3.4, 3.3.5): the top upright on the axis at z_s, zeta = sigma t,
p_zeta = C sigma. zeta is cyclic, so fixing p_zeta = C sigma and dropping (zeta, p_zeta) leaves a
Hamiltonian system in the ten other canonical variables q = (x, y, z, phi, vartheta), p = (p_x,
..., p_vartheta) whose Hamiltonian is H itself at that p_zeta (Routh's reduction). The relative
equilibrium is a true equilibrium of it: grad H = 0 in those ten variables (grad H = sigma
e_{p_zeta} in all twelve, so the state is a critical point of the augmented H - sigma p_zeta, whose
Hessian is H's: p_zeta enters it linearly). The linearisation is xdot = Jsym S x, S = Hess H in the
ten variables (the generated `full_jac` without zeta's column and p_zeta's row,
runtime/physics/apparatus/tilted_stability.py `reduced_jacobian`; S from the generated `full_energy` by CasADi,
or, where casadi is not loaded, S = -Jsym J, the same matrix for a Hamiltonian J: air friction is
set to 0 first, runtime/physics/apparatus/friction.py).

Each pair of eigenvalues +-i omega (eigenvector v of +i omega) is one real mode:
* its energy (Krein) sign kappa = sign(v^H S v): the sign of the quadratic energy H_2 = x^T S x / 2
  carried by the mode (the same for v and its conjugate). S is indefinite (the tilt and the
  horizontal translation sit on potential maxima, Earnshaw, held by the gyroscopic terms), so a
  stable mode may carry negative energy; two modes can collide (leave the imaginary axis) only if
  their signs differ: the window's ends (thesis 3.3.12-3.3.16) are such collisions.
* its sense: the mode's circulation about the vertical, m Im(x conj y) + A Im(vartheta conj phi)
  (the horizontal translation and the axis' tilt n = (vartheta, phi) turn the same way on a level
  axisymmetric base: u = x + i y and v = vartheta + i phi of thesis 3.3.6 carry the same e^{i omega
  t}), compared with the spin's (the sign of L.n, generated `full_invariants`): +1 with the spin,
  -1 against; the vertical bounce (z, p_z) has none.

On a level base with axial (or four-fold: its field is axisymmetric to second order about the axis,
scene/plates/symmetry.py) symmetry the bounce decouples, omega_z = sqrt(mu Phi_3(z_s) / m) (thesis
3.3.3) at every spin, and the transverse block splits into four circular modes of azimuthal number
1 whose frequencies signed by their sense are sigma rho t_k, t_k the roots of N(t) (thesis 3.3.11,
lambda = i sigma rho t, rho = C / A). Names: of the modes turning with the spin the fastest is the
"fast precession" (the nutation, omega -> rho sigma as sigma grows), of the other transverse modes
the one of negative energy is the "slow precession" (the axis' precession under the field's torque,
omega ~ mu Phi_1 / (C sigma) near the window's lower end; for sigma -> infinity the root t ~ g_1 -
g_2^2 / g_3 of N gives omega C sigma -> mu (Phi_1 - Phi_2^2 / (2 Phi_3))), the rest the horizontal
"translation(+1)" and "translation(-1)" by their sense. Inside the window the order of the signed
frequencies and the energy signs do not change, so the names follow each mode across it; its
content does (the slow precession turns from a tilt into mostly a translation towards the window's
upper end): `translation` gives the share m|u|^2 / (m|u|^2 + m|z|^2 + A|v|^2). Off the window a
colliding pair leaves the axis: both are listed, with their growth rate and krein 0. No sympy here.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.routes.eigen_route import EPS, balancing, transverse_matrix
from levitron.runtime.physics.apparatus.friction import without_friction
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.validate import spin_rate

_SI = Units(si=True)
STATES = ("x", "y", "z", "phi", "vartheta", "p_x", "p_y", "p_z", "p_phi", "p_vartheta")
BOUNCE, FAST, SLOW = "vertical bounce", "fast precession", "slow precession"
OFF_AXIS = ("base_tilt", "moment_tilt", "moment_offset")   # nonzero: the steady motion is not on the axis


@dataclass(frozen=True)
class Mode:
    """One linear mode: `frequency` |Im lambda| (rad/s), `sense` +1 with the spin, -1 against, 0 the
    bounce; `krein` its energy sign (+1/-1; 0 off the imaginary axis); `eigenvalue` lambda (1/s);
    `translation` the share of the horizontal translation in it; `azimuthal` 1 (transverse) or 0."""

    name: str
    frequency: float
    sense: int
    krein: int
    eigenvalue: complex
    translation: float
    azimuthal: int

    @property
    def signed(self) -> float:
        """The frequency signed by the sense (the bounce's positive)."""
        return self.frequency * (self.sense or 1)

    @property
    def growth(self) -> float:
        return abs(self.eigenvalue.real) if self.krein == 0 else 0.0

    def as_json(self) -> dict:
        return {"name": self.name, "frequency": self.frequency, "sense": self.sense, "krein": self.krein,
                "eigenvalue": [self.eigenvalue.real, self.eigenvalue.imag], "growth_rate": self.growth,
                "translation": self.translation, "azimuthal": self.azimuthal}


class LinearSystem:
    """The 10-D linearisation at the relative equilibrium on the axis of one model (module
    docstring), for any spin: `jacobian(sigma)`, `hessian(sigma)`, `modes(sigma)`.
    hessian: "casadi" (the generated full_energy's) or "jacobian" (-Jsym J, no casadi import)."""

    def __init__(self, model, z_s: float, p: np.ndarray | None = None, hessian: str = "casadi"):
        p = without_friction(model, model.p if p is None else p)
        P = model.pvals(p)
        off = [k for k in OFF_AXIS if P.get(k, 0.0) != 0]
        if off:
            raise UserError(f"the linear modes are those of the top upright on the axis of a level base: "
                            f"{', '.join(off)} moves its steady motion off it (set it to 0, e.g. «set=plate.tilt=0»)")
        self.model, self.p, self.z_s, self.P = model, p, float(z_s), P
        self.m, self.A, self.C, self.mu = P["m"], P["A"], P["C"], P["mu"]
        h = len(STATES) // 2
        self.Jsym = np.block([[np.zeros((h, h)), np.eye(h)], [-np.eye(h), np.zeros((h, h))]])
        self.full = model.has_function("full_jac") and "p_zeta" in model.part("full").states
        self.source = "full_jac (generated)" if self.full else "transverse_matrix (8-D) and the bounce"
        self.hessian_source = "Jsym^-1 J"
        self._hess = None
        if self.full:
            part = model.part("full")
            self.states = list(part.states)
            self.keep = [self.states.index(s) for s in STATES]
            self._jac = model.fast("full_jac", p)
            x0 = self.state(1.0)
            self.spin_sign = -1.0 if float(model.fast("full_invariants", p)(x0)[1]) < 0 else 1.0
            if hessian == "casadi" and model.has_function("full_energy"):
                import casadi as ca
                x, pp = ca.SX.sym("x", len(self.states)), ca.SX.sym("p", len(p))
                H = ca.Function("energy_hessian", [x, pp], [ca.hessian(model.casadi("full_energy")(x, pp), x)[0]])
                self._hess = H
                self.hessian_source = "full_energy (generated), CasADi's Hessian"
        else:
            self.phi = np.asarray(model.onaxis(self.z_s, p), float)
            self.spin_sign = -1.0            # thesis 3.2.9: omega_3 = -zeta' (the generated convention)

    def state(self, sigma: float) -> np.ndarray:
        x = np.zeros(len(self.states))
        x[self.states.index("z")] = self.z_s
        x[self.states.index("p_zeta")] = self.C * sigma
        return x

    def jacobian(self, sigma: float) -> np.ndarray:
        """The 10x10 Jacobian in STATES order at spin sigma."""
        if self.full:
            n = len(self.states)
            J = np.asarray(self._jac(self.state(sigma)), float).reshape(n, n)
            return J[np.ix_(self.keep, self.keep)]
        ph = self.phi
        T = transverse_matrix(ph[1], ph[2], ph[3], self.m, self.A, self.C, self.mu, sigma)
        # transverse_matrix: (x, y, vartheta, phi, p_x, p_y, p_vartheta, p_phi); STATES has z, p_z
        where = [STATES.index(s) for s in ("x", "y", "vartheta", "phi", "p_x", "p_y", "p_vartheta", "p_phi")]
        J = np.zeros((10, 10))
        J[np.ix_(where, where)] = T
        iz, ipz = STATES.index("z"), STATES.index("p_z")
        J[iz, ipz], J[ipz, iz] = 1 / self.m, -self.mu * ph[3]
        return J

    def hessian(self, sigma: float, J: np.ndarray | None = None) -> np.ndarray:
        """S = Hess H in STATES order (symmetrised)."""
        if self._hess is not None:
            H = np.asarray(self._hess(self.state(sigma), self.p), float)
            S = H[np.ix_(self.keep, self.keep)]
        else:
            S = -self.Jsym @ (self.jacobian(sigma) if J is None else J)
        return 0.5 * (S + S.T)

    def eig(self, sigma: float, d: np.ndarray | None = None):
        """(J, eigenvalues, eigenvectors, rounding bound per eigenvalue): balanced as
        runtime/physics/routes/eigen_route.py `on_imaginary_axis` and with its bound (d: a balancing to
        reuse along a scan)."""
        J = self.jacobian(sigma)
        d = balancing(J) if d is None else d
        Jb = J * np.outer(1.0 / d, d)
        w, Xb = np.linalg.eig(Jb)
        kappa = np.linalg.norm(Xb, axis=0) * np.linalg.norm(np.linalg.inv(Xb), axis=1)
        tol = kappa * (J.shape[0] + 1) * EPS * np.linalg.norm(Jb)
        return J, w, Xb * d[:, None], tol

    def modes(self, sigma: float, krein: bool = True, d: np.ndarray | None = None) -> tuple[Mode, ...]:
        """The five modes at spin sigma, in the order of their signed frequency, bounce first."""
        J, w, X, tol = self.eig(sigma, d)
        S = self.hessian(sigma, J) if krein else None
        i = {s: STATES.index(s) for s in STATES}
        picked = [k for k in range(len(w)) if w[k].imag > tol[k] or (abs(w[k].imag) <= tol[k] and w[k].real > 0)]
        rows = []
        for k in picked:
            v = X[:, k]
            u2 = abs(v[i["x"]]) ** 2 + abs(v[i["y"]]) ** 2
            t2 = abs(v[i["vartheta"]]) ** 2 + abs(v[i["phi"]]) ** 2
            z2 = abs(v[i["z"]]) ** 2
            weight = self.m * (u2 + z2) + self.A * t2
            circ = (self.m * (v[i["x"]] * np.conj(v[i["y"]])).imag
                    + self.A * (v[i["vartheta"]] * np.conj(v[i["phi"]])).imag)
            on_axis = abs(w[k].real) <= tol[k]
            kap = 0 if (S is None or not on_axis) else (1 if float((v.conj() @ S @ v).real) > 0 else -1)
            rows.append(dict(lam=complex(w[k]), freq=abs(float(w[k].imag)), zshare=self.m * z2 / weight,
                             trans=float(self.m * u2 / weight), circ=float(circ), krein=kap))
        bounce = max(rows, key=lambda r: r["zshare"])
        out = [Mode(BOUNCE, bounce["freq"], 0, bounce["krein"], bounce["lam"], bounce["trans"], 0)]
        trans = [r for r in rows if r is not bounce]
        for r in trans:
            r["sense"] = int(np.sign(r["circ"] * self.spin_sign)) or 1
        for r, name in zip(trans, _names(trans)):
            out.append(Mode(name, r["freq"], r["sense"], r["krein"], r["lam"], r["trans"], 1))
        return (out[0], *sorted(out[1:], key=lambda m: m.signed))

    def signed(self, sigma: float, d: np.ndarray | None = None) -> np.ndarray:
        """The signed frequencies at sigma (bounce first, then the transverse ones ascending): what
        runtime/physics/stability/resonances.py tabulates (no Krein signs: cheaper)."""
        return np.array([m.signed for m in self.modes(sigma, krein=False, d=d)])


def _names(rows: list[dict]) -> list[str]:
    """Names of the transverse modes (module docstring): the fastest with the spin the fast
    precession; of the rest the one of negative energy (else the least translational) the slow
    precession; the others translation(+1)/(-1) by their sense."""
    names = [""] * len(rows)
    order = sorted(range(len(rows)), key=lambda k: rows[k]["freq"])
    withspin = [k for k in order if rows[k]["sense"] > 0]
    if withspin:
        names[withspin[-1]] = FAST
    rest = [k for k in order if not names[k]]
    neg = [k for k in rest if rows[k]["krein"] < 0]
    if rest:
        slow = neg[0] if len(neg) == 1 else min(rest, key=lambda k: rows[k]["trans"])
        names[slow] = SLOW
    for k in range(len(rows)):
        if not names[k]:
            names[k] = f"translation({'+' if rows[k]['sense'] > 0 else '-'}1)"
    seen: dict[str, int] = {}
    for k, n in enumerate(names):        # off the window two may share a name: number them
        seen[n] = seen.get(n, 0) + 1
        if seen[n] > 1:
            names[k] = f"{n} #{seen[n]}"
    return names


@dataclass(frozen=True, repr=False)
class Modes:
    """The linear modes at one spin (rad/s): `modes` (Mode, bounce first, then by signed frequency),
    `stable` (all on the imaginary axis), `z_s` (m), `window` (the spin interval or None),
    `source` (the Jacobian's), `hessian_source`, `hessian_residual` (|Jsym S - J| / |J|)."""

    spin: float
    z_s: float
    modes: tuple[Mode, ...]
    stable: bool
    window: tuple[float, float] | None
    source: str
    hessian_source: str
    hessian_residual: float
    units: Units = field(default=_SI, compare=False)

    @classmethod
    def of(cls, model, spin: float, z_s: float, window=None, p=None, hessian: str = "casadi") -> Modes:
        spin = spin_rate(spin)      # the one check of a positive spin (runtime/ui/validate.py)
        ls = LinearSystem(model, z_s, p, hessian)
        modes = ls.modes(float(spin))
        J = ls.jacobian(float(spin))
        res = float(np.linalg.norm(ls.Jsym @ ls.hessian(float(spin)) - J) / np.linalg.norm(J))
        return cls(float(spin), float(z_s), modes, all(m.krein != 0 for m in modes),
                   None if window is None else tuple(window), ls.source, ls.hessian_source, res,
                   Units.of_scene(model.scene))

    @classmethod
    def at(cls, model, spin: float, height: float | None = None) -> Modes:
        """The modes of the model's top (with `height`: the top that hovers there, as
        runtime/physics/stability/analysis.py `stability_of` takes it) at its hover height."""
        from levitron.runtime.physics.stability.analysis import stability_of
        spin = spin_rate(spin)      # refused before the analysis
        res = stability_of(model, height=height, eigen=False)
        if not res.z_s:
            raise UserError(f"no linear modes: the top has no stable hover height ({res.reason})")
        p = model.with_params({"m": res.mass}) if res.mass else model.p
        return cls.of(model, spin, res.z_s, res.spin_interval, p)

    def __getitem__(self, name: str) -> Mode:
        for m in self.modes:
            if m.name == name:
                return m
        raise KeyError(f"{name!r}: the modes are {[m.name for m in self.modes]}")

    def as_json(self) -> dict:
        return {"spin": self.spin, "z_s": self.z_s, "stable": self.stable,
                "modes": [m.as_json() for m in self.modes], "source": self.source,
                "hessian_source": self.hessian_source, "hessian_residual": self.hessian_residual}

    @property
    def message(self) -> str:
        u = self.units
        inside = "" if self.window is None else (
            " (inside the spin interval)" if self.window[0] < self.spin < self.window[1] else
            " (outside the spin interval: a pair leaves the imaginary axis)" if not self.stable else "")
        return f"{len(self.modes)} linear modes at spin {u.value(self.spin, 'rad/s', 6)}{inside}"

    def lines(self, units: Units | None = None) -> list[str]:
        """One plain line a mode: name, frequency, sense, energy sign."""
        u = units or self.units
        out = []
        for m in self.modes:
            sense = {1: "with the spin", -1: "against the spin", 0: "vertical"}[m.sense]
            energy = {1: "energy +", -1: "energy - (Krein)"}.get(m.krein) or \
                f"unstable, grows at {u.value(m.growth, '1/s', 3)}"
            out.append(f"  {m.name}: {u.rate(m.frequency)}, {sense}, {energy}, "
                       f"translation {sig(m.translation, 2)}")
        return out

    def __repr__(self) -> str:
        inner = ", ".join(f"{m.name}={sig(m.signed, 5)}" for m in self.modes)
        return f"Modes(spin={sig(self.spin, 6)} {self.units.unit('rad/s')}, {inner}, stable={self.stable})"
