"""Rotations, the body angular velocity and the kinetic energy (thesis 2.1, 3.2.2-3.2.10).

Two coordinate sets, both built from the thesis's own matrices:

* "euler-zxz" (thesis eqs. 2.1.6-2.1.9): R = R3(psi) R2(theta) R1(phi) maps space components to
  body components (Goldstein's passive convention). The symmetry axis in space is n = R^T e_z.
  Singular at theta = 0, i.e. for the upright top that the levitron is.
* "tait-bryan" (thesis eqs. 3.2.2-3.2.5, after Dullin): R = Rx(phi) Ry(vartheta) Rz(zeta) maps
  body components to space components; n = R e_z = (sin vth, sin phi cos vth, cos phi cos vth)
  (the direction cosines of thesis eq. 3.2.11). Regular at the upright top; singular only at
  vartheta = +-pi/2.

In both, the body angular velocity is read off the skew matrix Omega = R_bs^T dR_bs/dt with
Omega = hat(omega) (thesis eqs. 3.2.7-3.2.9), never typed in.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from .symbols import A, C, m
from .trig import trig_reduce

c, s = sp.cos, sp.sin


def R1(a):
    """Thesis eq. 2.1.6 (rotation about z, passive)."""
    return sp.Matrix([[c(a), s(a), 0], [-s(a), c(a), 0], [0, 0, 1]])


def R2(a):
    """Thesis eq. 2.1.7 (rotation about the line of nodes, passive)."""
    return sp.Matrix([[1, 0, 0], [0, c(a), s(a)], [0, -s(a), c(a)]])


R3 = R1  # thesis eq. 2.1.8 has the same form as 2.1.6


def Rx(a):
    """Thesis eq. 3.2.3."""
    return sp.Matrix([[1, 0, 0], [0, c(a), s(a)], [0, -s(a), c(a)]])


def Ry(a):
    """Thesis eq. 3.2.4."""
    return sp.Matrix([[c(a), 0, s(a)], [0, 1, 0], [-s(a), 0, c(a)]])


def Rz(a):
    """Thesis eq. 3.2.5."""
    return sp.Matrix([[c(a), s(a), 0], [-s(a), c(a), 0], [0, 0, 1]])


def vee(W: sp.Matrix) -> sp.Matrix:
    """omega from a skew matrix W = hat(omega) = omega_1 S1 + omega_2 S2 + omega_3 S3 (thesis 3.2.8)."""
    return sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])


@dataclass(frozen=True)
class Rotation:
    """A parametrisation of the top's orientation.

    angles, rates:  the three angles and their time derivatives (plain symbols).
    R_bs:           body -> space rotation matrix.
    omega:          body-frame angular velocity, linear in the rates.
    n:              the symmetry axis in space components, n = R_bs e_z.
    """

    name: str
    angles: tuple[sp.Symbol, sp.Symbol, sp.Symbol]
    rates: tuple[sp.Symbol, sp.Symbol, sp.Symbol]
    R_bs: sp.Matrix
    omega: sp.Matrix
    n: sp.Matrix
    keep: str = "cos"   # which of sin/cos trig_reduce keeps (see derive/trig.py)


def time_derivative(M: sp.Matrix, angles, rates) -> sp.Matrix:
    """dM/dt for M(angles) along the rates: sum_i dM/dq_i qdot_i."""
    return sum((M.diff(q) * qd for q, qd in zip(angles, rates)), sp.zeros(*M.shape))


def body_angular_velocity(R_bs: sp.Matrix, angles, rates, keep: str = "cos") -> sp.Matrix:
    """omega_body = vee(R_bs^T dR_bs/dt) (thesis eqs. 3.2.7-3.2.9)."""
    W = (R_bs.T * time_derivative(R_bs, angles, rates)).applyfunc(lambda e: trig_reduce(e, angles, keep))
    assert W + W.T == sp.zeros(3, 3), "R^T dR/dt must be skew"
    return vee(W).applyfunc(sp.expand)


def euler_zxz() -> Rotation:
    """Euler angles z-x-z (thesis eqs. 2.1.5-2.1.10): R_sb = R3(psi) R2(theta) R1(phi) (2.1.9)."""
    phi, theta, psi = sp.symbols("phi theta psi", real=True)
    rates = sp.symbols("phi_dot theta_dot psi_dot", real=True)
    R_sb = R3(psi) * R2(theta) * R1(phi)
    R_bs = R_sb.T
    omega = body_angular_velocity(R_bs, (phi, theta, psi), rates, keep="sin")
    n = R_bs * sp.Matrix([0, 0, 1])
    return Rotation("euler-zxz", (phi, theta, psi), rates, R_bs, omega, n, keep="sin")


def tait_bryan() -> Rotation:
    """Dullin's singularity-free angles (thesis eqs. 3.2.2-3.2.9): R_bs = Rx(phi) Ry(vth) Rz(zeta)."""
    phi, vth, zeta = sp.symbols("phi vartheta zeta", real=True)
    rates = sp.symbols("phi_dot vartheta_dot zeta_dot", real=True)
    R_bs = Rx(phi) * Ry(vth) * Rz(zeta)
    omega = body_angular_velocity(R_bs, (phi, vth, zeta), rates)
    n = R_bs * sp.Matrix([0, 0, 1])
    return Rotation("tait-bryan", (phi, vth, zeta), rates, R_bs, omega, n)


ROTATIONS = {"euler-zxz": euler_zxz, "tait-bryan": tait_bryan}


def kinetic_energy(rot: Rotation, velocities) -> sp.Expr:
    """T = m v^2 / 2 + omega^T I omega / 2 with I = diag(A, A, C) (thesis eqs. 2.1.11-2.1.14)."""
    I = sp.diag(A, A, C)
    v = sp.Matrix(velocities)
    T_rot = (rot.omega.T * I * rot.omega)[0, 0] / 2
    return m * (v.T * v)[0, 0] / 2 + sp.collect(trig_reduce(T_rot, rot.angles, rot.keep), rot.rates)
