"""The double a number of a formula or of the lowered graph means: one rule for every backend.

The C printer (derive/emit/c/printer.py) and the CasADi builder (derive/emit/casadi/builder.py)
both turn every number through `as_double`, so the two compute with the same constants: an exact
integer or rational becomes its correctly rounded double (Python's int / int), never a C integer
literal (gcc reduces one of 2^63 or more modulo 2^64). A number no double holds (beyond
+-1.8e308, NaN, an infinity, a complex number) raises `DoubleRangeError`, which derive reports as
one line naming the formula (derive/build.py).
"""
from __future__ import annotations

import math

import sympy as sp

DOUBLE_MAX = 1.7976931348623157e308
DOUBLE_TINY = 2.2250738585072014e-308   # the smallest normal double


class DoubleRangeError(ValueError):
    """A number of the model has no double: the message says which and why (one line)."""


def shown(value: sp.Basic) -> str:
    """A short form of a (possibly huge) exact number for a message."""
    text = str(value)
    if len(text) <= 24:
        return text
    if isinstance(value, sp.Integer):
        digits = len(str(abs(int(value)))) - 1
        return f"{'-' if value < 0 else ''}{str(abs(int(value)))[0]}...e{digits} (a {digits + 1}-digit integer)"
    return text[:21] + "..."


def as_double(value: sp.Basic) -> float:
    """The correctly rounded double of a sympy number (Integer, Rational, Float, pi, E), or
    DoubleRangeError when there is none."""
    if isinstance(value, sp.Rational):            # Integer is a Rational
        try:
            out = int(value.p) / int(value.q)      # correctly rounded, raises OverflowError
        except OverflowError:
            raise DoubleRangeError(f"the constant {shown(value)} is beyond the range of a double "
                                   f"(|x| <= {DOUBLE_MAX:.4g})") from None
    elif isinstance(value, (sp.Float, sp.NumberSymbol)):
        out = float(value)
    else:
        raise DoubleRangeError(f"the constant {shown(value)} is not a real number "
                               "(NaN, an infinity or complex)")
    if not math.isfinite(out):
        raise DoubleRangeError(f"the constant {shown(value)} is beyond the range of a double "
                               f"(|x| <= {DOUBLE_MAX:.4g})")
    if out == 0 and value != 0:
        raise DoubleRangeError(f"the constant {shown(value)} is below the range of a double "
                               "(it would be 0)")
    return out


def c_literal(value: sp.Basic) -> str:
    """The C double literal of a sympy number: repr of its double, which C reads back exactly
    (always with a '.' or an exponent, so never an integer literal)."""
    text = repr(as_double(value))
    return text if any(ch in text for ch in ".e") else text + ".0"
