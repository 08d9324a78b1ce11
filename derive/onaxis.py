"""Cancellation-free on-axis potentials Phi_k(z) = d^k Phi0/dz^k of the axisymmetric plates.

The field off the axis (thesis eqs. 2.2.6-2.2.7) needs Phi_1 .. Phi_K. Differentiating the thesis's
Phi0 = 2 pi rho z (1/sqrt(z^2+w^2) - 1/sqrt(z^2+a^2)) (thesis eq. 2.2.11) by the product rule gives
the textbook forms (thesis eqs. 2.2.12-2.2.14), which evaluated in double precision lose
  - a factor ~ z^2/a^2 far from the plate (1/sqrt(z^2+w^2) - 1/sqrt(z^2+a^2) and z/r - 1 terms), and
  - a factor ~ a/(a - w) for thin rings (w/a -> 1, two nearly equal loop terms).
This module writes the same functions exactly but so that every difference of nearly equal
quantities has been done symbolically:

Notation: S = s^2 for a radius s, r_S = sqrt(z^2 + S); W = w^2, A = a^2; X = r_W, Y = r_A.

1. d/dz (z / r_S) = S / r_S^3, so for k >= 1, Phi_k / (2 pi rho) = W f_{k-1}(W) - A f_{k-1}(A) with
   f_n(S) = d^n/dz^n r_S^-3 = sum_j c_nj z^m_j r_S^-p_j (integer bookkeeping in `_fn_terms`; the
   alternating sum is a Legendre-type polynomial whose only cancellations are at its true zeros).
2. W f(W) - A f(A) = (W - A) [W f[W, A] + f(A)] (Leibniz rule for divided differences), with the
   factor (W - A) = (w - a)(w + a) kept as a product of parameters, and the divided difference
   f[W, A] = sum_j c_nj z^m_j (r^-p)[W, A] where
       (r^-p)[W, A] = (X^-p - Y^-p) / (W - A) = -e_p / (X + Y),   e_p = sum_{i<p} X^-(i+1) Y^-(p-i)
   is a sum of positive terms (no subtraction at all); e_p = (e_{p-1} + X^-p) / Y.
   W f[W, A] dominates when w << a near the hole, f(A) when z >> a: neither cancels the other
   except where Phi_k itself changes sign.
3. Phi_0 / (2 pi rho) = z (1/X - 1/Y) = (A - W) z / (X Y (X + Y)).
4. The disk (w = 0): Phi_0 = 2 pi rho (1 - z/Y) = 2 pi rho A / (Y (Y + z)), Phi_k = -2 pi rho A f_{k-1}(A).
   A current loop of radius a and current I is the disk with 2 pi rho = mu0 I / 2.
5. Ring magnet (axially magnetised, -t <= z <= 0): Phi_0 = -(mu0 M/2) sum_R +-[h_R(z+t) - h_R(z)]
   with h_R(zeta) = sqrt(zeta^2+R^2) - zeta = R^2/(sqrt(zeta^2+R^2) + zeta) (a constant mu0 M t/2
   dropped), h_R' = -R^2 Q_R, Q_R = 1/(r (r + zeta)), Q_R' = -r^-3 (so no z/r - 1 cancellation),
   and the difference between z and z + t taken symbolically (see `cylinder_phis`).

References: thesis eqs. 2.2.11-2.2.14; divided differences: e.g. C. de Boor, "Divided
differences", Surveys in Approximation Theory 1 (2005), Leibniz rule.
"""
from __future__ import annotations

from functools import cache

import sympy as sp


@cache
def power_terms(n: int, p0: int) -> tuple[tuple[int, int, int], ...]:
    """d^n/dz^n r^-p0 (r = sqrt(z^2 + S)) = sum c z^m r^-p: the tuple of (c, m, p), by the product
    rule d/dz (z^m r^-p) = m z^(m-1) r^-p - p z^(m+1) r^-(p+2)."""
    terms = {(0, p0): 1}
    for _ in range(n):
        new: dict[tuple[int, int], int] = {}
        for (m, p), c in terms.items():
            if m:
                new[(m - 1, p)] = new.get((m - 1, p), 0) + c * m
            new[(m + 1, p + 2)] = new.get((m + 1, p + 2), 0) - c * p
        terms = {k: v for k, v in new.items() if v}
    return tuple(sorted((c, m, p) for (m, p), c in terms.items()))


def _fn_terms(n: int) -> tuple[tuple[int, int, int], ...]:
    """d^n/dz^n (z^2 + S)^(-3/2) = sum c z^m r^-p (see `power_terms`)."""
    return power_terms(n, 3)


def derivative_of_power(n: int, z: sp.Expr, r: sp.Expr, p0: int) -> sp.Expr:
    """d^n/dz^n r^-p0 with r = sqrt(z^2 + S) given, as the sum of `power_terms`."""
    return sp.Add(*[c * z**m / r**p for c, m, p in power_terms(n, p0)])


def f_n(n: int, z: sp.Expr, r: sp.Expr) -> sp.Expr:
    """f_n = d^n/dz^n r^-3 with r = sqrt(z^2 + S), as the sum of `_fn_terms` (r given)."""
    return sp.Add(*[c * z**m / r**p for c, m, p in _fn_terms(n)])


def _e(p: int, x: sp.Expr, y: sp.Expr) -> sp.Expr:
    """e_p = sum_{i=0}^{p-1} x^-(i+1) y^-(p-i) (positive terms only)."""
    return sp.Add(*[1 / (x ** (i + 1) * y ** (p - i)) for i in range(p)])


def f_n_divided(n: int, z: sp.Expr, x: sp.Expr, y: sp.Expr) -> sp.Expr:
    """f_n[W, A] = (f_n(W) - f_n(A)) / (W - A), x = sqrt(z^2 + W), y = sqrt(z^2 + A), no subtraction
    of nearly equal quantities (see the module docstring, item 2)."""
    return sp.Add(*[-c * z**m * _e(p, x, y) for c, m, p in _fn_terms(n)]) / (x + y)


def annulus_phis(z: sp.Symbol, a: sp.Expr, w: sp.Expr, strength: sp.Expr):
    """k -> Phi_k of the thin annulus Phi0 = strength * z (1/sqrt(z^2+w^2) - 1/sqrt(z^2+a^2))
    (strength = 2 pi rho, thesis eq. 2.2.11), cancellation-free (module docstring items 1-3)."""
    x = sp.sqrt(z**2 + w**2)
    y = sp.sqrt(z**2 + a**2)

    def phi(k: int) -> sp.Expr:
        if k == 0:
            return strength * (a - w) * (a + w) * z / (x * y * (x + y))
        n = k - 1
        return strength * (w - a) * (w + a) * (w**2 * f_n_divided(n, z, x, y) + f_n(n, z, y))

    return phi


def disk_phis(z: sp.Symbol, a: sp.Expr, strength: sp.Expr):
    """k -> Phi_k of the thin disk Phi0 = strength (1 - z/sqrt(z^2+a^2)) (thesis eq. 2.2.11, w = 0,
    z > 0), cancellation-free (module docstring item 4). A current loop I is strength = mu0 I/2."""
    y = sp.sqrt(z**2 + a**2)

    def phi(k: int) -> sp.Expr:
        if k == 0:
            return strength * a**2 / (y * (y + z))
        return -strength * a**2 * f_n(k - 1, z, y)

    return phi


def _h(m: int, x: sp.Expr, y: sp.Expr) -> sp.Expr:
    """(x^m - y^m) / (x - y) = sum_{i<m} x^i y^(m-1-i) (positive for x, y > 0)."""
    return sp.Add(*[x**i * y ** (m - 1 - i) for i in range(m)])


def cylinder_phis(z: sp.Symbol, radius: sp.Expr, thickness: sp.Expr, strength: sp.Expr):
    """k -> Phi_k of a solid cylinder magnet of radius R, -t <= z <= 0, with strength = mu0 M / 2:
    on the axis B_z = strength [(z+t)/sqrt((z+t)^2+R^2) - z/sqrt(z^2+R^2)] (module item 5).

    Every Phi_k is a difference of one function at z and at u = z + t, which cancels when t << z;
    the difference is taken symbolically, with the factor t pulled out (r1 = r(z), r2 = r(u)):
      Phi_0 = strength R^2 t [(z+u)/(r1+r2) + 1] / ((r1+z)(r2+u))
      Phi_1 = -strength R^2 t [(z+u) + r2 + z (z+u)/(r1+r2)] / (r1 r2 (r1+z)(r2+u))
      Phi_k = strength R^2 [f_n(z) - f_n(u)], n = k - 2, term by term
              z^m r1^-p - u^m r2^-p = t [z^m (z+u) e_p(r1, r2)/(r1+r2) - h_m(z, u) r2^-p]
    (r2 - r1 = t (z+u)/(r1+r2), u^m - z^m = t h_m(z, u)); no term cancels another for z > 0 except
    near the zeros of Phi_k. Thin rings (r_in -> r_out) are not treated: outer minus inner.
    """
    R2 = radius**2
    t = thickness
    u = z + t
    r1 = sp.sqrt(z**2 + R2)
    r2 = sp.sqrt(u**2 + R2)
    s = z + u

    def phi(k: int) -> sp.Expr:
        if k == 0:
            return strength * R2 * t * (s / (r1 + r2) + 1) / ((r1 + z) * (r2 + u))
        if k == 1:
            return -strength * R2 * t * (s + r2 + z * s / (r1 + r2)) / (r1 * r2 * (r1 + z) * (r2 + u))
        terms = [c * (z**m * s * _e(p, r1, r2) / (r1 + r2) - _h(m, z, u) / r2**p)
                 for c, m, p in _fn_terms(k - 2)]
        return strength * R2 * t * sp.Add(*terms)

    return phi


def textbook_annulus_phis(z: sp.Symbol, a: sp.Expr, w: sp.Expr, strength: sp.Expr):
    """The naive forms: thesis eq. 2.2.11 differentiated k times by sympy (as in thesis eqs.
    2.2.12-2.2.14). Kept only to show in tests that they fail the precision target."""
    phi0 = strength * z * (1 / sp.sqrt(z**2 + w**2) - 1 / sp.sqrt(z**2 + a**2))
    return lambda k: sp.diff(phi0, z, k)
