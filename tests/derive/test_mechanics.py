"""Thesis 2.2.15 and 2.3: potential energy, Lagrangian, Legendre transform, Hamilton's equations."""
import sympy as sp

from levitron.derive import field as F
from levitron.derive.mechanics import hamiltonian_system, potential_energy
from levitron.derive.symbols import A, C, Phi, X, Y, Z, g, m, mu
from levitron.derive.zxz_form import full_angle

c, s = sp.cos, sp.sin


def _zero(e):
    """e == 0, with sin(theta/2) of the z-x-z chart's factored forms (derive/zxz_form.py) written
    through cos(theta) first (sympy's simplify does not see the half angle's identity)."""
    return sp.simplify(full_angle(e, sp.Symbol("theta", real=True))) == 0


def euler():
    return hamiltonian_system("euler-zxz", 2)


def test_eq_2_3_1_lagrangian():
    sysm = euler()
    phi, theta, psi = sysm.rotation.angles
    xd, yd, zd, dphi, dtheta, dpsi = sysm.qdot
    B = F.field(2)
    n = sysm.rotation.n
    thesis_T = (m * (xd**2 + yd**2 + zd**2) + A * (dtheta**2 + dphi**2 * s(theta)**2)
                + C * (dpsi + dphi * c(theta))**2) / 2
    L = thesis_T + mu * (n.T * B)[0, 0] - m * g * Z
    assert _zero(sysm.L - L)


def test_eq_2_3_2_to_2_3_7_momenta():
    sysm = euler()
    phi, theta, psi = sysm.rotation.angles
    xd, yd, zd, dphi, dtheta, dpsi = sysm.qdot
    expected = [m * xd, m * yd, m * zd,
                A * dphi * s(theta)**2 + C * (dpsi + dphi * c(theta)) * c(theta),   # p_phi (2.3.7)
                A * dtheta,                                                      # p_theta (2.3.5)
                C * (dpsi + dphi * c(theta))]                                    # p_psi (2.3.6)
    for got, want in zip(sysm.momenta, expected):
        assert _zero(got - want)


def test_eq_2_3_8_velocities():
    sysm = euler()
    phi, theta, psi = sysm.rotation.angles
    px, py, pz, pphi, ptheta, ppsi = sysm.p
    expected = [px / m, py / m, pz / m,
                (pphi - ppsi * c(theta)) / (A * s(theta)**2),
                ptheta / A,
                ppsi / C - (pphi * c(theta) - ppsi * c(theta)**2) / (A * s(theta)**2)]
    for got, want in zip(sysm.qdot_of_p, expected):
        assert _zero(got - want)


def test_eq_2_3_9_hamiltonian_by_legendre_transform():
    sysm = euler()
    phi, theta, psi = sysm.rotation.angles
    px, py, pz, pphi, ptheta, ppsi = sysm.p
    U = potential_energy(sysm.rotation, F.field(2))
    thesis = ((px**2 + py**2 + pz**2) / (2 * m) + ptheta**2 / (2 * A) + ppsi**2 / (2 * C)
              + (pphi - ppsi * c(theta))**2 / (2 * A * s(theta)**2) + U)
    assert _zero(sysm.H - thesis)
    # the Legendre identity: H(q, dL/dqdot) + L(q, qdot) = p . qdot on the velocity side
    back = sysm.H.xreplace(dict(zip(sysm.p, sysm.momenta)))
    assert _zero(back + sysm.L - (sysm.momenta.T * sp.Matrix(sysm.qdot))[0, 0])


def test_eq_2_3_14_p_theta_dot():
    sysm = euler()
    phi, theta, psi = sysm.rotation.angles
    px, py, pz, pphi, ptheta, ppsi = sysm.p
    dU = sp.diff(sysm.U, theta)
    thesis = (-ppsi * (pphi - ppsi * c(theta)) / (A * s(theta))
              + c(theta) * (pphi - ppsi * c(theta))**2 / (A * s(theta)**3) - dU)
    assert _zero(sysm.rhs[10] - thesis)


def test_eq_2_2_15_erratum_moment_direction():
    """Thesis 2.2.1/2.2.15 take the moment along R e_z = (sin psi sin th, cos psi sin th, cos th): the
    space z axis in body components. The moment points along the body axis, in space components
    n = R^T e_z = (sin th sin phi, -sin th cos phi, cos th). With the thesis's form the potential
    depends on the spin angle psi, so L.n = p_psi would not be conserved (2.3.15 != 0) while
    2.3.16 claims p_phi conserved; with n it is the other way round, as symmetry demands."""
    sysm = euler()
    phi, theta, psi = sysm.rotation.angles
    n_thesis = sp.Matrix([s(theta) * s(phi), -s(theta) * c(phi), c(theta)])
    assert (sysm.rotation.n - n_thesis).applyfunc(sp.simplify) == sp.zeros(3, 1)
    assert sp.diff(sysm.U, psi) == 0                       # so p_psi = L.n is conserved
    assert sysm.rhs[11] == 0                                 # p_psi dot = 0 (the corrected 2.3.15)
    assert not _zero(sysm.rhs[9])                            # p_phi dot != 0 off the axis (2.3.16 wrong)
    B = F.field(2)
    thesis_n = sp.Matrix([s(psi) * s(theta), c(psi) * s(theta), c(theta)])
    U_thesis = m * g * Z - mu * (thesis_n.T * B)[0, 0]
    assert not _zero(sp.diff(U_thesis, psi))                # the thesis's U depends on the spin angle
    # What is conserved instead of p_phi: J_z = x p_y - y p_x + p_phi; {J_z, H} = 0.
    x, y = X, Y
    px, py = sysm.p[0], sysm.p[1]
    Jz = x * py - y * px + sysm.p[3]
    bracket = sum(sp.diff(Jz, q) * sp.diff(sysm.H, p) - sp.diff(Jz, p) * sp.diff(sysm.H, q)
                  for q, p in zip(sysm.q, sysm.p))
    assert _zero(sp.expand(bracket))


def test_eq_2_3_10_to_2_3_13_hamilton_equations():
    """qdot = dH/dp reproduces 2.3.8; pdot_{x,y,z} = -dU/d{x,y,z} (2.3.11-2.3.13)."""
    for coords in ("euler-zxz", "tait-bryan"):
        sysm = hamiltonian_system(coords, 2)
        for i in range(6):
            assert _zero(sysm.rhs[i] - sysm.qdot_of_p[i])
        for i, v in enumerate((X, Y, Z)):
            assert sp.expand(sysm.rhs[6 + i] + sp.diff(sysm.U, v)) == 0


def test_tait_bryan_spin_momentum_is_conserved():
    """In Dullin's angles p_zeta = C (zeta_dot + phi_dot sin vth) = -L.n is conserved: U has no zeta."""
    sysm = hamiltonian_system("tait-bryan", 2)
    assert sysm.rhs[11] == 0
    assert Phi(1, Z) in sysm.H.atoms(Phi)
