"""The size of the terms of a CasADi function at many points: the yardstick of "relative 1e-12".

docs/contract.md: relative errors near a zero of a quantity are taken against the size of its terms.
`values_and_sizes(fn, X, P)` walks the SX function's instructions (the same graph derive printed as
C) over the columns of X and P at once and returns, beside each output's value v, its term size

    S(node) = |v| + sum_i |d node / d arg_i| * S(arg_i),      S(input) = |input|, S(const) = |c|,

the first-order bound of how far rounding in any operation can move the output, divided by the
unit roundoff (Wilkinson's running error analysis). For a sum it is the sum of the sizes of the
summands; for a product, the product of sizes; near a pole of 1/b it grows like S(b)/b^2. So two
backends that compute the same graph with different roundings (fused multiply-adds, x/3 against
x*(1/3)) differ by a small multiple of 1e-16 S, and a wrong constant (an integer literal that gcc
wrapped) by about |v|.
"""
from __future__ import annotations

import casadi as ca
import numpy as np


def _unary(op: int, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(value, |derivative|) of a unary operation."""
    with np.errstate(all="ignore"):
        table = {
            ca.OP_NEG: lambda: (-a, np.ones_like(a)),
            ca.OP_SQ: lambda: (a * a, 2 * np.abs(a)),
            ca.OP_TWICE: lambda: (2 * a, 2 * np.ones_like(a)),
            ca.OP_INV: lambda: (1 / a, 1 / (a * a)),
            ca.OP_SQRT: lambda: (np.sqrt(a), 0.5 / np.sqrt(np.abs(a))),
            ca.OP_SIN: lambda: (np.sin(a), np.abs(np.cos(a))),
            ca.OP_COS: lambda: (np.cos(a), np.abs(np.sin(a))),
            ca.OP_TAN: lambda: (np.tan(a), 1 + np.tan(a) ** 2),
            ca.OP_EXP: lambda: (np.exp(a), np.exp(a)),
            ca.OP_LOG: lambda: (np.log(a), 1 / np.abs(a)),
            ca.OP_ASIN: lambda: (np.arcsin(a), 1 / np.sqrt(np.abs(1 - a * a))),
            ca.OP_ACOS: lambda: (np.arccos(a), 1 / np.sqrt(np.abs(1 - a * a))),
            ca.OP_ATAN: lambda: (np.arctan(a), 1 / (1 + a * a)),
            ca.OP_SINH: lambda: (np.sinh(a), np.cosh(a)),
            ca.OP_COSH: lambda: (np.cosh(a), np.abs(np.sinh(a))),
            ca.OP_TANH: lambda: (np.tanh(a), 1 - np.tanh(a) ** 2),
            ca.OP_ASINH: lambda: (np.arcsinh(a), 1 / np.sqrt(a * a + 1)),
            ca.OP_ACOSH: lambda: (np.arccosh(a), 1 / np.sqrt(np.abs(a * a - 1))),
            ca.OP_ATANH: lambda: (np.arctanh(a), 1 / np.abs(1 - a * a)),
            ca.OP_FABS: lambda: (np.abs(a), np.ones_like(a)),
            ca.OP_SIGN: lambda: (np.sign(a), np.zeros_like(a)),
        }
        return table[op]()


def _binary(op: int, a: np.ndarray, b: np.ndarray):
    """(value, |d/da|, |d/db|) of a binary operation."""
    with np.errstate(all="ignore"):
        if op == ca.OP_ADD:
            return a + b, 1.0, 1.0
        if op == ca.OP_SUB:
            return a - b, 1.0, 1.0
        if op == ca.OP_MUL:
            return a * b, np.abs(b), np.abs(a)
        if op == ca.OP_DIV:
            return a / b, 1 / np.abs(b), np.abs(a) / (b * b)
        if op == ca.OP_CONSTPOW:
            return a ** b, np.abs(b * a ** (b - 1)), 0.0
        if op == ca.OP_POW:
            v = a ** b
            return v, np.abs(b * a ** (b - 1)), np.abs(v * np.log(np.abs(a)))
        if op == ca.OP_ATAN2:
            r2 = a * a + b * b
            return np.arctan2(a, b), np.abs(b) / r2, np.abs(a) / r2
    raise NotImplementedError(f"casadi operation {op} has no term-size rule")


def values_and_sizes(fn: ca.Function, X: np.ndarray, P: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """fn(in, p) -> out over the columns of X (n_in, N) and P (n_p, N): (values, sizes), both
    (n_out, N)."""
    sx = fn if fn.is_a("SXFunction") else fn.expand()
    n = X.shape[1]
    inputs = (np.asarray(X, dtype=float), np.asarray(P, dtype=float))
    work: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    out_v = np.zeros((sx.nnz_out(0), n))
    out_s = np.zeros((sx.nnz_out(0), n))
    for k in range(sx.n_instructions()):
        op, ins, outs = sx.instruction_id(k), sx.instruction_input(k), sx.instruction_output(k)
        if op == ca.OP_INPUT:
            v = inputs[ins[0]][ins[1]]
            work[outs[0]] = (v, np.abs(v))
        elif op == ca.OP_CONST:
            c = np.full(n, sx.instruction_constant(k))
            work[outs[0]] = (c, np.abs(c))
        elif op == ca.OP_OUTPUT:
            out_v[outs[1]], out_s[outs[1]] = work[ins[0]]
        elif op == ca.OP_ASSIGN:
            work[outs[0]] = work[ins[0]]
        elif len(ins) == 1 or op in (ca.OP_NEG, ca.OP_SQ, ca.OP_TWICE, ca.OP_INV, ca.OP_SQRT):
            (a, sa) = work[ins[0]]
            v, d = _unary(op, a)
            with np.errstate(all="ignore"):
                work[outs[0]] = (v, np.abs(v) + d * sa)
        else:
            (a, sa), (b, sb) = work[ins[0]], work[ins[1]]
            v, da, db = _binary(op, a, b)
            with np.errstate(all="ignore"):
                work[outs[0]] = (v, np.abs(v) + da * sa + db * sb)
    return out_v, out_s


def assert_agree(name: str, got: np.ndarray, want: np.ndarray, size: np.ndarray, rel: float = 1e-12):
    """got and want agree to `rel` of the size of the terms wherever both are finite, and are
    non-finite at the same points."""
    fin_g, fin_w = np.isfinite(got), np.isfinite(want)
    where = np.argwhere(fin_g != fin_w)[:5].tolist()
    assert np.array_equal(fin_g, fin_w), f"{name}: finite in one backend only at {where}"
    ok = fin_g & np.isfinite(size)
    with np.errstate(all="ignore"):
        dev = np.where(ok, np.abs(got - want) / np.where(size > 0, size, 1.0), 0.0)
    worst = np.unravel_index(np.argmax(dev), dev.shape)
    assert dev[worst] <= rel, (f"{name}: output {worst[0]} at point {worst[1]}: {got[worst]!r} against "
                               f"{want[worst]!r}, {dev[worst]:.2e} of the term size {size[worst]:.3e}")
