"""Thesis 2.2.2-2.2.14: the Laplace expansion off the axis and the annulus potential."""
import sympy as sp

from levitron.derive import field as F
from levitron.derive.geometry import annulus_phi0, build_plate
from levitron.derive.symbols import Phi, X, Y, Z

r, n = sp.symbols("r n", positive=True)


def test_eq_2_2_3_laplacian_of_r_power():
    """Delta r^n = n^2 r^(n-2) for r^2 = x^2 + y^2 (the identity after thesis eq. 2.2.3)."""
    for k in range(1, 7):
        f = (X**2 + Y**2)**sp.Rational(k, 2)
        lap = sp.diff(f, X, 2) + sp.diff(f, Y, 2)
        assert sp.simplify(lap - k**2 * (X**2 + Y**2)**sp.Rational(k - 2, 2)) == 0


def test_eq_2_2_4_2_2_5_recursion():
    """phi_2 = -Phi_0''/4, phi_4 = -phi_2''/16, phi_6 = -phi_4''/36 (thesis eqs. 2.2.4-2.2.5)."""
    c = F.laplace_coefficients(6)
    assert c[1] == -sp.Rational(1, 4)
    assert c[2] == c[1] * -sp.Rational(1, 16)
    assert c[3] == c[2] * -sp.Rational(1, 36)


def test_eq_2_2_6_potential_satisfies_laplace_to_its_order():
    """Delta phi of the order-N expansion is O(r^N): only the last term's Phi_{N+2} survives."""
    for order in (2, 4, 6, 8):
        phi = F.potential(order)
        lap = sp.expand(sum(sp.diff(phi, v, 2) for v in (X, Y, Z)))
        cN = F.laplace_coefficients(order)[-1]
        assert sp.simplify(lap - cN * (X**2 + Y**2)**(order // 2) * Phi(order + 2, Z)) == 0


def test_eq_2_2_7_field_at_order_two():
    B = F.field(2)
    thesis = sp.Matrix([X / 2 * Phi(2, Z), Y / 2 * Phi(2, Z),
                        -Phi(1, Z) + (X**2 + Y**2) / 4 * Phi(3, Z)])
    assert (B - thesis).applyfunc(sp.expand) == sp.zeros(3, 1)


def test_eq_2_2_7_field_is_curl_and_divergence_free_to_order():
    B = F.field(4)
    div = sp.expand(sum(sp.diff(B[i], v) for i, v in enumerate((X, Y, Z))))
    # div B = -Delta phi: exactly the truncation term -c_2 r^4 Phi_6 survives
    c2 = F.laplace_coefficients(4)[-1]
    assert sp.expand(div + c2 * (X**2 + Y**2)**2 * Phi(6, Z)) == 0
    curl_z = sp.expand(sp.diff(B[1], X) - sp.diff(B[0], Y))
    assert curl_z == 0


def test_eq_2_2_11_annulus_integral():
    """2 pi z int_w^a r rho /(r^2+z^2)^(3/2) dr = 2 pi z rho (1/sqrt(z^2+w^2) - 1/sqrt(z^2+a^2))."""
    a, w, rho, z = sp.symbols("a w rho z", positive=True)
    integral = 2 * sp.pi * z * sp.integrate(r * rho / (r**2 + z**2)**sp.Rational(3, 2), (r, w, a))
    assert sp.simplify(integral - annulus_phi0(a, w, rho).subs(Z, z)) == 0


def _annulus_derivs():
    """Phi_1..Phi_4 by differentiating thesis eq. 2.2.11 (the textbook route)."""
    a, w, rho = sp.symbols("plate_a plate_w plate_rho", real=True)
    P = [annulus_phi0(a, w, rho)]
    for _ in range(4):
        P.append(sp.diff(P[-1], Z))
    return P, a, w, rho


def test_generated_annulus_forms_equal_the_textbook_derivatives():
    """The plate's Phi_k (possibly rearranged against cancellation) equal d^k Phi0/dz^k, checked in
    40-digit arithmetic at seeded points."""
    import random
    P, a, w, rho = _annulus_derivs()
    plate = build_plate({"kind": "annulus"})
    mine = plate.phi_derivs(4)
    sym = dict(zip([str(s) for s in plate.symbols], plate.symbols))
    rnd = random.Random(7)
    for _ in range(5):
        vals = {"plate_a": rnd.uniform(0.05, 0.2), "plate_rho": rnd.uniform(-1, 1), "z": rnd.uniform(0.01, 0.5)}
        vals["plate_w"] = rnd.uniform(0.0, 0.9) * vals["plate_a"]
        vals = {n: sp.Float(v, 50) for n, v in vals.items()}
        for k in range(5):
            ref = P[k].subs({a: vals["plate_a"], w: vals["plate_w"], rho: vals["plate_rho"], Z: vals["z"]})
            got = mine[k].subs({sym[n]: vals[n] for n in ("plate_a", "plate_w", "plate_rho")} | {Z: vals["z"]})
            ref, got = sp.N(ref, 40), sp.N(got, 40)
            assert abs(ref - got) <= 1e-30 * max(1.0, abs(ref)), (k, ref, got)


def test_eq_2_2_12_phi1():
    P, a, w, rho = _annulus_derivs()
    z = Z
    thesis = (2 * sp.pi * rho * (1 / sp.sqrt(z**2 + w**2) - 1 / sp.sqrt(z**2 + a**2))
              + 2 * sp.pi * rho * z * (z / (z**2 + a**2)**sp.Rational(3, 2) - z / (z**2 + w**2)**sp.Rational(3, 2)))
    assert sp.simplify(P[1] - thesis) == 0


def test_eq_2_2_13_phi2_erratum():
    """Thesis 2.2.13 is garbled (a for w in the first bracket, 'd' for a, a stray term). The correct
    Phi_2 = 6 pi rho z (a^2/(z^2+a^2)^(5/2) - w^2/(z^2+w^2)^(5/2))."""
    P, a, w, rho = _annulus_derivs()
    z = Z
    correct = 6 * sp.pi * rho * z * (a**2 / (z**2 + a**2)**sp.Rational(5, 2) - w**2 / (z**2 + w**2)**sp.Rational(5, 2))
    assert sp.simplify(P[2] - correct) == 0


def test_eq_2_2_14_phi3_with_d_read_as_a():
    """Thesis 2.2.14 is right once its 'd' is read as the outer radius a."""
    P, a, w, rho = _annulus_derivs()
    z = Z
    h = sp.Rational
    thesis = (6 * sp.pi * rho * (-1 / (z**2 + w**2)**h(3, 2) + 3 * z**2 / (z**2 + w**2)**h(5, 2)
                                 + 1 / (z**2 + a**2)**h(3, 2) - 3 * z**2 / (z**2 + a**2)**h(5, 2))
              + 2 * sp.pi * rho * z * (9 * z / (z**2 + w**2)**h(5, 2) - 15 * z**3 / (z**2 + w**2)**h(7, 2)
                                       - 9 * z / (z**2 + a**2)**h(5, 2) + 15 * z**3 / (z**2 + a**2)**h(7, 2)))
    assert sp.simplify(P[3] - thesis) == 0
