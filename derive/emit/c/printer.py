"""The C99 printer: sympy's C99CodePrinter with integer and half-integer powers written out.

Every number is written as the double it means (derive/doubles.py): 3 -> 3.0, 1/3 ->
0.3333333333333333, 2**64 -> 1.8446744073709552e+19, never a C integer literal (which gcc reduces
modulo 2^64 from 2^63 on), pi and E too (never M_E or M_PI_2, which -std=c99's math.h does not
declare); a number no double holds raises DoubleRangeError.

x**3 -> x*x*x, x**-2 -> 1.0/(x*x), x**(1/2) -> sqrt(x), x**(-3/2) -> 1.0/(x*sqrt(x)):
no pow() call for the small powers that the field expansion is full of.

Every product that is a term of a sum is fused into it explicitly: a*b*c + d - e*f is printed
LEV_FMA(-e, f, LEV_FMA(a*b, c, d)), the terms that are not products first, in sympy's order, then
the products one by one. LEV_FMA (FMA_PRELUDE, at the top of model.c) is C99's fma() where the
target has the instruction (FP_FAST_FMA) and a*b + c otherwise, and the model is compiled with
contraction off (runtime/model/cbuild.py, the pragmas of model.c.j2), so the compiler fuses nothing
else: the scalar function and its lane variant (the same statements in a loop the compiler
vectorises) round alike by construction, where the compiler's own contraction fused them
differently.
"""
from __future__ import annotations

from sympy.printing.c import C99CodePrinter
from sympy.printing.precedence import PRECEDENCE, precedence

from ...doubles import DoubleRangeError, c_literal

MAX_INLINE_POWER = 8
FMA = "LEV_FMA"
# what every C file of printed expressions needs first (model.c.j2 and tests/c/test_c_vs_casadi.py):
# contraction off, math.h and LEV_FMA
FMA_PRELUDE = """#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif
#include <math.h>
#ifdef FP_FAST_FMA
#define LEV_FMA(a, b, c) fma(a, b, c)       /* one instruction: a * b + c rounded once */
#else
#define LEV_FMA(a, b, c) ((a) * (b) + (c))  /* no fma instruction: libm's would be slow */
#endif"""


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

    def _factor(self, f) -> str:
        return self._print(f) if f.is_Number else self.parenthesize(f, PRECEDENCE["Mul"])

    def _fma_operands(self, term) -> tuple[str, str] | None:
        """(a, b) with term = a * b as printed: a the product of all but the last factor (negated
        where the coefficient is negative, which is exact), b the last factor; x**n (n <= 8) as
        x*...*x times x. None when the term is no product of two or more factors or has a divisor
        (then its last operation is a division)."""
        if term.is_Pow and term.exp.is_Integer and 2 <= int(term.exp) <= MAX_INLINE_POWER:
            base = self._factor(term.base)
            return "*".join([base] * (int(term.exp) - 1)), base
        if not term.is_Mul:
            return None
        coeff, rest = term.as_coeff_Mul()
        factors = list(rest.as_ordered_factors()) if rest.is_Mul else [rest]
        if any(f.is_Pow and f.exp.is_number and f.exp < 0 for f in factors):
            return None
        ops = ([abs(coeff)] if abs(coeff) != 1 else []) + factors
        if len(ops) < 2:
            return None
        if len(ops) == 2 and coeff > 0:
            head = self._print(ops[0])
        else:
            head = "*".join(self._factor(f) for f in ops[:-1])
        return ("-" + head if coeff < 0 else head), self._print(ops[-1])

    def _print_Add(self, expr, order=None):
        """The terms that are no products first (sympy's order, as sympy prints them), then each
        product fused in: LEV_FMA(a, b, the sum so far)."""
        terms = self._as_ordered_terms(expr, order=order)
        operands = [self._fma_operands(t) for t in terms]
        plain = [t for t, ab in zip(terms, operands) if ab is None]
        products = [ab for ab in operands if ab is not None]
        if not plain:                    # all products: the first one starts the sum unfused
            plain, products = terms[:1], products[1:]
        acc = ""
        for term in plain:
            t = self._print(term)
            if precedence(term) < PRECEDENCE["Add"]:
                t = f"({t})"
            if not acc:
                acc = t
            elif t.startswith("-"):
                acc = f"{acc} - {t[1:]}"
            else:
                acc = f"{acc} + {t}"
        for a, b in products:
            acc = f"{FMA}({a}, {b}, {acc})"
        return acc
