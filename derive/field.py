"""The axisymmetric Laplace expansion of the base plate's potential off the axis (thesis 2.2.2-2.2.7).

phi(r, z) = sum_j (-1)^j r^(2j) / (4^j (j!)^2) Phi_{2j}(z)   (thesis eqs. 2.2.4-2.2.6 solved)
B = -grad(phi)                                               (thesis eq. 2.2.7 at order 2)

The recursion phi_{2j+2} = -phi_{2j}'' / (2j+2)^2 (thesis eq. 2.2.5) is solved here by
`laplace_coefficients`, and tests check that the result satisfies Laplace's equation to the order kept.
"""
from __future__ import annotations

import sympy as sp

from .symbols import Phi, X, Y, Z


def laplace_coefficients(order: int) -> list[sp.Rational]:
    """c_j with phi = sum_j c_j r^(2j) Phi_{2j}: the recursion of thesis eq. 2.2.5.

    Laplace in cylindrical coordinates gives phi_n'' + (n+2)^2 phi_{n+2} = 0 for the coefficient
    phi_n(z) of r^n (thesis eqs. 2.2.3-2.2.5, using Delta r^n = n^2 r^(n-2)).
    """
    if order < 0 or order % 2:
        raise ValueError(f"order must be even and >= 0, got {order}")
    coeffs = [sp.Integer(1)]
    for j in range(order // 2):
        coeffs.append(-coeffs[-1] / sp.Integer(2 * j + 2) ** 2)
    return coeffs


def potential(order: int, x=X, y=Y, z=Z) -> sp.Expr:
    """The scalar potential phi(x, y, z) to order `order` in r (thesis eq. 2.2.6)."""
    r2 = x**2 + y**2
    return sum(c * r2**j * Phi(2 * j, z) for j, c in enumerate(laplace_coefficients(order)))


def field(order: int, x=X, y=Y, z=Z) -> sp.Matrix:
    """B = -grad(phi) from the expansion to order `order` (thesis eq. 2.2.7 for order = 2)."""
    phi = potential(order, x, y, z)
    return sp.Matrix([-sp.diff(phi, v) for v in (x, y, z)])
