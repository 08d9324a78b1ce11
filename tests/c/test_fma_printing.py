"""Fused multiply-adds in the generated C are printed, never left to the compiler
(derive/emit/c/printer.py, FMA_PRELUDE): every product that is a term of a sum is one LEV_FMA, and
the model is compiled with contraction off, so a function and its lane variant (the same
statements in a vectorised loop) round alike by construction (tests/c/test_lanes.py checks that on
every scene)."""
from __future__ import annotations

import ctypes

import pytest
import sympy as sp

from levitron.derive.emit.c.printer import FMA_PRELUDE, LevitronCPrinter

x, y, z, w = sp.symbols("x y z w", real=True)


@pytest.mark.parametrize("expr, text", [
    (x * y + z, "LEV_FMA(x, y, z)"),
    (x * y - 3 * z + 1, "LEV_FMA(-3.0, z, LEV_FMA(x, y, 1.0))"),
    (-x * y - z * w, "LEV_FMA(-x, y, -w*z)"),
    (x / y + z * w, "LEV_FMA(w, z, x/y)"),             # a quotient is not fused: its last op divides
    (x ** 2 + y, "LEV_FMA(x, x, y)"),
    (x - y, "x - y"),
    (x * (y + z), "x*(y + z)"),                        # no sum around the product: nothing to fuse
    ((x + y) * (z + w * x) + 1, "LEV_FMA(x + y, LEV_FMA(w, x, z), 1.0)"),
])
def test_a_product_in_a_sum_is_printed_as_one_fma(expr, text):
    assert LevitronCPrinter().doprint(expr) == text


def _library(tmp_path):
    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compile_shared
    src = tmp_path / "fma.c"
    src.write_text(FMA_PRELUDE + """
double plain(double a, double b, double c) { return a * b + c; }
double fused(double a, double b, double c) { return LEV_FMA(a, b, c); }
int fast_fma(void)
{
#ifdef FP_FAST_FMA
    return 1;
#else
    return 0;
#endif
}
""")
    lib = ctypes.CDLL(str(compile_shared([src], DEFAULT_FLAGS)))
    for name in ("plain", "fused"):
        getattr(lib, name).argtypes = [ctypes.c_double] * 3
        getattr(lib, name).restype = ctypes.c_double
    return lib


def test_the_compiler_fuses_only_what_is_printed(tmp_path):
    """a = 1 + 2^-30, b = 1 - 2^-30, c = -1: a b = 1 - 2^-60 rounds to 1, so a b + c is 0 when
    rounded twice and -2^-60 when fused. With the model's flags and prelude `a * b + c` is rounded
    twice (no contraction: gcc -O3 -march=native would fuse it otherwise), and LEV_FMA is fused
    where the target has the instruction (FP_FAST_FMA), else it is the same two roundings."""
    lib = _library(tmp_path)
    a, b, c = 1 + 2.0 ** -30, 1 - 2.0 ** -30, -1.0
    assert lib.plain(a, b, c) == 0.0
    assert lib.fused(a, b, c) == (-(2.0 ** -60) if lib.fast_fma() else 0.0)
