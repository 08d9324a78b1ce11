"""More base plates (issue 5): loop, ring magnet, compound, expression, rectangle; and the
cancellation-free Phi_k of the thesis's annulus and disk.

Each builder takes the scene's [plate] table (validated by derive/scene.py) and returns a
derive.geometry.Plate: the on-axis potential Phi0(z) (thesis eq. 2.2.6 at r = 0) in the height Z,
its parameter symbols (named `plate_<key>`, valued by Scene.params), and `derivs`, k -> Phi_k in a
cancellation-free form (derive/onaxis.py). Parameter names per kind (SI):

  annulus      a, w, rho            (rho = mu0 D/(4 pi), T m; thesis eq. 2.2.11)
  disk         a, rho
  loop         a, current           (A; Phi0 = (mu0 I/2)(1 - z/sqrt(z^2+a^2)))
  ring_magnet  r_out, r_in, thickness, magnetization (A/m); r_in is absent for a solid cylinder
  compound     p<i>_<name> for part i (each part one of the kinds above, or expression)
  expression   the names of [plate.params]
  rectangle    side_x, side_y and either thickness, magnetization (a block magnet) or rho (thin)

The rectangle is not axisymmetric: `Plate.field3d(x, y, z)` gives its exact B as sympy
expressions (for the full model), and phi0 its exact on-axis potential (for the on-axis functions
and the reduced model, exact there because its 4-fold symmetry makes the r^2 terms isotropic).
"""
from __future__ import annotations

from typing import Callable

import sympy as sp

from . import onaxis
from .expr_parse import ExpressionError, parse_expression
from .geometry import Plate, plate_symbol
from .scene import MU0, SceneError
from .symbols import Z

MU0_SYM = sp.Float(MU0)


def _sym(prefix: str, key: str) -> sp.Symbol:
    return plate_symbol(prefix + key)


def phi_k(plate: Plate, k: int) -> sp.Expr:
    """Phi_k of a plate: its own (cancellation-free) form when it has one, else d^k Phi0/dz^k."""
    if k == 0:
        return plate.phi0
    return plate.derivs(k) if plate.derivs is not None else sp.diff(plate.phi0, Z, k)


def _axisymmetric(kind: str, phis: Callable[[int], sp.Expr], symbols) -> Plate:
    return Plate(kind, phis(0), tuple(symbols), lambda k: phis(k))


# ---------------------------------------------------------------- the thesis's plates, stable

def annulus(table: dict, prefix: str = "") -> Plate:
    """Thin annulus (thesis eq. 2.2.11), Phi_k cancellation-free (derive/onaxis.py)."""
    a, w, rho = _sym(prefix, "a"), _sym(prefix, "w"), _sym(prefix, "rho")
    return _axisymmetric("annulus", onaxis.annulus_phis(Z, a, w, 2 * sp.pi * rho), (a, w, rho))


def disk(table: dict, prefix: str = "") -> Plate:
    """Thin disk (thesis eq. 2.2.11 with w = 0): Phi0 = 2 pi rho (1 - z/sqrt(z^2+a^2))."""
    a, rho = _sym(prefix, "a"), _sym(prefix, "rho")
    return _axisymmetric("disk", onaxis.disk_phis(Z, a, 2 * sp.pi * rho), (a, rho))


# ---------------------------------------------------------------- new kinds

def loop(table: dict, prefix: str = "") -> Plate:
    """Circular current loop of radius a and current I in z = 0 (Jackson eq. 5.40 on the axis):
    B_z = mu0 I a^2 / (2 (z^2+a^2)^1.5), Phi0 = (mu0 I/2)(1 - z/sqrt(z^2+a^2)) (z > 0); the same
    field as a thin disk of dipole density D = I."""
    a, cur = _sym(prefix, "a"), _sym(prefix, "current")
    return _axisymmetric("loop", onaxis.disk_phis(Z, a, MU0_SYM * cur / 2), (a, cur))


def ring_magnet(table: dict, prefix: str = "") -> Plate:
    """Axially magnetised ring magnet r_in <= r <= r_out, -t <= z <= 0 (top face at z = 0),
    magnetisation M (A/m); r_in = 0 is a solid cylinder. On the axis (Derby & Olbert 2010):
    B_z = (mu0 M/2) sum_R +-[(z+t)/sqrt((z+t)^2+R^2) - z/sqrt(z^2+R^2)] (outer +, inner -)."""
    r_out, t, mag = _sym(prefix, "r_out"), _sym(prefix, "thickness"), _sym(prefix, "magnetization")
    strength = MU0_SYM * mag / 2
    outer = onaxis.cylinder_phis(Z, r_out, t, strength)
    if float(table.get("r_in", 0.0)) > 0:
        r_in = _sym(prefix, "r_in")
        inner = onaxis.cylinder_phis(Z, r_in, t, strength)
        return _axisymmetric("ring_magnet", lambda k: outer(k) - inner(k), (r_out, r_in, t, mag))
    return _axisymmetric("ring_magnet", outer, (r_out, t, mag))


def expression(table: dict, prefix: str = "") -> Plate:
    """A plate given by a formula for its on-axis potential `phi0` or on-axis field `bz` in z and
    the names of [plate.params] (parsed safely by derive/expr_parse.py, never evaluated as Python).
    With bz, Phi_1 = -bz (B = -grad phi) and Phi0 = -int bz dz, which must have a closed form."""
    params = table.get("params", {}) or {}
    names = {"z": Z}
    for key in sorted(params):
        names[key] = _sym(prefix, key)
    symbols = tuple(names[k] for k in sorted(params))
    where = f"plate{'.' + prefix.rstrip('_') if prefix else ''}"
    if "phi0" in table:
        try:
            phi0 = parse_expression(table["phi0"], names)
        except ExpressionError as exc:
            raise SceneError(f"{where}.phi0: {exc}; fix the formula") from None
        return Plate("expression", phi0, symbols, lambda k: sp.diff(phi0, Z, k))
    try:
        bz = parse_expression(table["bz"], names)
    except ExpressionError as exc:
        raise SceneError(f"{where}.bz: {exc}; fix the formula") from None
    phi0 = -sp.integrate(bz, Z)
    if phi0.has(sp.Integral):
        raise SceneError(f"{where}.bz = {table['bz']!r} has no closed-form antiderivative in z that "
                         "sympy finds: give the on-axis potential as `phi0` instead")
    return Plate("expression", phi0, symbols,
                 lambda k: phi0 if k == 0 else sp.diff(-bz, Z, k - 1))


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


def rect_solid_angle(w, hx, hy):
    """Solid angle of the rectangle |x| <= hx, |y| <= hy seen from (0, 0, w), w > 0:
    Omega = 4 atan(hx hy / (w sqrt(hx^2 + hy^2 + w^2))) (the disk's is 2 pi (1 - w/sqrt(w^2+a^2)))."""
    return 4 * sp.atan(hx * hy / (w * sp.sqrt(hx**2 + hy**2 + w**2)))


def rect_solid_angle_d1(w, hx, hy):
    """d Omega / dw = -4 hx hy (hx^2 + hy^2 + 2 w^2) / ((hx^2 + w^2)(hy^2 + w^2) R), R = sqrt(hx^2+hy^2+w^2)
    (sum of positive terms: no cancellation)."""
    R = sp.sqrt(hx**2 + hy**2 + w**2)
    return -4 * hx * hy * (hx**2 + hy**2 + 2 * w**2) / ((hx**2 + w**2) * (hy**2 + w**2) * R)


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


def rectangle(table: dict, prefix: str = "") -> Plate:
    """A uniformly magnetised rectangular plate centred on the z axis, sides side_x, side_y: a block
    magnet (thickness > 0, magnetization) with its top face in z = 0, or a thin dipole layer
    (thickness = 0, rho). Exact 3-D field in closed form (field3d), no axisymmetric expansion.

    On the axis (for `onaxis` and the reduced model) compact forms: thin layer Phi0 = rho Omega(z)
    (thesis eq. 2.2.10 over a rectangle), Phi_k = rho Omega^(k)(z); block Phi_1 = -(mu0 M / 4 pi)
    [Omega(z) - Omega(z+t)] (B_z = H_z of the two charged faces), Phi0 = (mu0 M/4 pi)[G(z) - G(z+t)]
    with G(w) = int int dA / R (G' = -Omega), and Phi_k = -(mu0 M/4 pi)[Omega^(k-1)(z) - Omega^(k-1)(z+t)].
    """
    sx, sy = _sym(prefix, "side_x"), _sym(prefix, "side_y")
    hx, hy = sx / 2, sy / 2
    x0, y0 = sp.Integer(0), sp.Integer(0)
    if float(table.get("thickness", 0.0)) > 0:
        t, mag = _sym(prefix, "thickness"), _sym(prefix, "magnetization")
        pot = lambda x, y, z: rectangle_block_potential(x, y, z, hx, hy, t, mag)  # noqa: E731
        fld = lambda x, y, z: rectangle_block_field(x, y, z, hx, hy, t, mag)  # noqa: E731
        symbols = (sx, sy, t, mag)
        k0 = MU0_SYM * mag / (4 * sp.pi)

        def derivs(k: int) -> sp.Expr:
            if k == 1:
                return -k0 * rect_solid_angle_difference(Z, t, hx, hy)
            return -k0 * (rect_solid_angle_derivative(k - 1, Z, hx, hy)
                          - rect_solid_angle_derivative(k - 1, Z + t, hx, hy))
    else:
        rho = _sym(prefix, "rho")
        pot = lambda x, y, z: rectangle_thin_potential(x, y, z, hx, hy, rho)  # noqa: E731
        fld = lambda x, y, z: rectangle_thin_field(x, y, z, hx, hy, rho)  # noqa: E731
        symbols = (sx, sy, rho)

        def derivs(k: int) -> sp.Expr:
            return rho * rect_solid_angle_derivative(k, Z, hx, hy)
    phi0 = pot(x0, y0, Z)
    return Plate("rectangle", phi0, symbols, derivs, fld, pot)


def compound(table: dict, prefix: str = "") -> Plate:
    """A sum of parts ([[plate.parts]], each a plate table of another kind): Phi_k adds up, and so
    does the exact 3-D field when some part is a rectangle."""
    parts = [BUILDERS[p["kind"]](p, f"{prefix}p{i}_") for i, p in enumerate(table["parts"])]
    symbols = tuple(s for p in parts for s in p.symbols)

    def phis(k: int) -> sp.Expr:
        return sp.Add(*[phi_k(p, k) for p in parts])

    if any(p.field3d is not None for p in parts):
        raise SceneError("plate.parts: a rectangle cannot be a part of a compound plate yet; use it "
                         "alone")
    return Plate("compound", phis(0), symbols, phis)


BUILDERS: dict[str, Callable[..., Plate]] = {
    "annulus": annulus,
    "disk": disk,
    "loop": loop,
    "ring_magnet": ring_magnet,
    "expression": expression,
    "rectangle": rectangle,
    "compound": compound,
}


def example_formulas() -> list[tuple[str, sp.Expr]]:
    """Phi0, bz = -Phi1, Phi2 and Phi3 of every built-in kind: what an expression plate could say
    about them (tests/test_expr_parse.py round-trips them through str; the formulas a scene could
    give, Phi0 and bz, must all parse)."""
    tables = {
        "annulus": {"kind": "annulus"},
        "disk": {"kind": "disk"},
        "loop": {"kind": "loop"},
        "ring_magnet": {"kind": "ring_magnet", "r_in": 0.01},
        "cylinder": {"kind": "ring_magnet", "r_in": 0.0},
        "rectangle_thin": {"kind": "rectangle", "thickness": 0.0},
        "rectangle_block": {"kind": "rectangle", "thickness": 0.01},
        "expression": {"kind": "expression", "phi0": "b*z/sqrt(z**2 + c**2)",
                       "params": {"b": 1.0, "c": 0.1}},
        "compound": {"kind": "compound", "parts": [{"kind": "disk"}, {"kind": "loop"}]},
    }
    out = []
    for label, tab in tables.items():
        kind = tab["kind"]
        plate = BUILDERS[kind](tab)
        out.append((label + " Phi0", plate.phi0))
        out.append((label + " bz = -Phi1", -phi_k(plate, 1)))
        for k in (2, 3):
            out.append((f"{label} Phi{k}", phi_k(plate, k)))
    # the thesis's textbook forms too (thesis eqs. 2.2.11-2.2.12)
    a, w, rho = plate_symbol("a"), plate_symbol("w"), plate_symbol("rho")
    naive = onaxis.textbook_annulus_phis(Z, a, w, 2 * sp.pi * rho)
    out += [("textbook Phi0", naive(0)), ("textbook Phi1", naive(1))]
    return out
