"""Fast, deterministic simplification of expressions polynomial in sines and cosines.

sympy's trigsimp is slow and picks shapes (tan, double angles) that cost operations in generated
code. Here sin(q) and cos(q) become independent symbols S, C; numerator and denominator are
reduced modulo S^2 + C^2 - 1 and the fraction is cancelled. The result is exact.
"""
from __future__ import annotations

import sympy as sp


def trig_reduce(expr: sp.Expr, angles, keep: str = "cos") -> sp.Expr:
    """Simplify `expr` using sin(a)^2 + cos(a)^2 = 1 for each angle a (exact, no heuristics).

    keep="cos" writes even powers of sin through cos, keep="sin" the other way round: choose the
    one that stays well conditioned where the model is used (1 - cos^2 loses digits near 0).
    """
    angles = list(angles)
    S = [sp.Dummy(f"s_{a}") for a in angles]
    Cs = [sp.Dummy(f"c_{a}") for a in angles]
    fwd = {}
    for a, s, c in zip(angles, S, Cs):
        fwd[sp.sin(a)] = s
        fwd[sp.cos(a)] = c
        fwd[sp.tan(a)] = s / c
    e = sp.cancel(sp.sympify(expr).xreplace(fwd))
    gens = S + Cs if keep == "cos" else Cs + S
    basis = [s**2 + c**2 - 1 for s, c in zip(S, Cs)]
    num, den = sp.fraction(e)

    def reduce(poly):
        poly = sp.expand(poly)
        if not poly.free_symbols & set(gens):
            return poly
        return sp.reduced(poly, basis, *gens, order="lex")[1]

    out = sp.factor(sp.cancel(reduce(num) / reduce(den)))
    back = {s: sp.sin(a) for a, s in zip(angles, S)}
    back.update({c: sp.cos(a) for a, c in zip(angles, Cs)})
    return out.xreplace(back)
