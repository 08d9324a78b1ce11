"""runtime/physics/routes/brent.py returns the double scipy.optimize.brentq returns (the same algorithm and
arithmetic), so the discriminant route's roots did not move when it replaced scipy's import."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq as scipy_brentq

from levitron.runtime.physics.routes.brent import RTOL_MIN, brentq


def _cases():
    rng = np.random.default_rng(20261201)
    for _ in range(1500):              # cubics with a root in the bracket, over many scales
        roots = np.sort(rng.uniform(-3, 3, 3)) * 10.0 ** rng.integers(-8, 9)
        coef = np.poly(roots) * 10.0 ** rng.integers(-20, 21)
        k = rng.integers(0, 3)
        lo = roots[k] - abs(rng.normal()) * (abs(roots[k]) + 1e-300) - 1e-300
        hi = roots[k] + abs(rng.normal()) * (abs(roots[k]) + 1e-300) + 1e-300
        yield (lambda x, c=coef: float(np.polyval(c, x))), float(lo), float(hi)
    yield math.cos, 0.0, 3.0
    yield (lambda x: x ** 3 - 2.0), 0.0, 2.0
    yield (lambda x: math.exp(x) - 1e-12), -40.0, 1.0
    yield (lambda x: math.atan(x - 0.3)), -1e6, 1e6      # flat far out: many bisections
    yield (lambda x: x), -1.0, 1.0                         # a root at an exact midpoint


@pytest.mark.parametrize("xtol, rtol", [(1e-300, RTOL_MIN), (2e-12, RTOL_MIN), (1e-6, 1e-10)])
def test_same_double_as_scipy(xtol, rtol):
    n = 0
    for f, lo, hi in _cases():
        if not (f(lo) < 0) ^ (f(hi) < 0) or f(lo) == 0 or f(hi) == 0:
            continue
        want = scipy_brentq(f, lo, hi, xtol=xtol, rtol=rtol, maxiter=200)
        got = brentq(f, lo, hi, xtol=xtol, rtol=rtol, maxiter=200)
        assert got == want or (math.isnan(got) and math.isnan(want)), (lo, hi, got, want)
        assert math.copysign(1, got) == math.copysign(1, want)
        n += 1
    assert n > 1000


def test_errors_like_scipy():
    with pytest.raises(ValueError, match="different signs"):
        brentq(lambda x: x * x + 1, -1.0, 1.0)
    with pytest.raises(ValueError, match="NaN"):
        brentq(lambda x: math.nan if x > 0 else -1.0, -1.0, 1.0)
    with pytest.raises(ValueError, match="rtol too small"):
        brentq(lambda x: x, -1.0, 1.0, rtol=1e-17)
    with pytest.raises(ValueError, match="xtol too small"):
        brentq(lambda x: x, -1.0, 1.0, xtol=0.0)
    with pytest.raises(RuntimeError, match="converge"):
        brentq(lambda x: math.atan(x - 0.3), -1e6, 1e6, xtol=1e-300, maxiter=3)
    assert brentq(lambda x: x - 1.0, 1.0, 2.0) == 1.0        # a root at an end is returned as is
