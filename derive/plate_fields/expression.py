"""A plate given by a formula for its on-axis potential `phi0` or field `bz` (docs/scenes.md).

The formula is parsed safely (derive/expr_parse.py: never evaluated as Python, size and nesting
checked before sympy sees it). The sympy work on it is bounded: every Phi_k may have at most
MAX_DERIVATIVE_OPS operations, and the plate's whole symbolic work (parsing, the antiderivative of
bz, every derivative) at most TIME_BUDGET_S seconds of wall time (derive/plate_fields/budget.py).
"""
from __future__ import annotations

import time

import sympy as sp

from levitron.scene.checks import SceneError

from ..expr_parse import FUNCTIONS, NOT_SMOOTH, ExpressionError, parse_expression
from ..symbols import Z
from .budget import time_budget
from .plate import Plate, plate_symbol

MAX_DERIVATIVE_OPS = 10_000   # operations of one Phi_k (sympy count_ops)
TIME_BUDGET_S = 60.0          # seconds of symbolic work on one expression plate


class _Derivatives:
    """k -> Phi_k = d^k Phi0/dz^k (Phi_1 = -bz when bz is given), memoised, within the budgets."""

    def __init__(self, first: list[sp.Expr], where: str, left: float):
        self.cache = list(first)
        self.where = where
        self.left = left

    def __call__(self, k: int) -> sp.Expr:
        while len(self.cache) <= k:
            k_next = len(self.cache)
            t0 = time.monotonic()
            with time_budget(self.left, f"{self.where}: the formula's derivative Phi_{k_next}"):
                nxt = sp.diff(self.cache[-1], Z)
                ops = sp.count_ops(nxt)
            self.left -= time.monotonic() - t0
            if ops > MAX_DERIVATIVE_OPS:
                raise SceneError(f"{self.where}: the formula's derivative Phi_{k_next} has {ops} "
                                 f"operations (limit {MAX_DERIVATIVE_OPS}): simplify the formula "
                                 "or lower field.order")
            self.cache.append(nxt)
        return self.cache[k]


def _check_functions(expr: sp.Expr, where: str) -> None:
    """The antiderivative sympy found uses only functions the C printer and CasADi have (those a
    formula may name): exp(z**2) integrates to erfi, which neither has."""
    allowed = {func for func, _ in FUNCTIONS.values()} | {sp.atan2}
    other = sorted({str(f.func) for f in expr.atoms(sp.Function) if f.func not in allowed})
    if other or expr.has(*NOT_SMOOTH):
        name = ", ".join(other) or "a non-smooth function"
        raise SceneError(f"{where}: its antiderivative needs {name}, which the generated code "
                         "cannot compute: give the on-axis potential as `phi0` instead")


def build(table: dict, prefix: str = "") -> Plate:
    """Phi0 from `phi0`, or from `bz` by Phi_1 = -bz (B = -grad phi) and Phi0 = -int bz dz, which
    must have a closed form; the parameters are the names of [plate.params]."""
    params = table.get("params", {}) or {}
    names = {"z": Z, **{key: plate_symbol(prefix + key) for key in sorted(params)}}
    symbols = tuple(names[k] for k in sorted(params))
    where = f"plate.parts[{prefix[1:-1]}]" if prefix else "plate"   # prefix "p<i>_": part i
    key = "phi0" if "phi0" in table else "bz"
    t0 = time.monotonic()
    with time_budget(TIME_BUDGET_S, f"{where}.{key}"):
        try:
            expr = parse_expression(table[key], names)
        except ExpressionError as exc:
            raise SceneError(f"{where}.{key}: {exc}; fix the formula") from None
        if key == "phi0":
            first = [expr]
        else:
            phi0 = -sp.integrate(expr, Z)
            if phi0.has(sp.Integral):
                raise SceneError(f"{where}.bz = {table['bz']!r} has no closed-form antiderivative "
                                 "in z that sympy finds: give the on-axis potential as `phi0` "
                                 "instead")
            first = [phi0, -expr]
            _check_functions(phi0, f"{where}.bz = {table['bz']!r}")
    derivs = _Derivatives(first, where, TIME_BUDGET_S - (time.monotonic() - t0))
    return Plate("expression", first[0], symbols, derivs)
