"""The expansion order from an accuracy target (scene keys field.tolerance, field.radius).

The Laplace expansion of thesis eqs. 2.2.2-2.2.7 truncated at order n in r,

    phi_n(r, z) = sum_{j <= n/2} (-1)^j r^(2j) / (4^j (j!)^2) Phi_{2j}(z),   B = -grad(phi_n),

is compared with the exact field of the plate, and the lowest even n whose error stays within the
tolerance is chosen. The exact field is computed here, in derive (which never imports runtime), for
any axisymmetric plate from its on-axis potential alone, by Whittaker's integral representation of
an axisymmetric harmonic function (E. T. Whittaker and G. N. Watson, "A Course of Modern Analysis",
sec. 18.3; W. R. Smythe, "Static and Dynamic Electricity", sec. 5.12):

    phi(r, z) = (1/pi) int_0^pi Phi0(z + i r cos t) dt,
    B_z = -(1/pi) int_0^pi Re Phi_1(z + i r cos t) dt,
    B_r = -(1/pi) int_0^pi Re[i cos t Phi_1(z + i r cos t)] dt.

For z > 0 the path stays in Re z' > 0, where the plates' Phi0 (built from sqrt(z'^2 + s^2) with the
principal branch; the cut lies on Re z' = 0) is analytic, so this is the true field above the plate
(tests compare it with the closed forms of runtime/physics/exact_field.py). The integrand is smooth and
periodic-like, and Gauss-Legendre with 96 nodes is checked against 192.

Error measure: max over the grid (0 <= r <= radius, z in the heights) of |B_n - B| divided by the
largest |B| on the grid (a relative error that stays meaningful where B_z changes sign).
Heights: by default the band around the vertical equilibria of the top (mu Phi_2(z) + m g = 0,
thesis eq. 3.2.12), from 0.8 of the lowest to 1.2 of the highest; else [0.5 L, 3 L] with L the
plate's size.
"""
from __future__ import annotations

import math

import numpy as np
import sympy as sp

from levitron.scene.load import Scene, SceneError

from .field import laplace_coefficients
from .geometry import Plate, build_plate
from .symbols import Z

MAX_ORDER = 12
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(96)
_NODES2, _WEIGHTS2 = np.polynomial.legendre.leggauss(192)


def _numeric_phis(plate: Plate, params: dict, kmax: int):
    """Phi_0..Phi_kmax as numpy functions of z (complex z allowed), parameters substituted."""
    values = {s: params[s.name] for s in plate.symbols}
    derivs = plate.phi_derivs(kmax)
    return [sp.lambdify(Z, d.xreplace(values), "numpy") for d in derivs]


def whittaker_field(phi1, r: np.ndarray, z: np.ndarray, nodes=_NODES, weights=_WEIGHTS):
    """(B_r, B_z) of the axisymmetric field whose on-axis Phi_1 is `phi1` (numpy, complex-capable),
    by Whittaker's integral (module docstring), Gauss-Legendre on t in [0, pi]."""
    r = np.asarray(r, dtype=float)[..., None]
    z = np.asarray(z, dtype=float)[..., None]
    t = 0.5 * math.pi * (nodes + 1.0)
    w = 0.5 * math.pi * weights
    c = np.cos(t)
    vals = np.asarray(phi1(z + 1j * r * c), dtype=complex) * np.ones_like(r * c)
    bz = -(vals.real * w).sum(axis=-1) / math.pi
    br = -((1j * c * vals).real * w).sum(axis=-1) / math.pi
    return br, bz


def expansion_field(phis, order: int, r: np.ndarray, z: np.ndarray):
    """(B_r, B_z) of the expansion to `order` (thesis eqs. 2.2.6-2.2.7 generalised)."""
    coeffs = [float(c) for c in laplace_coefficients(order)]
    br = np.zeros_like(r, dtype=float)
    bz = np.zeros_like(r, dtype=float)
    for j, c in enumerate(coeffs):
        if j:
            br -= 2 * j * c * r ** (2 * j - 1) * np.asarray(phis[2 * j](z), dtype=float)
        bz -= c * r ** (2 * j) * np.asarray(phis[2 * j + 1](z), dtype=float)
    return br, bz


def default_heights(scene: Scene, phis) -> tuple[float, float]:
    """The band around the vertical equilibria: mu Phi_2(z) + m g = 0 (thesis eq. 3.2.12), on
    heights scaled by the plate's length (Scene.length_scale, from the plate registry)."""
    p = scene.params
    size = scene.length_scale
    zs = size * np.geomspace(1e-3, 1e3, 4000)
    f = p["mu"] * np.asarray(phis[2](zs), dtype=float) + p["m"] * p["g"]
    roots = [zs[i] for i in range(len(zs) - 1) if np.sign(f[i]) != np.sign(f[i + 1])]
    if roots:
        return 0.8 * min(roots), 1.2 * max(roots)
    return 0.5 * size, 3.0 * size


def order_errors(plate: Plate, params: dict, radius: float, z_range: tuple[float, float],
                 orders=range(2, MAX_ORDER + 1, 2), n_r: int = 9, n_z: int = 15) -> dict[int, float]:
    """{order: error} for the given even orders (module docstring: error measure)."""
    kmax = max(orders) + 1
    phis = _numeric_phis(plate, params, kmax)
    rr, zz = np.meshgrid(np.linspace(0.0, radius, n_r), np.linspace(z_range[0], z_range[1], n_z))
    br, bz = whittaker_field(phis[1], rr, zz)
    br2, bz2 = whittaker_field(phis[1], rr, zz, _NODES2, _WEIGHTS2)
    scale = float(np.max(np.hypot(br, bz)))
    quad_err = float(np.max(np.hypot(br - br2, bz - bz2))) / scale
    out = {}
    for n in orders:
        er, ez = expansion_field(phis, n, rr, zz)
        out[n] = max(float(np.max(np.hypot(er - br, ez - bz))) / scale, quad_err)
    return out


def choose_order(scene_or_plate, tolerance: float, radius: float, z_range=None,
                 params: dict | None = None) -> tuple[int, float]:
    """The lowest even order whose off-axis field error (module docstring) is <= tolerance within
    `radius` of the axis over the heights `z_range` (default: around the equilibria); returns
    (order, measured error). Called by derive/build.py as choose_order(scene, tolerance, radius).

    A non-axisymmetric plate (rectangle) has its exact field in the model: order 2, error 0; one
    with axisymmetric parts besides (a hole, a compound's rings) gets the order of their expansion.
    Raises SceneError when even order MAX_ORDER misses the target (the expansion's radius of
    convergence at height z is the distance to the plate's complex singularities, ~z)."""
    if isinstance(scene_or_plate, Scene):
        scene = scene_or_plate
        plate = build_plate(scene.data["plate"])
        params = scene.params
    else:
        scene, plate = None, scene_or_plate
        if params is None:
            raise ValueError("choose_order(plate, ...) needs params (name -> SI value)")
    if plate.field3d is not None and plate.axial is None:
        return 2, 0.0
    if z_range is None:
        if scene is None:
            raise ValueError("choose_order(plate, ...) needs z_range")
        z_range = default_heights(scene, _numeric_phis(plate, params, 2))
    if plate.field3d is not None:
        # the exact field of the non-axisymmetric parts is in the model: the order is that of the
        # axial parts' expansion, judged on their field alone (stricter than on the whole plate's)
        plate = Plate(plate.kind, plate.axial(0), plate.symbols, plate.axial)
    errors = order_errors(plate, params, radius, z_range)
    for order in sorted(errors):
        if errors[order] <= tolerance:
            return order, errors[order]
    best = min(errors, key=errors.get)
    raise SceneError(f"field.tolerance = {tolerance:g} is not reached within field.radius = {radius:g} m "
                     f"at heights {z_range[0]:.3g}..{z_range[1]:.3g} m by any order up to {MAX_ORDER} "
                     f"(best: order {best}, error {errors[best]:.2g}): raise the tolerance or reduce "
                     "the radius")
