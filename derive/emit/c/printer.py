"""The C99 printer: sympy's C99CodePrinter with integer and half-integer powers written out.

Every number is written as the double it means (derive/doubles.py): 3 -> 3.0, 1/3 ->
0.3333333333333333, 2**64 -> 1.8446744073709552e+19, never a C integer literal (which gcc reduces
modulo 2^64 from 2^63 on), pi and E too (never M_E or M_PI_2, which -std=c99's math.h does not
declare); a number no double holds raises DoubleRangeError.

x**3 -> x*x*x, x**-2 -> 1.0/(x*x), x**(1/2) -> sqrt(x), x**(-3/2) -> 1.0/(x*sqrt(x)):
no pow() call for the small powers that the field expansion is full of.
"""
from __future__ import annotations

from sympy.printing.c import C99CodePrinter

from ...doubles import DoubleRangeError, c_literal

MAX_INLINE_POWER = 8


class LevitronCPrinter(C99CodePrinter):
    """C99 printer used for every generated model (see derive/emit/c/emitter.py)."""

    def __init__(self, settings=None):
        # no math.h macros (M_E, M_PI_2, M_SQRT2, ...): -std=c99 does not declare them
        super().__init__({"full_prec": True, "math_macros": {}, **(settings or {})})

    def _print_NumberSymbol(self, expr):
        return c_literal(expr)

    _print_Pi = _print_Exp1 = _print_NumberSymbol

    def _print_Float(self, expr):
        return c_literal(expr)

    def _print_Rational(self, expr):
        return c_literal(expr)

    def _print_Integer(self, expr):
        return c_literal(expr)

    def _no_double(self, expr):
        raise DoubleRangeError(f"the constant {expr} is not a real number (NaN, an infinity or complex)")

    _print_NaN = _print_Infinity = _print_NegativeInfinity = _print_ComplexInfinity = _no_double
    _print_ImaginaryUnit = _no_double

    def _product(self, base: str, n: int) -> str:
        return "*".join([base] * n)

    def _print_Pow(self, expr):
        b, e = expr.base, expr.exp
        if b.is_Symbol or (b.is_Number and b >= 0):
            base = self._print(b)
        else:
            base = f"({self._print(b)})"
        if e.is_Integer and 1 <= abs(int(e)) <= MAX_INLINE_POWER:
            n = int(e)
            prod = self._product(base, abs(n))
            if n > 0:
                return prod if n == 1 else f"({prod})"
            return f"(1.0/({prod}))"
        if e.is_Rational and e.q == 2 and abs(e.p) <= 2 * MAX_INLINE_POWER + 1:
            n = abs(int(e.p))
            k = n // 2
            root = f"sqrt({self._print(b)})"
            prod = "*".join([base] * k + [root])
            if e.p > 0:
                return prod if k == 0 else f"({prod})"
            return f"(1.0/({prod}))"
        return super()._print_Pow(expr)
