"""Every number of the generated C is the double it means.

gcc reads a whole-number literal of 2^63 or more as an integer and reduces it modulo 2^64, so an
expression plate `phi0 = "b*1e20*z/sqrt(z**2 + c**2)"` computed B_z = -1.46e7 in C where the
formula and CasADi give -1.886e8, and `b*2**64*...` gave 0. The printer now writes every Integer,
Rational and Float as the repr of its correctly rounded double (derive/doubles.py), which C reads
back exactly; a constant no double holds is a one-line SceneError naming the formula.
"""
from __future__ import annotations

import math

import pytest
import sympy as sp

from levitron.derive.build import render
from levitron.derive.doubles import DoubleRangeError, as_double
from levitron.derive.emit.c.printer import LevitronCPrinter
from levitron.scene.load import SceneError, validate

x = sp.Symbol("x", real=True)


@pytest.mark.parametrize("number", [sp.Integer(2) ** 63, sp.Integer(2) ** 64, sp.Integer(10) ** 20,
                                    -sp.Integer(3) * 10 ** 30, sp.Rational(10 ** 40, 3),
                                    sp.Integer(7), sp.Rational(1, 3), sp.Integer(10) ** 308])
def test_printer_writes_a_number_as_its_double(number):
    """The literal the printer writes for `number * x` is a C double literal equal to the number's
    correctly rounded double (never a C integer literal, whatever its size)."""
    text = LevitronCPrinter().doprint(number * x)
    literal = text.replace("*x", "").replace("x*", "").strip("()")
    assert "." in literal or "e" in literal, f"{text!r} holds an integer literal"
    assert float(literal) == int(number.p) / int(number.q), text


def test_an_overflowing_constant_has_no_double():
    with pytest.raises(DoubleRangeError, match="beyond the range of a double"):
        LevitronCPrinter().doprint(sp.Integer(10) ** 309 * x)
    for bad in (sp.nan, sp.oo, sp.zoo, sp.I):
        with pytest.raises(DoubleRangeError):
            as_double(bad)
    assert as_double(sp.Integer(2) ** 64) == 2.0 ** 64
    assert as_double(sp.Rational(-1, 3)) == -1 / 3 and math.isfinite(as_double(sp.pi))


def _expression_data(formula: str, **params) -> dict:
    return {"name": "expr", "top": {"mass": 0.02, "A": 2.2e-6, "C": 1.32e-6, "moment": -1.0},
            "plate": {"kind": "expression", "phi0": formula, "params": params or {"b": 1.0}},
            "field": {"order": 2}, "model": {"needs": ["reduced"]}}


@pytest.mark.parametrize("formula", ["1e308*10*z", "b*1e200*1e200*z", "b*(1e160*z)**2",
                                     "b*z*(10**100)**4", "b*1e306*z**90", "b*exp(800)*z"])
def test_an_overflowing_constant_is_a_one_line_scene_error(formula):
    """Before: derive wrote an integer literal gcc made 0 (or inf). `b*1e306*z**90` passes the
    parser (every constant of the formula has a double) but Phi_4 has 90*89*88*87e306: the
    lowering's constants are checked too."""
    scene = validate(_expression_data(formula))
    with pytest.raises(SceneError) as err:
        render(scene)
    msg = str(err.value)
    assert "\n" not in msg and "plate.phi0" in msg and "double" in msg, msg


def test_constants_are_doubles_not_math_h_macros():
    """Found by tests/battery/test_properties.py: E and pi/2 were printed M_E and M_PI_2, which math.h does
    not declare under -std=c99 (phi0 = "E*z" did not compile)."""
    p = LevitronCPrinter()
    for expr, value in ((sp.E * x, math.e), (sp.pi / 2 * x, math.pi / 2), (sp.pi * x, math.pi),
                        (x / sp.pi, 1 / math.pi)):
        text = p.doprint(expr)
        assert "M_" not in text, text
        factors = text.replace("*x", "").replace("x*", "").replace("x/", "1.0/").split("*")
        got = 1.0
        for f in factors:                       # "(0.5)*3.141592653589793" or "1.0/3.14..."
            num, _, den = f.strip("()").partition("/")
            got *= float(num) / (float(den) if den else 1.0)
        assert got == value, text
