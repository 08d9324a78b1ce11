"""Exact magnetic fields of the base plates, off the axis, in closed form (numpy/scipy, no sympy).

These are the references against which the Laplace expansion of thesis eqs. 2.2.2-2.2.7 is
judged (`levitron field`, derive/field_order.py); runtime/physics/plates/<kind>.py maps each plate kind of a
scene to them. Conventions (docs/contract.md): SI, the plate's (top)
face in z = 0, its axis the z axis, B in tesla. Every function takes points (N, 3) in metres and
returns B (N, 3).

Building blocks
- `cel(kc, p, c, s)`: Bulirsch's generalized complete elliptic integral
      cel = int_0^{pi/2} (c cos^2 t + s sin^2 t) / ((cos^2 t + p sin^2 t) sqrt(cos^2 t + kc^2 sin^2 t)) dt
  (R. Bulirsch, Numer. Math. 13, 305 (1969); the algorithm as printed by N. Derby and S. Olbert,
  Am. J. Phys. 78, 229 (2010), appendix), vectorised.
- `loop_field`: a circular current loop. The textbook K/E form (Jackson 5.37; Simpson et al.,
  NASA/TM-2013-217919) divides by rho and cancels near the axis and far away; the two brackets are
  rewritten exactly as single cel integrals with positive weights (derivation in `loop_field`), so
  that the field is accurate near the axis (rho -> 0, the limit rho = 0 included) and far away.
- `solenoid_field`: a cylindrical current sheet (ideal finite solenoid), Derby & Olbert (2010) eq.
  for B_rho and B_z in cel form. An axially magnetised cylinder of magnetisation M is the sheet with
  surface current K = M (Jackson 5.8); a ring magnet is the outer sheet minus the inner one.
- `annulus_field`: the thesis's thin annulus (thesis eq. 2.2.11) as a dipole layer of density D
  (A): a uniformly magnetised thin disk equals a current loop I = D at its rim, so the annulus is
  loop(a, D) - loop(w, D); on the axis B_z = (mu0 D/2)[a^2/(z^2+a^2)^1.5 - w^2/(z^2+w^2)^1.5].
- `block_field`: a uniformly z-magnetised rectangular block, by the fields of its two charged faces
  (E. P. Furlani, "Permanent Magnet and Electromechanical Devices", Academic Press 2001, sec. 4.3;
  J. M. Camacho and V. Sosa, Rev. Mex. Fis. E 59, 8 (2013)), written with asinh instead of
  log(v + R) so that no log of a cancelling sum appears.
- `rect_loop_field`: a rectangular current loop = a thin rectangular dipole layer of density D = I,
  by Biot-Savart for straight segments (Hanson and Hirshman, Phys. Plasmas 9, 3385 (2002)).

Singular points: on a current filament (loop wire, the rim of a thin layer) the field is infinite and
NaN is returned; on a current sheet or a charged face the field is discontinuous and the value
returned there is the mean of the two sides (the principal value the closed forms give; NaN at the
sheet's edges). `singular` in the docstrings names these sets.
"""
from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from levitron.scene.constants import MU0

_HALF_PI = 0.5 * math.pi


def _points(points) -> np.ndarray:
    pts = np.asarray(points, dtype=float)
    if pts.ndim == 1:
        pts = pts.reshape(1, 3)
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points must have shape (N, 3), got {pts.shape}")
    return pts


def _cel_iterate(k, cc, ss, pp, em, kk, g, tol, max_iter):
    """The AGM loop of Bulirsch's cel after its first step (arrays, updated in place)."""
    active = np.abs(g - k) > g * tol
    for _ in range(max_iter):
        if not np.any(active):
            break
        i = active
        k_i = 2.0 * np.sqrt(kk[i])
        kk_i = k_i * em[i]
        f_i = cc[i]
        cc[i] = cc[i] + ss[i] / pp[i]
        g_i = kk_i / pp[i]
        ss[i] = 2.0 * (ss[i] + f_i * g_i)
        pp[i] = g_i + pp[i]
        g[i] = em[i]
        em[i] = k_i + em[i]
        k[i] = k_i
        kk[i] = kk_i
        active = active & (np.abs(g - k) > g * tol)
    return _HALF_PI * (ss + cc * em) / (em * (em + pp))


def cel(kc, p, c, s, *, tol: float = 1e-9, max_iter: int = 60) -> np.ndarray:
    """Bulirsch's complete elliptic integral cel(kc, p, c, s) (Derby & Olbert 2010, appendix).

    Special cases: K(m) = cel(sqrt(1-m), 1, 1, 1), E(m) = cel(sqrt(1-m), 1, 1, 1-m). The iteration
    is an arithmetic-geometric mean and converges quadratically; it stops when the relative gap is
    below `tol` (so the error is ~tol^2). kc = 0 (a singular point) gives NaN.
    """
    kc, p, c, s = (np.array(v, dtype=float) for v in np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (kc, p, c, s))))
    shape = kc.shape
    kc, p, c, s = (v.ravel() for v in (kc, p, c, s))
    k = np.abs(kc)
    pp = p.copy()
    cc = c.copy()
    ss = s.copy()
    with np.errstate(divide="ignore", invalid="ignore"):
        pos = p > 0
        pp[pos] = np.sqrt(p[pos])
        ss[pos] = s[pos] / pp[pos]
        neg = ~pos
        if np.any(neg):
            f = kc[neg] ** 2
            q = 1.0 - f
            g = 1.0 - p[neg]
            f = f - p[neg]
            q = q * (s[neg] - c[neg] * p[neg])
            ppn = np.sqrt(f / g)
            ccn = (c[neg] - s[neg]) / g
            pp[neg] = ppn
            cc[neg] = ccn
            ss[neg] = -q / (g * g * ppn) + ccn * ppn
        f = cc.copy()
        cc = cc + ss / pp
        g = k / pp
        ss = 2.0 * (ss + f * g)
        pp = g + pp
        em = k + 1.0
        out = _cel_iterate(k, cc, ss, pp, em, k.copy(), np.ones_like(k), tol, max_iter)
    out[kc == 0] = np.nan
    return out.reshape(shape)


def _cel_p1(kc, c_plus_s, s_plus_c_kc, *, tol: float = 1e-9, max_iter: int = 60) -> np.ndarray:
    """cel(kc, 1, c, s) given c + s and s + c kc directly: Bulirsch's algorithm with p = 1 depends
    on (c, s) only through these two after its first step. When they are small (c ~ -s, kc ~ 1:
    B_rho near the axis or far away) the caller computes them without cancellation, e.g. for
    (c, s) = (1, -kc^2): c + s = m = 1 - kc^2, s + c kc = kc m / (1 + kc)."""
    k = np.array(np.abs(kc), dtype=float).ravel()
    cc = np.array(c_plus_s, dtype=float) * np.ones_like(k)
    ss = 2.0 * np.array(s_plus_c_kc, dtype=float) * np.ones_like(k)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = _cel_iterate(k, cc.ravel().copy(), ss.ravel().copy(), k + 1.0, k + 1.0, k.copy(),
                           np.ones_like(k), tol, max_iter)
    out[k == 0] = np.nan
    return out


def _to_cartesian(pts: np.ndarray, b_rho: np.ndarray, b_z: np.ndarray) -> np.ndarray:
    x, y = pts[:, 0], pts[:, 1]
    rho = np.hypot(x, y)
    with np.errstate(divide="ignore", invalid="ignore"):
        cphi = np.where(rho > 0, x / rho, 1.0)
        sphi = np.where(rho > 0, y / rho, 0.0)
    return np.stack([b_rho * cphi, b_rho * sphi, b_z], axis=1)


def loop_field(points, radius: float, current: float, z0: float = 0.0) -> np.ndarray:
    """B of a circular current loop of radius a in the plane z = z0, current I (counter-clockwise
    seen from +z, so B_z > 0 at the centre): on the axis B_z = mu0 I a^2 / (2 (a^2 + z^2)^1.5).

    With zeta = z - z0, D = (a + rho)^2 + zeta^2, kc^2 = ((a - rho)^2 + zeta^2) / D, m = 1 - kc^2,
    the textbook form (Jackson eq. 5.37 differentiated; Simpson et al. 2013)

        B_z   = mu0 I / (2 pi sqrt(D)) [K + (a^2 - rho^2 - zeta^2) / ((a-rho)^2 + zeta^2) E]
        B_rho = mu0 I zeta / (2 pi rho sqrt(D)) [-K + (a^2 + rho^2 + zeta^2) / ((a-rho)^2 + zeta^2) E]

    is rewritten with K = cel(kc,1,1,1), E = cel(kc,1,1,kc^2) and linearity of cel in (c, s):

        B_z   = mu0 I a / (pi D^1.5) cel(kc, 1, (a - rho) / kc^2, a + rho)
        B_rho = mu0 I a zeta / (pi D^1.5 kc^2) cel(kc, 1, 1, -kc^2)

    with cel(kc, 1, 1, -kc^2) = O(m) started from m = 4 a rho / D (see `_cel_p1`), which has no 1/rho
    (the limit rho -> 0 is the value at rho = 0: B_rho = 0, B_z on-axis) and no
    difference of large terms far away. Singular: the wire (rho = a, z = z0) -> NaN.
    """
    pts = _points(points)
    a = float(radius)
    rho = np.hypot(pts[:, 0], pts[:, 1])
    zeta = pts[:, 2] - z0
    dd = (a + rho) ** 2 + zeta**2
    n2 = (a - rho) ** 2 + zeta**2
    with np.errstate(divide="ignore", invalid="ignore"):
        kc2 = n2 / dd
        kc = np.sqrt(kc2)
        pref = MU0 * current * a / (math.pi * dd**1.5)
        bz = pref * cel(kc, 1.0, (a - rho) / kc2, a + rho)
        m = 4.0 * a * rho / dd                    # = 1 - kc^2, without the subtraction
        br = pref * zeta / kc2 * _cel_p1(kc, m, kc * m / (1.0 + kc))
    wire = n2 == 0
    bz[wire] = np.nan
    br[wire] = np.nan
    return _to_cartesian(pts, br, bz)


_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(24)


def _far_from_slab(rho: np.ndarray, z: np.ndarray, r_lo: float, r_hi: float, z_lo: float,
                   z_hi: float) -> np.ndarray:
    """Points whose distance in the (rho, z) half-plane from the rectangle [r_lo, r_hi] x [z_lo, z_hi]
    is at least its height h = z_hi - z_lo. There, a 24-point Gauss-Legendre sum over the height
    converges to ~1e-30: the integrand's nearest complex singularity lies >= h away, a Bernstein
    ellipse parameter >= 2 + sqrt(5)."""
    h = z_hi - z_lo
    dr = np.maximum(np.maximum(r_lo - rho, rho - r_hi), 0.0)
    dz = np.maximum(np.maximum(z_lo - z, z - z_hi), 0.0)
    return np.hypot(dr, dz) >= h


def _gauss_over_height(points: np.ndarray, z_lo: float, z_hi: float,
                       layer: Callable[[np.ndarray, float], np.ndarray]) -> np.ndarray:
    half, mid = 0.5 * (z_hi - z_lo), 0.5 * (z_hi + z_lo)
    out = np.zeros((len(points), 3))
    for node, weight in zip(_GL_NODES, _GL_WEIGHTS):
        out += (weight * half) * layer(points, mid + half * node)
    return out


def _derby_olbert(pts: np.ndarray, a: float, z_lo: float, z_hi: float, k_surf: float) -> np.ndarray:
    rho = np.hypot(pts[:, 0], pts[:, 1])
    z = pts[:, 2]
    b0 = MU0 * k_surf / math.pi
    gamma = (a - rho) / (a + rho)
    br = np.zeros_like(rho)
    bz = np.zeros_like(rho)
    with np.errstate(divide="ignore", invalid="ignore"):
        for sign, zend in ((1.0, z_lo), (-1.0, z_hi)):
            zz = z - zend
            root = np.sqrt(zz**2 + (rho + a) ** 2)
            alpha = a / root
            beta = zz / root
            k = np.sqrt(zz**2 + (a - rho) ** 2) / root
            m = 4.0 * a * rho / root**2           # 1 - k^2; cel(k,1,1,-1): c + s = 0, s + c k = k - 1
            br += sign * alpha * _cel_p1(k, 0.0, -m / (1.0 + k))
            bz += sign * beta * cel(k, gamma**2, 1.0, gamma)
    return _to_cartesian(pts, b0 * br, b0 * a / (a + rho) * bz)


def solenoid_field(points, radius: float, z_lo: float, z_hi: float, surface_current: float) -> np.ndarray:
    """B of an ideal solenoid: an azimuthal surface current K (A/m) on the cylinder rho = a,
    z_lo <= z <= z_hi (Derby & Olbert 2010, their eqs. for B_rho and B_z):

        B0 = mu0 K / pi, alpha = a / sqrt(z^2 + (rho+a)^2), beta = z / sqrt(z^2 + (rho+a)^2),
        gamma = (a - rho)/(a + rho), k = sqrt((z^2 + (a-rho)^2) / (z^2 + (a+rho)^2))
        B_rho = B0 [alpha_+ cel(k_+, 1, 1, -1) - alpha_- cel(k_-, 1, 1, -1)]
        B_z   = B0 a/(a + rho) [beta_+ cel(k_+, gamma^2, 1, gamma) - beta_- cel(k_-, gamma^2, 1, gamma)]

    where + has z measured from the lower end (z - z_lo) and - from the upper end (z - z_hi). Valid
    inside and outside the sheet and on the axis (rho = 0: gamma = 1, k = 1, B_rho = 0).

    Far from the sheet the two end terms are nearly equal and their difference loses digits
    (relative error ~ eps d^3 / (h a^2) at distance d); there (distance >= the height h, see
    `_far_from_slab`) the field is instead the sum of loops over the height (the solenoid is a stack
    of loops, K dz each) by 24-point Gauss-Legendre, each loop by the cancellation-free `loop_field`.
    Singular: the two end circles (NaN); on the sheet itself B_z is the mean of inside and outside.
    """
    pts = _points(points)
    rho = np.hypot(pts[:, 0], pts[:, 1])
    far = _far_from_slab(rho, pts[:, 2], radius, radius, z_lo, z_hi)
    out = np.empty((len(pts), 3))
    if np.any(~far):
        out[~far] = _derby_olbert(pts[~far], float(radius), z_lo, z_hi, surface_current)
    if np.any(far):
        out[far] = _gauss_over_height(pts[far], z_lo, z_hi,
                                      lambda p, zz: loop_field(p, radius, surface_current, zz))
    return out


def annulus_field(points, a: float, w: float, dipole_density: float) -> np.ndarray:
    """The thesis's thin annulus (thesis eq. 2.2.11; w = 0 is the thin disk) in z = 0 as a dipole
    layer of density D (A m^2 per m^2 = A), rho_thesis = mu0 D / (4 pi): the loop at a minus the
    loop at w, each carrying I = D. Singular: the two rims (NaN)."""
    out = loop_field(points, a, dipole_density)
    if w > 0:
        out = out - loop_field(points, w, dipole_density)
    return out


def ring_magnet_field(points, r_out: float, r_in: float, thickness: float, magnetization: float) -> np.ndarray:
    """An axially magnetised ring magnet (r_in = 0: solid cylinder), magnetisation M (A/m) along +z,
    occupying r_in <= rho <= r_out, -t <= z <= 0 (top face in z = 0, docs/contract.md). Equivalent surface
    currents K = M on the outer and -M on the inner mantle (Jackson sec. 5.8); Derby & Olbert (2010).
    On the axis of a solid cylinder B_z = (mu0 M/2)[(z+t)/sqrt((z+t)^2+R^2) - z/sqrt(z^2+R^2)]. The
    result is B everywhere, inside the magnet included."""
    out = solenoid_field(points, r_out, -thickness, 0.0, magnetization)
    if r_in > 0:
        out = out - solenoid_field(points, r_in, -thickness, 0.0, magnetization)
    return out


def _asinh_ratio(num: np.ndarray, den2: np.ndarray) -> np.ndarray:
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.arcsinh(num / np.sqrt(den2))


def charged_rectangle_h(points, x1: float, x2: float, y1: float, y2: float, z0: float,
                        sigma: float) -> np.ndarray:
    """H (A/m) of a uniform surface charge sigma (A/m) on x1<=x<=x2, y1<=y<=y2, z = z0 (Furlani 2001
    sec. 4.3): with u_i = x - x_i, v_j = y - y_j, w = z - z0, H = sigma/(4 pi) grad-free sums

        H_x = sigma/(4 pi) sum_ij s_ij asinh(v_j / sqrt(u_i^2 + w^2)) * (-1)
        H_y = sigma/(4 pi) sum_ij s_ij asinh(u_i / sqrt(v_j^2 + w^2)) * (-1)
        H_z = sigma/(4 pi) sum_ij s_ij atan(u_i v_j / (w R_ij))

    with s_ij = +1 for (i,j) = (1,1),(2,2), -1 otherwise, R_ij = sqrt(u_i^2 + v_j^2 + w^2).
    (log(v + R) = asinh(v / sqrt(u^2 + w^2)) + log sqrt(u^2 + w^2), and the second part cancels in
    the alternating sum, so asinh replaces the cancelling log of the textbook form.) On the face
    (w = 0) H_z is the mean of the two sides, 0; the edges are singular (NaN or inf).
    """
    pts = _points(points)
    u = (pts[:, 0] - x1, pts[:, 0] - x2)
    v = (pts[:, 1] - y1, pts[:, 1] - y2)
    w = pts[:, 2] - z0
    hx = np.zeros(len(pts))
    hy = np.zeros(len(pts))
    hz = np.zeros(len(pts))
    with np.errstate(divide="ignore", invalid="ignore"):
        for i in range(2):
            for j in range(2):
                sgn = 1.0 if i == j else -1.0
                R = np.sqrt(u[i] ** 2 + v[j] ** 2 + w**2)
                hx -= sgn * _asinh_ratio(v[j], u[i] ** 2 + w**2)
                hy -= sgn * _asinh_ratio(u[i], v[j] ** 2 + w**2)
                hz += sgn * np.where(w == 0, 0.0, np.arctan(u[i] * v[j] / (w * R)))
    return sigma / (4 * math.pi) * np.stack([hx, hy, hz], axis=1)


def block_field(points, side_x: float, side_y: float, thickness: float, magnetization: float) -> np.ndarray:
    """A rectangular block magnet, sides side_x * side_y centred on the z axis, -t <= z <= 0 (top
    face in z = 0), uniformly magnetised M (A/m) along +z: surface charges +M on the top face and -M
    on the bottom (Furlani 2001 sec. 4.3). B = mu0 (H + M), M counted inside the block only.

    Far from the block (distance >= t from it) the two faces' fields cancel to O(t/d); there the
    block is instead summed as a stack of rectangular current loops (its side-face currents, K = M)
    by 24-point Gauss-Legendre over the height, each loop by Biot-Savart (`rect_loop_field`).
    """
    pts = _points(points)
    hx, hy = side_x / 2, side_y / 2
    dx = np.maximum(np.abs(pts[:, 0]) - hx, 0.0)
    dy = np.maximum(np.abs(pts[:, 1]) - hy, 0.0)
    dz = np.maximum(np.maximum(-thickness - pts[:, 2], pts[:, 2]), 0.0)
    far = np.sqrt(dx**2 + dy**2 + dz**2) >= thickness
    b = np.empty((len(pts), 3))
    if np.any(~far):
        near = pts[~far]
        h = charged_rectangle_h(near, -hx, hx, -hy, hy, 0.0, magnetization)
        h -= charged_rectangle_h(near, -hx, hx, -hy, hy, -thickness, magnetization)
        bn = MU0 * h
        inside = ((np.abs(near[:, 0]) < hx) & (np.abs(near[:, 1]) < hy)
                  & (near[:, 2] < 0) & (near[:, 2] > -thickness))
        bn[inside, 2] += MU0 * magnetization
        b[~far] = bn
    if np.any(far):
        b[far] = _gauss_over_height(pts[far], -thickness, 0.0,
                                    lambda p, zz: rect_loop_field(p, side_x, side_y, magnetization, zz))
    return b


def segment_field(points, start, end, current: float) -> np.ndarray:
    """Biot-Savart field of a straight segment start -> end carrying I (Hanson & Hirshman 2002):
    B = mu0 I / (4 pi) (r1 x r2) (|r1| + |r2|) / (|r1| |r2| (|r1| |r2| + r1 . r2)),  r_i = r - end_i.
    Singular: the segment itself (NaN)."""
    pts = _points(points)
    r1 = pts - np.asarray(start, dtype=float)
    r2 = pts - np.asarray(end, dtype=float)
    n1 = np.linalg.norm(r1, axis=1)
    n2 = np.linalg.norm(r2, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        fac = (n1 + n2) / (n1 * n2 * (n1 * n2 + np.einsum("ij,ij->i", r1, r2)))
        out = MU0 * current / (4 * math.pi) * np.cross(r1, r2) * fac[:, None]
    out[~np.isfinite(fac)] = np.nan
    return out


def rect_loop_field(points, side_x: float, side_y: float, current: float, z0: float = 0.0) -> np.ndarray:
    """A rectangular current loop centred on the z axis in z = z0, counter-clockwise seen from +z.
    A thin rectangular dipole layer of density D (A) is this loop with I = D."""
    hx, hy = side_x / 2, side_y / 2
    corners = [(hx, -hy, z0), (hx, hy, z0), (-hx, hy, z0), (-hx, -hy, z0)]
    out = np.zeros((len(_points(points)), 3))
    for k in range(4):
        out += segment_field(points, corners[k], corners[(k + 1) % 4], current)
    return out


def dipole_density(rho: float) -> float:
    """Dipole density D (A) of a thin plate from its resolved rho (T m): rho = mu0 D / (4 pi)."""
    return 4 * math.pi * rho / MU0
