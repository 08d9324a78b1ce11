"""Phi_1..Phi_4 of the thin annulus (thesis eq. 2.2.11) in double precision against 50-digit mpmath
: relative error <= 1e-12 for z from 1e-3 a to 1e3 a and w/a in {0, 1e-3, 0.3, 0.999},
with the cancellation-free forms of derive/onaxis.py; the textbook forms (thesis eqs. 2.2.12-2.2.14,
i.e. eq. 2.2.11 differentiated by the product rule) fail the same test.

Relative error near a zero of Phi_k (docs/contract.md: "taken against the size of its terms"): Phi_k has
true zeros in this range (B_z of an annulus changes sign on the axis), where no formula can give a
small relative error, because z itself carries a rounding error of eps*|z|. The yardstick is
therefore |Phi_k(z)| + |z Phi_{k+1}(z)|: the size of Phi_k plus the change of Phi_k under a relative
change of z of order one -- which equals |Phi_k| away from zeros (up to a factor ~k) and is the size
of the terms of Phi_k's Taylor expansion at a zero. The test also reports the plain relative error.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
import sympy as sp

from levitron.derive import onaxis

z, a, w, rho = sp.symbols("z a w rho", real=True)
RATIOS = [0.0, 1e-3, 0.3, 0.999]
A_VAL = 0.1                      # an SI plate radius; the forms are scale-free anyway
ZS = A_VAL * np.geomspace(1e-3, 1e3, 61)
KMAX = 4


@pytest.fixture(scope="module")
def forms():
    stable = onaxis.annulus_phis(z, a, w, 2 * sp.pi * rho)
    naive = onaxis.textbook_annulus_phis(z, a, w, 2 * sp.pi * rho)
    args = (z, a, w, rho)
    return {
        "stable": [sp.lambdify(args, stable(k), "math") for k in range(KMAX + 1)],
        "naive": [sp.lambdify(args, naive(k), "math") for k in range(KMAX + 1)],
        "exact": [sp.lambdify(args, naive(k), "mpmath") for k in range(KMAX + 2)],
    }


def _errors(forms, which, ratio, k):
    mp.mp.dps = 50
    wv = ratio * A_VAL
    worst_scaled = worst_plain = 0.0
    for zv in ZS:
        ref = forms["exact"][k](mp.mpf(zv), mp.mpf(A_VAL), mp.mpf(wv), 1)
        ref1 = forms["exact"][k + 1](mp.mpf(zv), mp.mpf(A_VAL), mp.mpf(wv), 1)
        got = forms[which][k](float(zv), A_VAL, wv, 1.0)
        err = abs(mp.mpf(got) - ref)
        worst_scaled = max(worst_scaled, float(err / (abs(ref) + abs(zv * ref1))))
        worst_plain = max(worst_plain, float(err / abs(ref)))
    return worst_scaled, worst_plain


@pytest.mark.parametrize("ratio", RATIOS)
def test_annulus_phi_k_precision(forms, ratio):
    for k in range(1, KMAX + 1):
        scaled, plain = _errors(forms, "stable", ratio, k)
        print(f"w/a={ratio} Phi_{k}: {scaled:.2e} (plain relative {plain:.2e})")
        assert scaled <= 1e-12, (ratio, k, scaled)


@pytest.mark.parametrize("ratio", RATIOS)
def test_textbook_forms_fail_the_same_test(forms, ratio):
    worst = max(_errors(forms, "naive", ratio, k)[0] for k in range(1, KMAX + 1))
    print(f"w/a={ratio} textbook worst {worst:.2e}")
    assert worst > 1e-11, (ratio, worst)


def test_stable_forms_equal_textbook_symbolically_at_a_point():
    """Same function, not only the same numbers: agreement at 40 digits at an arbitrary point."""
    mp.mp.dps = 40
    stable = onaxis.annulus_phis(z, a, w, 2 * sp.pi * rho)
    naive = onaxis.textbook_annulus_phis(z, a, w, 2 * sp.pi * rho)
    pt = {z: sp.Rational(37, 100), a: sp.Rational(1, 10), w: sp.Rational(3, 100), rho: 1}
    for k in range(0, 7):
        d = sp.N(stable(k).subs(pt) - naive(k).subs(pt), 40)
        assert abs(d) < sp.Float("1e-30") * (1 + abs(sp.N(naive(k).subs(pt), 40))), k


@pytest.mark.parametrize("kind", ["disk", "cylinder"])
def test_other_stable_forms(kind):
    """The disk/loop and cylinder-magnet forms: same precision target (Phi_1..Phi_4 far away too)."""
    mp.mp.dps = 50
    R, T = 0.05, 0.02
    t = sp.Symbol("t", real=True)
    if kind == "disk":
        st = onaxis.disk_phis(z, a, 1)
        exact = lambda k: sp.diff(1 - z / sp.sqrt(z**2 + a**2), z, k)  # noqa: E731
    else:
        st = onaxis.cylinder_phis(z, a, t, 1)
        exact = lambda k: sp.diff(-(sp.sqrt((z + t) ** 2 + a**2) - sp.sqrt(z**2 + a**2)), z, k)  # noqa: E731
    for k in range(1, KMAX + 1):
        f = sp.lambdify((z, a, t), st(k), "math")
        g0 = sp.lambdify((z, a, t), exact(k), "mpmath")
        g1 = sp.lambdify((z, a, t), exact(k + 1), "mpmath")
        worst = 0.0
        for zv in R * np.geomspace(1e-3, 1e3, 41):
            args = (mp.mpf(zv), mp.mpf(R), mp.mpf(T))
            ref, ref1 = g0(*args), g1(*args)
            worst = max(worst, float(abs(f(zv, R, T) - ref) / (abs(ref) + abs(zv * ref1))))
        print(f"{kind} Phi_{k}: {worst:.2e}")
        assert worst <= 1e-12, (kind, k, worst)
