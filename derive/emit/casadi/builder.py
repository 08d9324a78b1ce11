"""sympy -> CasADi SX, by walking the expression tree (no lambdify, no exec), and Function.save.

The builder consumes the same lowered blocks as the C emitter (derive/emit/lower.py), so the two
backends compute the same expression graph.
"""
from __future__ import annotations

from pathlib import Path

import casadi as ca
import sympy as sp

from ...doubles import as_double
from ..lower import Lowered

_UNARY = {
    sp.sin: ca.sin, sp.cos: ca.cos, sp.tan: ca.tan, sp.exp: ca.exp, sp.log: ca.log,
    sp.asin: ca.asin, sp.acos: ca.acos, sp.atan: ca.atan, sp.sinh: ca.sinh, sp.cosh: ca.cosh,
    sp.tanh: ca.tanh, sp.asinh: ca.asinh, sp.acosh: ca.acosh, sp.atanh: ca.atanh,
    sp.Abs: ca.fabs, sp.sign: ca.sign,
}


class SXBuilder:
    """Translate sympy expressions to SX given a symbol -> SX environment."""

    def __init__(self, env: dict):
        self.env = dict(env)

    def __call__(self, e: sp.Basic):
        if e.is_Symbol:
            try:
                return self.env[e]
            except KeyError:
                raise KeyError(f"no CasADi value for symbol {e}") from None
        if e.is_Rational or e.is_Float or e is sp.pi or e is sp.E:
            return ca.SX(as_double(e))       # the printer's double (derive/doubles.py)
        if e.is_Add:
            args = [self(a) for a in e.args]
            out = args[0]
            for a in args[1:]:
                out = out + a
            return out
        if e.is_Mul:
            args = [self(a) for a in e.args]
            out = args[0]
            for a in args[1:]:
                out = out * a
            return out
        if e.is_Pow:
            b, x = e.args
            base = self(b)
            if x.is_Integer:
                n = int(x)
                if n == -1:
                    return 1 / base
                return ca.constpow(base, n)
            if x == sp.Rational(1, 2):
                return ca.sqrt(base)
            if x == -sp.Rational(1, 2):
                return 1 / ca.sqrt(base)
            return ca.power(base, self(x))
        if e.func in _UNARY:
            return _UNARY[e.func](self(e.args[0]))
        if e.func == sp.atan2:
            return ca.atan2(self(e.args[0]), self(e.args[1]))
        raise NotImplementedError(f"no CasADi translation for {e.func} in {e}")

    def assign(self, sym, expr):
        self.env[sym] = self(expr)


def build_function(f: Lowered, n_params: int) -> ca.Function:
    """The casadi.Function (in, p) -> out for a lowered function."""
    x = ca.SX.sym("in", f.n_in)
    p = ca.SX.sym("p", n_params)
    env = {v: x[i] for i, v in f.inputs}
    env.update({v: p[i] for i, v in f.params})
    b = SXBuilder(env)
    for s, fn, a in f.trig:
        b.env[s] = (ca.sin if fn == "sin" else ca.cos)(b.env[a])
    for s, e in f.body:
        b.assign(s, e)
    out = ca.vertcat(*[b(e) for e in f.outputs]) if f.outputs else ca.SX(0, 1)
    return ca.Function(f.name, [x, p], [out], ["in", "p"], ["out"])


def save(fn: ca.Function, path: Path) -> None:
    fn.save(str(path))
