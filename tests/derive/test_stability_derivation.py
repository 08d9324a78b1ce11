"""Thesis section 3.3 (after Dullin & Easton 1999), re-derived: one test per equation.

Where the thesis is wrong the test asserts the correct form and shows how the printed one differs
(docs/errata.md lists each case with the name of the test that proves it).
"""
from __future__ import annotations

import random

import numpy as np
import sympy as sp

from tests.helpers import stability_derivation as st
from levitron.derive.symbols import A, C, Phi, g, m, mu
from levitron.runtime.physics.routes import eigen_route
from levitron.runtime.physics.routes import ray_algebra

P1, P2, P3 = st.P1, st.P2, st.P3
lam, t, l, sigma = st.lam, st.t, st.l, st.sigma
g1, g2, g3, g21, g31, alpha = st.g1, st.g2, st.g3, st.g21, st.g31, st.alpha
rho = C / A


def zero(expr) -> bool:
    return sp.simplify(sp.expand(expr)) == 0


# ------------------------------------------------------------------ 3.3.1-3.3.3

def test_eq_3_3_1_to_3_3_3_reduced_potential():
    """On the invariant set (3.2.1) H = p_z^2/2m + p_zeta^2/2C + m g z + mu Phi1 (3.2.12), so
    U = m g z + mu Phi1 (3.3.1), U' = m g + mu Phi2 (3.3.2), U'' = mu Phi3 (3.3.3)."""
    H = st.full_hamiltonian().H
    z = st.z
    on_set = {st.x: 0, st.y: 0, st.phi: 0, st.vth: 0, st.p_x: 0, st.p_y: 0, st.p_phi: 0, st.p_vth: 0}
    HI = sp.simplify(H.xreplace(on_set))
    U = m * g * z + mu * Phi(1, z)
    assert zero(HI - (st.p_z ** 2 / (2 * m) + st.p_zeta ** 2 / (2 * C) + U))
    assert zero(sp.diff(U, z) - (m * g + mu * Phi(2, z)))
    assert zero(sp.diff(U, z, 2) - mu * Phi(3, z))


# ------------------------------------------------------------------ 3.3.5: the 8-D linear system

def test_eq_3_3_5_jacobian_splits_at_the_relative_equilibrium():
    """At x = y = phi = vth = 0, p = (0,..,C sigma) the 12-D Jacobian splits: transverse (8) and
    (z, zeta, p_z, p_zeta); the vertical block is z'' = -(mu Phi3/m) z, zeta' = p_zeta/C."""
    J = st.jacobian_at_equilibrium(st.full_hamiltonian())
    J8, V, TV, VT = st.split_blocks(J)
    assert TV == sp.zeros(8, 4) and VT == sp.zeros(4, 8)
    assert V == sp.Matrix([[0, 0, 1 / m, 0], [0, 0, 0, 1 / C], [-mu * P3, 0, 0, 0], [0, 0, 0, 0]])


def test_eq_3_3_5_linear_system_two_routes():
    """The 8-D system from the full Hamiltonian (derive/mechanics.py) equals that of the small-angle
    quadratic Hamiltonian H2 built independently in tests/helpers/stability_derivation.py."""
    assert (st.linear_system_8d() - st.small_angle_system_8d()).applyfunc(sp.simplify) \
        == sp.zeros(8, 8)


def test_eq_3_3_5_thesis_list_has_a_duplicated_left_hand_side():
    """The thesis prints 'd vth/dt' twice; its 4th line is the phi equation. With that left-hand
    side corrected, every printed line equals the derivation (signs included)."""
    J8 = st.linear_system_8d()
    printed = st.thesis_system_8d()           # row 4 placed at phi, as corrected
    assert (J8 - printed).applyfunc(sp.simplify) == sp.zeros(8, 8)
    # the printed 4th line cannot be d vth/dt: the derived d vth/dt row differs from it
    assert (J8.row(2) - printed.row(3)).applyfunc(sp.simplify) != sp.zeros(1, 8)


def test_eq_3_3_6_complex_form():
    """Eliminating the momenta, q'' = K q + D q' with K, D the real forms of A and B of 3.3.6
    (u = dx + i dy, v = dvth + i dphi)."""
    K, D = st.second_order_form(st.linear_system_8d())
    Am, Bm = st.complex_form()
    assert (K - st.realify(Am)).applyfunc(sp.simplify) == sp.zeros(4, 4)
    assert (D - st.realify(Bm)).applyfunc(sp.simplify) == sp.zeros(4, 4)


# ------------------------------------------------------------------ 3.3.8-3.3.11

def test_eq_3_3_9_quartic():
    """P(lambda) = det(A + lambda B - lambda^2 1): mu^2 (not mu) in the constant term, and the odd
    terms of the printed 3.3.9 have the opposite sign (printed = P(-lambda), i.e. sigma -> -sigma)."""
    P = st.P_of_lambda()
    expected = (lam ** 4 + sp.I * sigma * rho * lam ** 3 - mu * (P1 / A + P3 / (2 * m)) * lam ** 2
                - sp.I * sigma * rho * mu * P3 / (2 * m) * lam
                + mu ** 2 * (2 * P1 * P3 - P2 ** 2) / (4 * m * A))
    assert zero(P - expected)
    diff = sp.expand(P.subs(lam, -lam) - st.THESIS_P)
    assert zero(diff - (mu ** 2 - mu) * (2 * P1 * P3 - P2 ** 2) / (4 * m * A))
    assert not zero(diff)


def test_eq_3_3_9_eight_dim_charpoly_is_P_times_conjugate():
    """The eigenvalues of the real 8-D system are the roots of P(lambda) and of its conjugate
    (the same with sigma -> -sigma): det(lambda 1 - J8) = P(lambda) P(lambda)|_{sigma -> -sigma}."""
    J8 = st.linear_system_8d()
    cp = (lam * sp.eye(8) - J8).det(method="berkowitz")
    P = st.P_of_lambda()
    assert zero(cp - P * P.subs(sigma, -sigma))


def test_eq_3_3_11_normalised_quartic():
    """lambda = i sigma rho t in the correct P gives N(-t); lambda = -i sigma rho t gives the printed
    N(t) (3.3.11) exactly, with g1, g2, g3 of 3.3.10. Both have the same real-root count."""
    assert zero(st.N_from_P(-1) - st.N_THESIS)
    assert zero(st.N_from_P(+1) - st.N_THESIS.subs(t, -t))


# ------------------------------------------------------------------ 3.3.12 the discriminant

def test_eq_3_3_12_discriminant():
    """G = disc_t N(t) equals the printed 3.3.12 coefficient by coefficient (all 32 terms)."""
    G = sp.Poly(st.discriminant_G(), g1, g2, g3)
    T = sp.Poly(st.THESIS_G, g1, g2, g3)
    assert len(G.terms()) == 32
    assert dict(G.terms()) == dict(T.terms())


def test_runtime_G_terms_regenerated():
    """runtime/physics/routes/ray_algebra.py's hard-coded G_TERMS are the derivation's (regenerated here)."""
    assert [list(r) for r in ray_algebra.G_TERMS] == st.ray_polynomial_terms()


# ------------------------------------------------------------------ 3.3.13-3.3.18 the ray

def test_eq_3_3_13_ray_polynomial_is_l_cubed_times_cubic():
    """L(l) = G(l, -l g21, -l g31) has no terms below l^3: L/l^3 is a cubic (the thesis's 'divide by
    l^3')."""
    L = sp.Poly(st.L_of_l(), l)
    assert min(mon[0] for mon in L.monoms()) == 3 and L.degree() == 6
    assert sp.Poly(st.L_reduced(), l).degree() == 3


def test_eq_3_3_14_g_ratios():
    """g21 = -g2/g1 = -alpha Phi2/(2 Phi1), g31 = -g3/g1 = -alpha^2 Phi3/(2 Phi1), alpha^2 = A/m."""
    r = st.g_ratios()
    assert zero(r[g21] + alpha * P2 / (2 * P1))
    assert zero(r[g31] + alpha ** 2 * P3 / (2 * P1))


def test_eq_3_3_15_g21_bound():
    """At g31 = 0 the roots of L are real iff g21^2 <= 1/12 (disc = 16 (1 - 12 g21^2)^3)."""
    Q = sp.Poly(st.L_at_g31_zero(), l)
    assert zero(sp.discriminant(Q) - 16 * (1 - 12 * g21 ** 2) ** 3)


def test_eq_3_3_16_L_at_g31_zero():
    """L(l, g31 = 0) = -g21^2 l^4 [16 (4 g21^2 + 1)^2 l^2 - (144 g21^2 + 4) l + 27 g21^2]; the printed
    3.3.16 has 144 g21 where 144 g21^2 belongs (and drops the factor g21^2 l^4)."""
    correct = 16 * (4 * g21 ** 2 + 1) ** 2 * l ** 2 - (144 * g21 ** 2 + 4) * l + 27 * g21 ** 2
    assert zero(st.L_at_g31_zero() - correct)
    assert zero(st.L_of_l().subs(g31, 0) + g21 ** 2 * l ** 4 * correct)
    assert zero(st.THESIS_L16 + correct - 144 * (g21 - g21 ** 2) * l)


def test_eq_3_3_17_l1_series():
    """The larger root of 3.3.16 is l1 = (1 + g21^2)/4 + O(g21^4) (exact root, series)."""
    l2_exact, l1_exact = st.critical_l_at_g31_zero()
    ser = sp.series(l1_exact.subs(g21, sp.Symbol("e", positive=True)), sp.Symbol("e", positive=True), 0, 4)
    e = sp.Symbol("e", positive=True)
    assert zero(ser.removeO() - (1 + e ** 2) / 4)
    # with the printed (144 g21 + 4) the root would start 1/4 + 9 g21: inconsistent with 3.3.17
    a2, a1, a0 = sp.Poly(-st.THESIS_L16, l).all_coeffs()
    wrong = (-a1 + sp.sqrt(a1 ** 2 - 4 * a2 * a0)) / (2 * a2)
    assert zero(sp.series(wrong.subs(g21, e), e, 0, 2).removeO() - (sp.Rational(1, 4) + 9 * e))


def test_eq_3_3_18_l2_series():
    """The smaller root is l2 = 27 g21^2/4 + O(g21^4)."""
    e = sp.Symbol("e", positive=True)
    l2_exact, _ = st.critical_l_at_g31_zero()
    ser = sp.series(l2_exact.subs(g21, e), e, 0, 4).removeO()
    assert zero(ser - sp.Rational(27, 4) * e ** 2)


def test_runtime_l_cubic_matches_derivation():
    """runtime/ray_algebra.l_cubic (from G_TERMS) equals -L(l)/l^3 of the derivation."""
    coeffs = sp.Poly(st.L_reduced(), l).all_coeffs()[::-1]
    rng = random.Random(7)
    for _ in range(5):
        a, b = rng.uniform(0, 0.3), rng.uniform(-0.05, 0.05)
        want = [float(c.subs({g21: a, g31: b})) for c in coeffs]
        got = ray_algebra.l_cubic(a, b)
        scale = max(abs(v) for v in want)
        assert np.allclose(got, want, rtol=1e-13, atol=1e-13 * scale)


# ------------------------------------------------------------------ 3.3.19-3.3.23 the spin rates

def test_eq_3_3_19_to_3_3_21_sigma_squared_of_l():
    """g1 = l gives sigma^2 = mu Phi1/(l rho^2 A); with m g = -mu Phi2 and alpha^2 = A/m it equals
    each of the four printed forms of 3.3.21 (g2 = -l g21, 3.3.20)."""
    s2 = st.sigma_squared_of_l()
    assert zero(s2 - mu * P1 / (l * rho ** 2 * A))
    mp = sp.Symbol("mp", positive=True)
    on_eq = {mu: -mp * g / P2, m: mp, A: alpha ** 2 * mp}
    ref = s2.subs(on_eq)
    for form in st.sigma_squared_thesis_forms():
        f = form.subs(g21, st.g_ratios()[g21]).subs(on_eq)
        assert zero(sp.simplify(f - ref)), form
    # 3.3.20: sigma^2 = -m g alpha/(2 rho g2 C) at g2 = -l g21
    s320 = (-m * g * alpha / (2 * rho * g2 * C)).subs(g2, -l * g21).subs(g21, st.g_ratios()[g21])
    assert zero(sp.simplify(s320.subs(on_eq) - ref))


def _is_rate_squared(expr) -> bool:
    """Under a change of time unit (g -> k^2 g, the only time-carrying input) a rate scales as k and
    a squared rate as k^2."""
    k = sp.Symbol("k", positive=True)
    return zero(sp.simplify(expr.subs(g, k ** 2 * g) / expr) - k ** 2)


def test_eq_3_3_22_sigma1_is_a_square():
    """The printed sigma_1 (3.3.22) is sigma_1^2 = mu Phi1/(l1 rho^2 A) at l1 = 1/4."""
    approx = st.sigma_approximations()
    assert zero(approx["sigma1_sq"] - st.THESIS_SIGMA1)
    assert _is_rate_squared(st.THESIS_SIGMA1)


def test_eq_3_3_23_sigma2_is_a_square():
    """The printed sigma_2 (3.3.23, all three forms) is sigma_2^2 at l2 = 27 g21^2/4."""
    approx = st.sigma_approximations()
    first = -4 * g * P1 / (27 * st.g_ratios()[g21] ** 2 * alpha ** 2 * rho ** 2 * P2)
    second = -16 * P1 ** 3 * g / (27 * alpha ** 4 * P2 ** 3 * rho ** 2)
    for form in (first, second, st.THESIS_SIGMA2):
        assert zero(approx["sigma2_sq"] - form)
    assert _is_rate_squared(st.THESIS_SIGMA2)


# ------------------------------------------------------------------ runtime matrices

def test_runtime_transverse_matrix_matches_derivation():
    """runtime/eigen_route.transverse_matrix is the derived 8-D system (random values)."""
    J8 = st.linear_system_8d()
    f = sp.lambdify((P1, P2, P3, m, A, C, mu, sigma), J8, "numpy")
    rng = random.Random(3)
    for _ in range(5):
        args = [rng.uniform(-2, 2) for _ in range(3)] + [rng.uniform(0.01, 1) for _ in range(3)] \
            + [rng.uniform(-2, 2), rng.uniform(-50, 50)]
        want = np.array(f(*args), float)
        assert np.allclose(eigen_route.transverse_matrix(*args), want, rtol=1e-14, atol=0)


# ------------------------------------------------------------------ Berry-Simon: |B| near the axis

def test_field_strength_near_axis():
    """|B|^2 = Phi1^2 + r^2 (Phi2^2/4 - Phi1 Phi3/2) + O(r^4) from B = -grad(phi) (2.2.6, 2.2.7),
    the basis of the adiabatic (Berry-Simon) band in runtime/physics/equilibrium/finder.py."""
    from levitron.derive import field
    r = sp.Symbol("r", positive=True)
    x, y, z = sp.symbols("x y z", real=True)
    B = field.field(4, x, y, z)
    B2 = sp.expand((B.T * B)[0, 0].xreplace({x: r, y: 0}))
    ser = sp.series(B2, r, 0, 4).removeO()
    want = Phi(1, z) ** 2 + r ** 2 * (Phi(2, z) ** 2 / 4 - Phi(1, z) * Phi(3, z) / 2)
    assert zero(ser - want)
