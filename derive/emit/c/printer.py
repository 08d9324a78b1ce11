"""The C99 printer: sympy's C99CodePrinter with integer and half-integer powers written out.

x**3 -> x*x*x, x**-2 -> 1.0/(x*x), x**(1/2) -> sqrt(x), x**(-3/2) -> 1.0/(x*sqrt(x)):
no pow() call for the small powers that the field expansion is full of.
"""
from __future__ import annotations

from sympy.printing.c import C99CodePrinter

MAX_INLINE_POWER = 8


class LevitronCPrinter(C99CodePrinter):
    """C99 printer used for every generated model (see derive/emit/c/emitter.py)."""

    def __init__(self, settings=None):
        super().__init__({"full_prec": True, **(settings or {})})

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Rational(self, expr):
        return f"{float(expr.p)!r}/{float(expr.q)!r}"

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
