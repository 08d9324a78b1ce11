"""runtime/physics/field/exact_field.py against independent references: numerical Biot-Savart and surface-charge
quadrature (scipy), high-precision mpmath, the closed on-axis forms, and Maxwell's equations."""
from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest
from scipy import integrate, special

from levitron.runtime.physics.field import exact_field as ef

MU0 = ef.MU0
RNG = np.random.default_rng(20240505)


def test_cel_special_cases_and_quadrature():
    m = RNG.uniform(0, 0.999, 20)
    kc = np.sqrt(1 - m)
    assert np.allclose(ef.cel(kc, 1, 1, 1), special.ellipk(m), rtol=1e-15, atol=0)
    assert np.allclose(ef.cel(kc, 1, 1, 1 - m), special.ellipe(m), rtol=1e-15, atol=0)
    for kcv, p, c, s in [(0.3, 0.5, 1, -1), (0.9, 0.01, 1, 0.1), (0.2, 1, 2, -3), (1e-3, 1e-6, 1, 1e-3)]:
        f = lambda t: ((c * math.cos(t) ** 2 + s * math.sin(t) ** 2)  # noqa: E731
                       / ((math.cos(t) ** 2 + p * math.sin(t) ** 2)
                          * math.sqrt(math.cos(t) ** 2 + kcv**2 * math.sin(t) ** 2)))
        ref = integrate.quad(f, 0, math.pi / 2, epsabs=0, epsrel=1e-13, limit=500)[0]
        assert ef.cel(kcv, p, c, s) == pytest.approx(ref, rel=1e-13)


def _loop_mp(rho, zeta, a, current):
    """Textbook K/E loop field (Jackson 5.37 differentiated) at 40 digits: (B_rho, B_z)."""
    mp.mp.dps = 40
    rho, zeta, a = mp.mpf(rho), mp.mpf(zeta), mp.mpf(a)
    d = (a + rho) ** 2 + zeta**2
    n = (a - rho) ** 2 + zeta**2
    m = 4 * a * rho / d
    K, E = mp.ellipk(m), mp.ellipe(m)
    c = mp.mpf(MU0) * current / (2 * mp.pi * mp.sqrt(d))
    bz = c * (K + (a**2 - rho**2 - zeta**2) / n * E)
    br = c * zeta / rho * (-K + (a**2 + rho**2 + zeta**2) / n * E) if rho else mp.mpf(0)
    return br, bz


@pytest.mark.parametrize("rho,zeta", [(0.03, 0.02), (0.2, -0.05), (1e-7, 0.1), (0.0, 0.1),
                                      (0.1, 1e-4), (0.5, 30.0), (3.0, 100.0), (0.099, 0.001)])
def test_loop_against_mpmath(rho, zeta):
    a, cur = 0.1, 2.5
    br, bz = _loop_mp(rho, zeta, a, cur)
    B = ef.loop_field([[rho, 0.0, zeta]], a, cur)[0]
    scale = float(mp.sqrt(br**2 + bz**2))
    assert abs(B[0] - float(br)) <= 1e-14 * scale
    assert abs(B[2] - float(bz)) <= 1e-14 * scale
    assert B[1] == 0.0


def test_loop_near_axis_has_no_cancellation():
    """B_rho ~ rho near the axis: relative accuracy of B_rho itself, where K/E in double fails."""
    a, cur = 0.1, 1.0
    for rho in (1e-4, 1e-6, 1e-8):
        br, _ = _loop_mp(rho, 0.05, a, cur)
        B = ef.loop_field([[rho, 0.0, 0.05]], a, cur)[0]
        assert B[0] == pytest.approx(float(br), rel=1e-9)


def _biot_savart_loop(p, a, current):
    def comp(c):
        def f(t):
            l = np.array([a * math.cos(t), a * math.sin(t), 0.0])  # noqa: E741
            dl = np.array([-a * math.sin(t), a * math.cos(t), 0.0])
            r = p - l
            return np.cross(dl, r)[c] / np.linalg.norm(r) ** 3
        return integrate.quad(f, 0, 2 * math.pi, epsabs=0, epsrel=1e-12, limit=400)[0]
    return MU0 * current / (4 * math.pi) * np.array([comp(c) for c in range(3)])


def test_loop_against_biot_savart_quadrature():
    pts = np.array([[0.01, 0.02, 0.03], [0.2, -0.1, 0.05], [0.3, 0.4, -2.0]])
    B = ef.loop_field(pts, 0.1, 2.0)
    for p, b in zip(pts, B):
        ref = _biot_savart_loop(p, 0.1, 2.0)
        assert np.max(np.abs(b - ref)) <= 1e-11 * np.linalg.norm(ref)


def test_annulus_is_two_loops_and_matches_axis_formula():
    a, w, D = 0.1, 0.03, 1234.0
    z = np.geomspace(1e-3, 10, 30)
    pts = np.stack([0 * z, 0 * z, z], axis=1)
    bz = ef.annulus_field(pts, a, w, D)[:, 2]
    want = MU0 * D / 2 * (a**2 / (z**2 + a**2) ** 1.5 - w**2 / (z**2 + w**2) ** 1.5)
    assert np.allclose(bz, want, rtol=1e-13, atol=0)


def test_solenoid_against_loop_stack_quadrature():
    a, zl, zh, K = 0.1, -0.02, 0.0, 1000.0
    for p in np.array([[0.01, 0.02, 0.03], [0.2, -0.1, 0.05], [1e-9, 0, 0.1], [0.05, 0.0, 0.001],
                       [0.05, 0.0, -0.01], [0.15, 0.0, -0.01]]):
        b = ef.solenoid_field(p[None, :], a, zl, zh, K)[0]
        ref = np.array([integrate.quad(lambda zz: ef.loop_field(p[None, :], a, K, zz)[0, c], zl, zh,
                                       epsabs=0, epsrel=1e-13, limit=200)[0] for c in range(3)])
        assert np.max(np.abs(b - ref)) <= 1e-12 * np.linalg.norm(ref), p


def test_derby_olbert_and_gauss_branches_agree():
    """Both ways of summing the sheet agree where both are accurate (just outside the switch)."""
    a, zl, zh, K = 0.05, -0.02, 0.0, 1.0
    pts = np.array([[0.0, 0.0, 0.021], [0.03, 0.0, 0.025], [0.09, 0.0, -0.01], [0.2, 0.1, 0.05]])
    far = ef._gauss_over_height(pts, zl, zh, lambda p, zz: ef.loop_field(p, a, K, zz))
    do = ef._derby_olbert(pts, a, zl, zh, K)
    assert np.allclose(far, do, rtol=1e-13, atol=1e-15 * np.abs(do).max())


def test_cylinder_axis_closed_form_and_far_field_mpmath():
    R, t, M = 0.05, 0.02, 9e5
    mp.mp.dps = 40
    for zv in (1e-3, 0.05, 1.0, 100.0):
        B = ef.ring_magnet_field([[0.0, 0.0, zv]], R, 0.0, t, M)[0]
        Z, T, RR = mp.mpf(zv), mp.mpf(t), mp.mpf(R)
        ref = mp.mpf(MU0) * M / 2 * ((Z + T) / mp.sqrt((Z + T) ** 2 + RR**2) - Z / mp.sqrt(Z**2 + RR**2))
        assert B[2] == pytest.approx(float(ref), rel=1e-13)
        assert B[0] == 0 and B[1] == 0


def test_ring_is_outer_minus_inner_cylinder():
    pts = RNG.uniform(-0.1, 0.1, (20, 3)) + np.array([0, 0, 0.12])
    ring = ef.ring_magnet_field(pts, 0.05, 0.02, 0.01, 1e5)
    diff = ef.ring_magnet_field(pts, 0.05, 0, 0.01, 1e5) - ef.ring_magnet_field(pts, 0.02, 0, 0.01, 1e5)
    assert np.allclose(ring, diff, rtol=1e-12, atol=1e-18)


def _block_quad(p, sx, sy, t, M):
    out = np.zeros(3)
    for z0, sig in ((0.0, M), (-t, -M)):
        for c in range(3):
            def f(y, x):
                r = p - np.array([x, y, z0])
                return r[c] / np.linalg.norm(r) ** 3
            out[c] += sig / (4 * math.pi) * integrate.dblquad(f, -sx / 2, sx / 2, -sy / 2, sy / 2,
                                                              epsabs=0, epsrel=1e-11)[0]
    return MU0 * out


@pytest.mark.parametrize("p", [[0.01, 0.02, 0.03], [0.2, -0.1, 0.05], [0.0, 0.0, 0.1]])
def test_block_against_surface_charge_quadrature(p):
    p = np.array(p)
    b = ef.block_field(p[None, :], 0.1, 0.15, 0.02, 8e5)[0]
    ref = _block_quad(p, 0.1, 0.15, 0.02, 8e5)
    assert np.max(np.abs(b - ref)) <= 1e-9 * np.linalg.norm(ref)


def test_thin_block_tends_to_rectangular_loop():
    p = np.array([[0.03, 0.01, 0.05], [0.2, 0.3, 0.1]])
    D = 100.0
    for t in (1e-4, 1e-5):
        blk = ef.block_field(p, 0.1, 0.15, t, D / t)
        loop = ef.rect_loop_field(p, 0.1, 0.15, D)
        assert np.allclose(blk, loop, rtol=3 * t / 0.05, atol=0)


def test_square_loop_against_circle_far_away():
    """Far away every flat loop is a dipole of moment I * area."""
    side, I = 0.1, 3.0
    p = np.array([[0.0, 0.0, 50.0], [30.0, 0.0, 40.0]])
    sq = ef.rect_loop_field(p, side, side, I)
    circ = ef.loop_field(p, side / math.sqrt(math.pi), I)
    assert np.allclose(sq, circ, rtol=1e-5, atol=0)


def _div_curl(f, p, h=2e-4):
    """Jacobian of B by 4th-order central differences; div and curl."""
    J = np.zeros((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        J[:, j] = (8 * (f(p + e) - f(p - e)) - (f(p + 2 * e) - f(p - 2 * e))) / (12 * h)
    return np.trace(J), np.array([J[2, 1] - J[1, 2], J[0, 2] - J[2, 0], J[1, 0] - J[0, 1]]), np.abs(J).max()


@pytest.mark.parametrize("name", ["loop", "ring", "block", "rect_loop"])
def test_maxwell_div_and_curl_vanish(name):
    fields = {
        "loop": lambda p: ef.loop_field(p[None, :], 0.1, 1.0)[0],
        "ring": lambda p: ef.ring_magnet_field(p[None, :], 0.05, 0.02, 0.01, 1e5)[0],
        "block": lambda p: ef.block_field(p[None, :], 0.1, 0.07, 0.02, 1e5)[0],
        "rect_loop": lambda p: ef.rect_loop_field(p[None, :], 0.1, 0.07, 1.0)[0],
    }
    for p in RNG.uniform([-0.15, -0.15, 0.01], [0.15, 0.15, 0.2], (5, 3)):
        div, curl, scale = _div_curl(fields[name], p)
        assert abs(div) <= 1e-6 * scale and np.abs(curl).max() <= 1e-6 * scale, (div, curl, scale)


def test_singular_points_are_nan_and_axis_is_finite():
    B = ef.loop_field([[0.1, 0.0, 0.0], [0.0, 0.0, 0.0]], 0.1, 1.0)
    assert np.all(np.isnan(B[0])) and np.all(np.isfinite(B[1]))
    B = ef.rect_loop_field([[0.05, 0.0, 0.0]], 0.1, 0.1, 1.0)
    assert np.all(np.isnan(B[0]))
