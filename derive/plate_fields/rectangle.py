"""Uniformly magnetised rectangular plate centred on the z axis: exact 3-D field (Furlani 2001)."""
from __future__ import annotations

import sympy as sp

from levitron.scene.plates.rectangle import block, holed

from .. import onaxis
from ..symbols import Z
from .plate import MU0_SYM, Plate, plate_symbol


def _rect_corner_sum(f, hx, hy, x, y):
    """sum over the corners (x_i, y_j) of s_ij f(x - x_i, y - y_j), s = +1 on the diagonal."""
    us = (x + hx, x - hx)   # u_1 = x - (-hx), u_2 = x - hx
    vs = (y + hy, y - hy)
    return sum((1 if i == j else -1) * f(us[i], vs[j]) for i in range(2) for j in range(2))


def rectangle_thin_potential(x, y, z, hx, hy, rho):
    """Thin rectangular dipole layer |x| <= hx, |y| <= hy in z = 0, strength rho = mu0 D/(4 pi):
    phi = rho * Omega, Omega = sum_ij s_ij atan(u_i v_j / (z R_ij)) the solid angle (thesis eq.
    2.2.10 integrated over a rectangle; the disk gives Omega = 2 pi (1 - z/sqrt(z^2+a^2)), eq. 2.2.11)."""
    return rho * _rect_corner_sum(lambda u, v: sp.atan(u * v / (z * sp.sqrt(u**2 + v**2 + z**2))),
                                  hx, hy, x, y)


def rectangle_thin_field(x, y, z, hx, hy, rho):
    """B = -grad(rho Omega) of the thin rectangular layer, written as the Biot-Savart field of its
    rim current I = D = 4 pi rho / mu0 (Hanson & Hirshman 2002, straight segments):
    B = rho sum_seg (r1 x r2)(|r1| + |r2|) / (|r1||r2| (|r1||r2| + r1.r2))."""
    corners = [(hx, -hy), (hx, hy), (-hx, hy), (-hx, -hy)]
    out = sp.zeros(3, 1)
    for k in range(4):
        (ax, ay), (bx, by) = corners[k], corners[(k + 1) % 4]
        r1 = sp.Matrix([x - ax, y - ay, z])
        r2 = sp.Matrix([x - bx, y - by, z])
        n1, n2 = sp.sqrt(r1.dot(r1)), sp.sqrt(r2.dot(r2))
        out += r1.cross(r2) * ((n1 + n2) / (n1 * n2 * (n1 * n2 + r1.dot(r2))))
    return rho * out


def _charged_face_h(x, y, w, hx, hy):
    """H / sigma of a uniformly charged rectangle |x| <= hx, |y| <= hy at height offset w = z - z0
    (Furlani 2001 sec. 4.3, asinh form; see runtime/exact_field.charged_rectangle_h)."""
    hxv = -_rect_corner_sum(lambda u, v: sp.asinh(v / sp.sqrt(u**2 + w**2)), hx, hy, x, y)
    hyv = -_rect_corner_sum(lambda u, v: sp.asinh(u / sp.sqrt(v**2 + w**2)), hx, hy, x, y)
    hzv = _rect_corner_sum(lambda u, v: sp.atan(u * v / (w * sp.sqrt(u**2 + v**2 + w**2))),
                           hx, hy, x, y)
    return sp.Matrix([hxv, hyv, hzv]) / (4 * sp.pi)


def _charged_face_potential(x, y, w, hx, hy):
    """phi_H / sigma = (1/4 pi) int int dA / R over the rectangle (antiderivative
    u asinh(v/sqrt(u^2+w^2)) + v asinh(u/sqrt(v^2+w^2)) - w atan(u v/(w R)), corner sum with the
    signs of the integration limits)."""
    def F(u, v):
        R = sp.sqrt(u**2 + v**2 + w**2)
        return (u * sp.asinh(v / sp.sqrt(u**2 + w**2)) + v * sp.asinh(u / sp.sqrt(v**2 + w**2))
                - w * sp.atan(u * v / (w * R)))
    return _rect_corner_sum(F, hx, hy, x, y) / (4 * sp.pi)


def rectangle_block_field(x, y, z, hx, hy, t, mag):
    """B outside a block |x| <= hx, |y| <= hy, -t <= z <= 0 magnetised M along +z: charges +M on
    the top face and -M on the bottom (Furlani 2001), B = mu0 H."""
    return MU0_SYM * mag * (_charged_face_h(x, y, z, hx, hy) - _charged_face_h(x, y, z + t, hx, hy))


def rectangle_block_potential(x, y, z, hx, hy, t, mag):
    """phi with B = -grad(phi) outside the block: mu0 M (phi_H,top - phi_H,bottom)."""
    return MU0_SYM * mag * (_charged_face_potential(x, y, z, hx, hy)
                            - _charged_face_potential(x, y, z + t, hx, hy))


def rect_solid_angle_derivative(k: int, w, hx, hy):
    """d^k Omega / dw^k for k >= 1, by partial fractions and the Leibniz rule:
    (s2 + 2 w^2)/((hx^2 + w^2)(hy^2 + w^2)) = 1/(hx^2 + w^2) + 1/(hy^2 + w^2), so
    Omega' = -4 hx hy sum_{h = hx, hy} (h^2 + w^2)^-1 R^-1, and
    d^n [(h^2 + w^2)^-1 R^-1] = sum_j binom(n, j) d^j (h^2+w^2)^-1 d^(n-j) R^-1, each factor a short
    sum (derive/onaxis.power_terms) -- much smaller than differentiating the quotient directly."""
    n = k - 1
    R = sp.sqrt(hx**2 + hy**2 + w**2)
    total = 0
    for h in (hx, hy):
        rh = sp.sqrt(h**2 + w**2)
        total += sp.Add(*[sp.binomial(n, j) * onaxis.derivative_of_power(j, w, rh, 2)
                          * onaxis.derivative_of_power(n - j, w, R, 1) for j in range(n + 1)])
    return -4 * hx * hy * total


def rect_solid_angle_difference(z, t, hx, hy):
    """Omega(z) - Omega(z + t) without cancellation for t << z: with p = c/(z R1), q = c/(u R2),
    c = hx hy, u = z + t, atan p - atan q = atan((p - q)/(1 + p q)) (p, q > 0) and
    u R2 - z R1 = t (z + u)(s2 + z^2 + u^2)/(u R2 + z R1), s2 = hx^2 + hy^2."""
    c = hx * hy
    s2 = hx**2 + hy**2
    u = z + t
    R1 = sp.sqrt(s2 + z**2)
    R2 = sp.sqrt(s2 + u**2)
    num = c * t * (z + u) * (s2 + z**2 + u**2)
    den = (u * R2 + z * R1) * (z * R1 * u * R2 + c**2)
    return 4 * sp.atan(num / den)


def build(table: dict, prefix: str = "") -> Plate:
    """A uniformly magnetised rectangular plate centred on the z axis, sides side_x, side_y: a block
    magnet (thickness > 0, magnetization) with its top face in z = 0, or a thin dipole layer
    (thickness = 0, rho). Exact 3-D field in closed form (field3d), no axisymmetric expansion.

    On the axis (for `onaxis` and the reduced model) compact forms: thin layer Phi0 = rho Omega(z)
    (thesis eq. 2.2.10 over a rectangle), Phi_k = rho Omega^(k)(z); block Phi_1 = -(mu0 M / 4 pi)
    [Omega(z) - Omega(z+t)] (B_z = H_z of the two charged faces), Phi0 = (mu0 M/4 pi)[G(z) - G(z+t)]
    with G(w) = int int dA / R (G' = -Omega), and Phi_k = -(mu0 M/4 pi)[Omega^(k-1)(z) - Omega^(k-1)(z+t)].

    With a hole (decision `holed`): the plate minus a cylinder (block, derive/onaxis.cylinder_phis)
    or a thin disk (layer, onaxis.disk_phis) of radius plate_hole and the same magnetisation; on the
    axis exactly, and in the full model field3d (the plain plate) plus the hole's expansion (`axial`).
    """
    sx, sy = plate_symbol(prefix + "side_x"), plate_symbol(prefix + "side_y")
    hx, hy = sx / 2, sy / 2
    x0, y0 = sp.Integer(0), sp.Integer(0)
    if block(table):   # structural decision `block` (scene/plates/rectangle.py)
        t, mag = plate_symbol(prefix + "thickness"), plate_symbol(prefix + "magnetization")
        pot = lambda x, y, z: rectangle_block_potential(x, y, z, hx, hy, t, mag)
        fld = lambda x, y, z: rectangle_block_field(x, y, z, hx, hy, t, mag)
        symbols = (sx, sy, t, mag)
        k0 = MU0_SYM * mag / (4 * sp.pi)

        def derivs(k: int) -> sp.Expr:
            if k == 1:
                return -k0 * rect_solid_angle_difference(Z, t, hx, hy)
            return -k0 * (rect_solid_angle_derivative(k - 1, Z, hx, hy)
                          - rect_solid_angle_derivative(k - 1, Z + t, hx, hy))
    else:
        rho = plate_symbol(prefix + "rho")
        pot = lambda x, y, z: rectangle_thin_potential(x, y, z, hx, hy, rho)
        fld = lambda x, y, z: rectangle_thin_field(x, y, z, hx, hy, rho)
        symbols = (sx, sy, rho)

        def derivs(k: int) -> sp.Expr:
            return rho * rect_solid_angle_derivative(k, Z, hx, hy)
    phi0 = pot(x0, y0, Z)
    if not holed(table):   # structural decision `holed` (scene/plates/rectangle.py)
        return Plate("rectangle", phi0, symbols, derivs, fld, pot)
    hole = plate_symbol(prefix + "hole")
    if block(table):
        taken = onaxis.cylinder_phis(Z, hole, t, MU0_SYM * mag / 2)
    else:
        taken = onaxis.disk_phis(Z, hole, 2 * sp.pi * rho)
    whole = derivs

    def holed_derivs(k: int) -> sp.Expr:
        return whole(k) - taken(k)

    def axial(k: int) -> sp.Expr:
        return -taken(k)
    return Plate("rectangle", phi0 - taken(0), symbols + (hole,), holed_derivs, fld, pot, axial)
