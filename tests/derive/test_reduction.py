"""Thesis 3.2.1 and 3.2.12: the invariant set and the reduced 4-D model."""
import sympy as sp

from levitron.derive.mechanics import hamiltonian_system
from levitron.derive.reduction import reduced_system
from levitron.derive.symbols import C, Phi, Z, g, m, mu


def test_eq_3_2_1_invariant_set_is_invariant():
    """On I the full vector field has zero components along x, y, phi, vth, p_x, p_y, p_phi, p_vth."""
    full = hamiltonian_system("tait-bryan", 4)
    red = reduced_system(4)
    on_I = full.rhs.xreplace(red.invariant_set)
    for i in (0, 1, 3, 4, 6, 7, 9, 10):
        assert sp.simplify(on_I[i]) == 0, full.state_names[i]


def test_eq_3_2_12_reduced_hamiltonian():
    red = reduced_system(2)
    z, zeta, pz, pzeta = red.state
    thesis = pz**2 / (2 * m) + pzeta**2 / (2 * C) + mu * Phi(1, Z) + m * g * z
    assert sp.expand(red.H - thesis) == 0


def test_reduced_equations_after_3_2_12():
    """zdot = p_z/m, p_z dot = -U_z = -(m g + mu Phi_2), zeta dot = p_zeta/C = sigma, p_zeta dot = 0."""
    red = reduced_system(2)
    z, zeta, pz, pzeta = red.state
    assert list(red.rhs) == [pz / m, pzeta / C, -g * m - mu * Phi(2, Z), 0]
    full = hamiltonian_system("tait-bryan", 2)
    on_I = full.rhs.xreplace(red.invariant_set)
    assert [sp.expand(on_I[i]) for i in (2, 5, 8, 11)] == [sp.expand(e) for e in red.rhs]


def test_reduced_model_is_order_independent():
    """On the axis the expansion's higher orders vanish: the reduced model is exact at any order."""
    assert sp.expand(reduced_system(2).H - reduced_system(6).H) == 0
