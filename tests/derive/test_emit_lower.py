"""The lowering (derive/emit/lower.py): powers of a common base share one chain, one sqrt and one
division per base, no pow(); the lowered code computes the same numbers as the expressions."""
from __future__ import annotations

import math
import re
from types import SimpleNamespace

import sympy as sp

from levitron.derive.emit.c.emitter import body_lines
from levitron.derive.emit.c.printer import LevitronCPrinter
from levitron.derive.emit.lower import lower
from levitron.derive.spec import Function

z, x, a = sp.symbols("z x a", real=True)


def _lowered():
    u = a ** 2 + z ** 2
    outs = (u ** sp.Rational(-5, 2) + x * u ** sp.Rational(-3, 2) + sp.sqrt(u),
            x ** -3 + x ** 2 * u ** -4 - u ** sp.Rational(-9, 2) / x,
            sp.sin(x) * u ** -1)
    fn = Function("f", (z, x), outs, (3,), "test")
    spec = SimpleNamespace(params=(a,), plate=None, field3d=None)
    return outs, lower(fn, spec)


def _evaluate(low, values):
    env = dict(values)
    for s, fn, arg in low.trig:
        env[s] = getattr(math, fn)(env[arg])
    for s, e in low.body:
        env[s] = float(e.xreplace(env))
    return [float(sp.sympify(e).xreplace(env)) for e in low.outputs]


def test_powers_of_a_base_share_one_sqrt_and_one_division():
    _, low = _lowered()
    sqrts = [s for s, e in low.body if e.is_Pow and e.args[1] == sp.Rational(1, 2)]
    divs = [s for s, e in low.body if e.is_Pow and e.args[1] == -1]
    assert len(sqrts) == 1                      # a^2 + z^2 only
    assert len(divs) == 2                       # 1/(a^2 + z^2) and 1/x
    lines = body_lines(low, LevitronCPrinter())
    text = "\n".join(lines)
    assert "pow(" not in text
    assert text.count("sqrt(") == 1 and text.count("/") == 2, text
    # every other link of a chain is one product of two symbols
    links = [s for s, _ in low.body if re.search(r"_[mp]\d+h?$", str(s))]
    assert len(links) >= 8                      # the chains are there to check
    for s, e in low.body:
        if s not in sqrts and s not in divs and re.search(r"_[mp]\d+h?$", str(s)):
            assert e.is_Mul and len(e.args) == 2 and all(t.is_Symbol for t in e.args), (s, e)


def test_lowered_code_computes_the_expressions():
    outs, low = _lowered()
    for vals in ({z: 0.3, x: 1.7, a: 0.05}, {z: -2.0, x: -0.4, a: 1.3}):
        want = [float(e.xreplace(vals)) for e in outs]
        got = _evaluate(low, vals)
        assert all(math.isclose(g, w, rel_tol=1e-13) for g, w in zip(got, want)), (got, want)
