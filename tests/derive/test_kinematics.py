"""Thesis 2.1 and 3.2.2-3.2.10: rotations, angular velocity, kinetic energy (derived, not typed in)."""
import sympy as sp

from levitron.derive.kinematics import R1, R2, R3, Rx, Ry, Rz, euler_zxz, kinetic_energy, tait_bryan, vee
from levitron.derive.symbols import A, C, m

c, s = sp.cos, sp.sin


def _zero(expr):
    return sp.simplify(sp.expand_trig(expr)) == 0


def _identically_zero(expr) -> bool:
    """sin and cos written as exponentials and multiplied out give exactly 0: a proof that expr is
    zero, as simplify(expr) == 0 is, in a tenth of simplify's time on the matrices of 3.2.7."""
    return sp.expand(expr.rewrite(sp.exp)) == 0


def test_eq_2_1_9_rotation_product():
    phi, theta, psi = euler_zxz().angles
    R = R3(psi) * R2(theta) * R1(phi)
    thesis = sp.Matrix([
        [c(psi) * c(phi) - c(theta) * s(phi) * s(psi), c(psi) * s(phi) + c(theta) * c(phi) * s(psi), s(psi) * s(theta)],
        [-s(psi) * c(phi) - c(theta) * s(phi) * c(psi), -s(psi) * s(phi) + c(theta) * c(phi) * c(psi),
         c(psi) * s(theta)],
        [s(theta) * s(phi), -s(theta) * c(phi), c(theta)]])
    assert (R - thesis).applyfunc(sp.expand) == sp.zeros(3, 3)
    assert (R * R.T).applyfunc(sp.simplify) == sp.eye(3)


def test_eq_2_1_10_body_angular_velocity():
    rot = euler_zxz()
    phi, theta, psi = rot.angles
    dphi, dtheta, dpsi = rot.rates
    thesis = sp.Matrix([dphi * s(theta) * s(psi) + dtheta * c(psi),
                        dphi * c(psi) * s(theta) - dtheta * s(psi),
                        dphi * c(theta) + dpsi])
    assert (rot.omega - thesis).applyfunc(sp.expand) == sp.zeros(3, 1)


def test_eq_2_1_10_erratum_omega_psi_is_already_in_body_frame():
    """Thesis 2.1.10 writes omega' = R w_phi + R w_theta + R w_psi; w_psi = (0,0,psi_dot) is along the
    body axis already, so R w_psi is wrong (it is not (0, 0, psi_dot)); the result the thesis
    prints is R w_phi + R w_theta + w_psi, which is what the derivation gives."""
    rot = euler_zxz()
    phi, theta, psi = rot.angles
    dphi, dtheta, dpsi = rot.rates
    R = R3(psi) * R2(theta) * R1(phi)
    w_phi = sp.Matrix([0, 0, dphi])
    w_theta = sp.Matrix([dtheta * c(phi), dtheta * s(phi), 0])       # thesis eq. 2.1.5
    w_psi = sp.Matrix([0, 0, dpsi])
    as_printed = R * w_phi + R * w_theta + R * w_psi
    corrected = R * w_phi + R * w_theta + w_psi
    assert (corrected - rot.omega).applyfunc(sp.simplify) == sp.zeros(3, 1)
    assert (as_printed - rot.omega).applyfunc(sp.simplify) != sp.zeros(3, 1)


def test_eq_2_1_14_kinetic_energy():
    rot = euler_zxz()
    _phi, theta, _psi = rot.angles
    dphi, dtheta, dpsi = rot.rates
    v = sp.symbols("u v w")
    T = kinetic_energy(rot, v)
    thesis = (m * (v[0]**2 + v[1]**2 + v[2]**2) + A * (dtheta**2 + dphi**2 * s(theta)**2)
              + C * (dpsi + dphi * c(theta))**2) / 2
    assert _zero(T - thesis)


def test_eq_3_2_7_skew_matrix_and_3_2_9_angular_velocity():
    rot = tait_bryan()
    phi, vth, zeta = rot.angles
    dphi, dvth, dzeta = rot.rates
    R = Rx(phi) * Ry(vth) * Rz(zeta)
    Rdot = sum((R.diff(q) * qd for q, qd in zip(rot.angles, rot.rates)), sp.zeros(3, 3))
    W = R.T * Rdot
    thesis_W = sp.Matrix([
        [0, dphi * s(vth) + dzeta, -dphi * s(zeta) * c(vth) + dvth * c(zeta)],
        [-dphi * s(vth) - dzeta, 0, dvth * s(zeta) + dphi * c(zeta) * c(vth)],
        [dphi * s(zeta) * c(vth) - dvth * c(zeta), -dvth * s(zeta) - dphi * c(zeta) * c(vth), 0]])
    assert all(map(_identically_zero, W - thesis_W))
    thesis_omega = sp.Matrix([-dvth * s(zeta) - dphi * c(zeta) * c(vth),
                              -dphi * s(zeta) * c(vth) + dvth * c(zeta),
                              -dphi * s(vth) - dzeta])
    assert all(map(_identically_zero, vee(W) - thesis_omega))
    assert (rot.omega - thesis_omega).applyfunc(sp.simplify) == sp.zeros(3, 1)


def test_eq_3_2_10_rotational_energy_erratum():
    """Thesis 3.2.10 prints A (zeta_dot^2 + phi_dot^2 cos^2 vth); the derivation gives vartheta_dot^2
    in place of zeta_dot^2 (a typo: zeta_dot already enters through the C term)."""
    rot = tait_bryan()
    _phi, vth, _zeta = rot.angles
    dphi, dvth, dzeta = rot.rates
    T = kinetic_energy(rot, (0, 0, 0))
    correct = ((dphi * s(vth) + dzeta)**2 * C + (dvth**2 + dphi**2 * c(vth)**2) * A) / 2
    as_printed = ((dphi * s(vth) + dzeta)**2 * C + (dzeta**2 + dphi**2 * c(vth)**2) * A) / 2
    assert _zero(T - correct)
    assert not _zero(T - as_printed)


def test_eq_3_2_11_axis_direction():
    """n = R e_z = (sin vth, sin phi cos vth, cos phi cos vth), the direction cosines of thesis 3.2.11."""
    rot = tait_bryan()
    phi, vth, _ = rot.angles
    assert (rot.n - sp.Matrix([s(vth), s(phi) * c(vth), c(phi) * c(vth)])).applyfunc(sp.simplify) == sp.zeros(3, 1)


def test_axis_follows_angular_velocity():
    """Kinematic identity for both sets: dn/dt = omega_space x n with omega_space = R_bs omega."""
    for rot in (euler_zxz(), tait_bryan()):
        ndot = sum((rot.n.diff(q) * qd for q, qd in zip(rot.angles, rot.rates)), sp.zeros(3, 1))
        w_space = rot.R_bs * rot.omega
        assert (ndot - w_space.cross(rot.n)).applyfunc(sp.simplify) == sp.zeros(3, 1), rot.name


def test_eq_2_1_6_to_2_1_8_and_3_2_3_to_3_2_5_rotation_matrices():
    """The thesis's elementary matrices are proper rotations, each about the axis it names
    (the axis is the matrix's fixed vector)."""
    a = sp.Symbol("a", real=True)
    for R, axis in ((R1(a), (0, 0, 1)), (R2(a), (1, 0, 0)), (R3(a), (0, 0, 1)),
                    (Rx(a), (1, 0, 0)), (Ry(a), (0, 1, 0)), (Rz(a), (0, 0, 1))):
        assert (R * R.T).applyfunc(sp.simplify) == sp.eye(3)
        assert sp.simplify(R.det()) == 1
        assert R * sp.Matrix(axis) == sp.Matrix(axis)


def test_eq_3_2_2_composition_is_body_to_space():
    """R = Rx(phi) Ry(vth) Rz(zeta) (thesis 3.2.2) maps body to space: the spin angle zeta does not
    move the symmetry axis n = R e_z, while phi and vth do."""
    rot = tait_bryan()
    phi, vth, zeta = rot.angles
    assert rot.n.diff(zeta) == sp.zeros(3, 1)
    assert rot.n.diff(phi) != sp.zeros(3, 1) and rot.n.diff(vth) != sp.zeros(3, 1)
    assert rot.n.subs({phi: 0, vth: 0}) == sp.Matrix([0, 0, 1])
