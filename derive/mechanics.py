"""Lagrangian, Legendre transform and Hamilton's equations of the levitron (thesis 2.3).

L = T - U with T from derive/kinematics.py (thesis eq. 2.1.14) and the potential energy
U = m g z - mu n.B(r) (thesis eq. 2.2.1, with n the symmetry axis in space components; see
docs/errata.md for why n = R_bs e_z and not the thesis's R e_z).
On a tilted base (scene key plate.tilt) gravity is no longer along -e_z of the plate's
frame: g_vec = g (sin t cos a, sin t sin a, -cos t) with t the tilt and a its azimuth (the downhill
direction), so m g z becomes -m g_vec.r = m g (z cos t - (x cos a + y sin a) sin t); t = 0 gives
thesis eq. 2.2.1 back. The axial symmetry is broken (L_z is no longer conserved), L.n still is.
A magnet whose centre sits a distance d along the axis from the centre of mass (scene key
top.moment_offset) feels the field at r + d n: U = m g z - mu n.B(r + d n); d = 0 gives eq. 2.2.1.
A magnet whose moment is tilted by b from the symmetry axis (scene key top.moment_tilt), fixed in
the body so that it turns with the spin, is m = mu (cos b n + sin b e1) with e1 = R_bs e_x the
body's first transverse axis in space components: U = m g z - m.B(r + d n); b = 0 gives eq. 2.2.1.
The top's inertia stays symmetric, but the potential now depends on the spin angle: L.n is no
longer conserved (the torque m x B has a component along n), L_z still is over a level base.
The momenta p = dL/dqdot (thesis eqs. 2.3.2-2.3.7) are solved for the velocities (2.3.8), and
H = p.qdot - L (2.3.9) is formed by that actual Legendre transform; Hamilton's equations
qdot = dH/dp, pdot = -dH/dq (2.3.10-2.3.16) follow by differentiation.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from . import field as fieldmod
from .kinematics import ROTATIONS, Rotation, kinetic_energy
from .symbols import X, Y, Z, base_tilt, base_tilt_azimuth, g, m, moment_offset, moment_tilt, mu
from .trig import trig_reduce
from .zxz_form import cancellation_free


@dataclass(frozen=True)
class HamiltonianSystem:
    """The full 12-D model in one coordinate set.

    q, qdot, p:  coordinates (x, y, z, 3 angles), velocities, conjugate momenta.
    L, H, U:     Lagrangian, Hamiltonian, potential energy (Phi(k, z) kept abstract).
    momenta:     dL/dqdot in terms of (q, qdot)           (thesis eqs. 2.3.2-2.3.7)
    qdot_of_p:   the velocities in terms of (q, p)         (thesis eq. 2.3.8)
    rhs:         d(q, p)/dt = (dH/dp, -dH/dq)              (thesis eqs. 2.3.10-2.3.16)
    """

    rotation: Rotation
    order: int
    q: tuple
    qdot: tuple
    p: tuple
    L: sp.Expr
    U: sp.Expr
    momenta: sp.Matrix
    qdot_of_p: sp.Matrix
    H: sp.Expr
    rhs: sp.Matrix

    @property
    def state(self) -> tuple:
        return tuple(self.q) + tuple(self.p)

    @property
    def state_names(self) -> list[str]:
        return [str(v) for v in self.state]


def gravity_height(tilted: bool = False) -> sp.Expr:
    """-g_vec.r / g: the height in the field of gravity, z on a level base (thesis eq. 2.2.1), and
    z cos t - (x cos a + y sin a) sin t on a base tilted by t towards azimuth a (module docstring)."""
    if not tilted:
        return Z
    t, a = base_tilt, base_tilt_azimuth
    return Z * sp.cos(t) - (X * sp.cos(a) + Y * sp.sin(a)) * sp.sin(t)


def potential_energy(rot: Rotation, B: sp.Matrix, tilted: bool = False, offset: bool = False,
                     askew: bool = False) -> sp.Expr:
    """U = m g z - mu n.B (thesis eq. 2.2.1 with n = R_bs e_z); on a tilted base z is
    `gravity_height`; with `offset` B is taken at the magnet's centre r + d n; with `askew` the
    moment's direction is cos b n + sin b R_bs e_x, b = moment_tilt (module docstring)."""
    if offset:
        d, n = moment_offset, rot.n
        B = B.xreplace({X: X + d * n[0], Y: Y + d * n[1], Z: Z + d * n[2]})
    direction = rot.n
    if askew:
        e1 = rot.R_bs * sp.Matrix([1, 0, 0])
        direction = sp.cos(moment_tilt) * rot.n + sp.sin(moment_tilt) * e1
    return m * g * gravity_height(tilted) - mu * (direction.T * B)[0, 0]


def legendre(L: sp.Expr, q, qdot, p, keep: str = "cos") -> tuple[sp.Matrix, sp.Matrix, sp.Expr]:
    """Momenta, velocities in terms of momenta, and H = p.qdot - L (thesis eqs. 2.3.2-2.3.9).

    L is quadratic in qdot (L = qdot^T M(q) qdot / 2 + ...), so p = dL/dqdot is linear in qdot and
    is solved exactly; the result is substituted back, not assumed.
    """
    momenta = sp.Matrix([sp.diff(L, v) for v in qdot])
    M = momenta.jacobian(qdot)
    assert all(sp.diff(e, v) == 0 for e in M for v in qdot), "L must be quadratic in the velocities"
    rest = (momenta - M * sp.Matrix(qdot)).applyfunc(sp.expand)
    assert rest == sp.zeros(len(qdot), 1), "no gyroscopic (velocity-linear) terms expected in L"
    angles = [a for a in q if a.free_symbols & set(q) and a not in (X, Y, Z)]
    simp = lambda e: trig_reduce(e, angles, keep)  # noqa: E731
    Minv = (M.adjugate() / M.det()).applyfunc(simp)
    qdot_of_p = (Minv * sp.Matrix(p)).applyfunc(sp.expand)
    H_raw = (sp.Matrix(p).T * qdot_of_p)[0, 0] - L.xreplace(dict(zip(qdot, qdot_of_p)))
    return momenta, qdot_of_p, _quadratic_form(H_raw, p, simp)


def _quadratic_form(H: sp.Expr, p, simp) -> sp.Expr:
    """Write H as sum_ij c_ij p_i p_j + U with every coefficient simplified on its own."""
    poly = sp.Poly(sp.expand(H), *p)
    terms = []
    for powers, coeff in sorted(poly.terms(), key=lambda t: t[0], reverse=True):
        mono = sp.Mul(*[pi**k for pi, k in zip(p, powers)])
        terms.append((simp(coeff) if any(powers) else coeff) * mono)
    return sp.Add(*terms)


@lru_cache(maxsize=None)
def hamiltonian_system(coords: str = "tait-bryan", order: int = 2,
                       B: sp.ImmutableMatrix | None = None,
                       tilted: bool = False, offset: bool = False,
                       askew: bool = False) -> HamiltonianSystem:
    """The full model in `coords` ("tait-bryan" or "euler-zxz").

    The field is the axisymmetric expansion to `order` (thesis eq. 2.2.7, Phi_k kept abstract) unless
    an exact 3-D field B(x, y, z) is given (a plate without axial symmetry, e.g. a rectangle).
    `tilted`: gravity along the tilted vector of the module docstring (parameters base_tilt,
    base_tilt_azimuth); `offset`: the moment at r + d n (parameter moment_offset); `askew`: the
    moment tilted by moment_tilt from the axis, fixed in the body.
    """
    rot = ROTATIONS[coords]()
    pos = (X, Y, Z)
    vel = sp.symbols("x_dot y_dot z_dot", real=True)
    q = pos + tuple(rot.angles)
    qdot = tuple(vel) + tuple(rot.rates)
    p = tuple(sp.Symbol(f"p_{v}", real=True) for v in q)
    T = kinetic_energy(rot, vel)
    U = potential_energy(rot, fieldmod.field(order) if B is None else sp.Matrix(B), tilted, offset, askew)
    L = T - U
    momenta, qdot_of_p, H = legendre(L, q, qdot, p, rot.keep)
    rhs = sp.Matrix([sp.diff(H, pi) for pi in p] + [-sp.diff(H, qi) for qi in q])
    if coords == "euler-zxz":        # the same H and rhs, written so that nothing cancels at theta ~ 0
        H, rhs = cancellation_free(q, p, H, rhs)
    return HamiltonianSystem(rot, order, q, qdot, p, L, U, momenta, qdot_of_p, H, rhs)
