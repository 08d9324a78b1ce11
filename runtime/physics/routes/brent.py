"""Brent's root finder on a bracket, the same arithmetic as scipy.optimize.brentq.

Why not scipy's: importing scipy.optimize costs about half a second (it loads linprog, scipy.fft,
scipy.special ...), ten times the rest of `levitron stability`, for one scalar root on a bracket.
This is a line-by-line transcription of scipy's C routine (scipy/optimize/Zeros/brentq.c, Charles
Harris; Brent 1973, ch. 4) in Python floats, which are the same IEEE doubles with the same
operations in the same order, so it returns the same double as scipy.optimize.brentq
(tests/runtime/physics/routes/test_brent.py compares the two bit for bit on thousands of brackets).
"""
from __future__ import annotations

import math
from collections.abc import Callable

EPS = 2.220446049250313e-16
RTOL_MIN = 4 * EPS          # scipy's smallest rtol


def brentq(f: Callable[[float], float], a: float, b: float, xtol: float = 2e-12,
           rtol: float = RTOL_MIN, maxiter: int = 100) -> float:
    """A root of f in [a, b] (f(a) and f(b) of opposite signs), to |x - x0| <= xtol + rtol |x0|.

    Raises ValueError as scipy does: bad tolerances, f(a) and f(b) of the same sign, f NaN; and
    RuntimeError when maxiter iterations did not converge.
    """
    if xtol <= 0:
        raise ValueError(f"xtol too small ({xtol:g} <= 0)")
    if rtol < RTOL_MIN:
        raise ValueError(f"rtol too small ({rtol:g} < {RTOL_MIN:g})")

    def call(x: float) -> float:
        fx = float(f(x))
        if math.isnan(fx):
            raise ValueError(f"The function value at x={x} is NaN; solver cannot continue.")
        return fx

    xpre, xcur = float(a), float(b)
    xblk = fblk = spre = scur = 0.0
    fpre, fcur = call(xpre), call(xcur)
    if fpre == 0:
        return xpre
    if fcur == 0:
        return xcur
    if math.copysign(1.0, fpre) == math.copysign(1.0, fcur):
        raise ValueError("f(a) and f(b) must have different signs")
    for _ in range(maxiter):
        if fpre != 0 and fcur != 0 and math.copysign(1.0, fpre) != math.copysign(1.0, fcur):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:            # interpolate
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:                       # extrapolate (inverse quadratic)
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre, scur = scur, stry     # a good short step
            else:
                spre = scur = sbis          # bisect
        else:
            spre = scur = sbis              # bisect
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        fcur = call(xcur)
    raise RuntimeError(f"brentq: failed to converge after {maxiter} iterations, value is {xcur}")
