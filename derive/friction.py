"""Air friction: a Rayleigh dissipation function and its generalised forces in canonical variables.

The thesis's top is conservative (thesis 2.3); a real top slows down in air. The friction is
modelled by Rayleigh's dissipation function, quadratic in the velocities,

    F = 1/2 k_spin C omega_3^2 + 1/2 k_tilt A (omega_1^2 + omega_2^2) + 1/2 k_trans m |v|^2,

with omega the body angular velocity (derive/kinematics.py, thesis eqs. 3.2.7-3.2.9 / 2.1.10) and
v the velocity of the centre of mass. The rates k = 1/tau are the reciprocal e-folding times of a
free top in still air (scene keys top.spin_decay_time, top.tilt_decay_time,
top.translation_decay_time): with F alone, C d(omega_3)/dt = -k_spin C omega_3, the transverse
angular velocity and the velocity decay as exp(-k_tilt t) and exp(-k_trans t).

The generalised forces Q_j = -dF/d(qdot_j) enter Hamilton's equations as

    dq/dt = dH/dp,    dp/dt = -dH/dq + Q(q, qdot(q, p)),

with qdot(q, p) the Legendre map of derive/mechanics.py (thesis eq. 2.3.8). Since F is
homogeneous of degree 2 in qdot, dH/dt = Q.qdot = -2F: the energy balance that tests check.
The magnetic torque mu n x B is perpendicular to the axis n, so omega_3 decays exactly as
exp(-k_spin t) along every trajectory (a test checks this too).
"""
from __future__ import annotations

import sympy as sp

from .mechanics import HamiltonianSystem
from .symbols import A, C, m
from .trig import trig_reduce

k_spin, k_tilt, k_trans = sp.symbols("k_spin k_tilt k_trans", real=True)
RATES = (k_spin, k_tilt, k_trans)     # the names scene/keys.py's FRICTION_KEYS resolve to


def body_rates(system: HamiltonianSystem) -> sp.Matrix:
    """omega (body frame) in canonical variables: omega(q, qdot(q, p)) (thesis eqs. 3.2.9, 2.3.8)."""
    rot = system.rotation
    sub = dict(zip(system.qdot, system.qdot_of_p))
    simp = lambda e: trig_reduce(sp.expand(e), rot.angles, rot.keep)  # noqa: E731
    return rot.omega.xreplace(sub).applyfunc(simp)


def rayleigh(system: HamiltonianSystem) -> sp.Expr:
    """F(q, qdot), the Rayleigh dissipation function of the module docstring."""
    w = system.rotation.omega
    v = sp.Matrix(system.qdot[:3])
    return (k_spin * C * w[2] ** 2 + k_tilt * A * (w[0] ** 2 + w[1] ** 2)
            + k_trans * m * (v.T * v)[0, 0]) / 2


def generalised_forces(system: HamiltonianSystem) -> sp.Matrix:
    """Q_j = -dF/d(qdot_j) at qdot = qdot(q, p), one per coordinate, in the order of system.q.

    F = 1/2 omega^T K I omega + ..., omega = W(q) qdot, so Q_angles = -W^T K I omega and
    Q_position = -k_trans m v = -k_trans p_position; omega is written through body_rates."""
    F = rayleigh(system)
    w = body_rates(system)
    rot = system.rotation
    sub_w = dict(zip(sp.symbols("w1:4", real=True), w))
    dF = sp.Matrix([sp.diff(F, qd) for qd in system.qdot])
    # dF/dqdot is linear in omega and v: write it in omega, v, then substitute the canonical forms
    wsym = tuple(sub_w)
    W = rot.omega.jacobian(sp.Matrix(rot.rates))
    K_I = sp.diag(k_tilt * A, k_tilt * A, k_spin * C)
    Q_ang = -(W.T * K_I * sp.Matrix(wsym)).xreplace(sub_w)
    Q_pos = sp.Matrix([-k_trans * p for p in system.p[:3]])
    Q = sp.Matrix.vstack(Q_pos, Q_ang.applyfunc(lambda e: trig_reduce(sp.expand(e), rot.angles, rot.keep)))
    # the same forces straight from F (a second route, exact): -dF/dqdot at qdot(q, p)
    direct = (-dF).xreplace(dict(zip(system.qdot, system.qdot_of_p)))
    check = (Q - direct).applyfunc(lambda e: trig_reduce(sp.expand(e), rot.angles, rot.keep))
    assert check == sp.zeros(len(system.q), 1), "generalised forces: the two routes disagree"
    return Q


def dissipated_power(system: HamiltonianSystem) -> sp.Expr:
    """2F = -Q.qdot in canonical variables: the rate at which friction removes energy, -dH/dt."""
    w = body_rates(system)
    p_pos = sp.Matrix(system.p[:3])
    return (k_spin * C * w[2] ** 2 + k_tilt * A * (w[0] ** 2 + w[1] ** 2)
            + k_trans * (p_pos.T * p_pos)[0, 0] / m)


def dissipative_rhs(system: HamiltonianSystem) -> sp.Matrix:
    """Hamilton's equations with the generalised forces added to the momentum rows."""
    n = len(system.q)
    Q = generalised_forces(system)
    return sp.Matrix([system.rhs[i] for i in range(n)] + [system.rhs[n + i] + Q[i] for i in range(n)])
