"""A safe parser for the formulas of `plate.kind = "expression"` scenes (docs/scenes.md).

A scene may give its base plate's on-axis potential `phi0 = "..."` (Phi0(z), thesis eq. 2.2.6 at
r = 0) or on-axis field `bz = "..."` as a formula in `z` and the names declared in [plate.params].
Scene text is never evaluated as Python and never handed to `sympy.sympify`/`parse_expr` (both call
`eval`). Instead the text is parsed by `ast.parse(mode="eval")` -- which only builds a syntax tree --
and a strict whitelist walk builds the sympy expression node by node:

- numbers (int and float literals such as 2, 0.5, 1e-3), converted exactly to sympy Rationals;
- the operators + - * / ** and unary + -, parentheses;
- the declared names (z and the parameters) and the constants `pi` and `E`;
- calls of the functions in `FUNCTIONS`, positional arguments only, with their exact arity
  (the names are those of scene/plates/expression.py, the scene side of the registry). `abs` is
  refused with its reason: the model differentiates the formula, and |x|'s derivatives (sign(x),
  a Dirac delta) have no code; the same holds where sympy turns sqrt(x**2) into |x|.

Everything else -- attribute access, subscripts, other calls, keyword arguments, strings, lambda,
comprehensions, comparisons, conditionals, walrus, names starting with "_", unknown names -- is
refused with an `ExpressionError` quoting the offending part. Resource limits keep hostile input
cheap, checked on the syntax tree before sympy sees any of it: the text length (`MAX_LENGTH`), the
number of tree nodes (`MAX_NODES`), the nesting depth (`MAX_DEPTH`) and the nesting of function
calls (`MAX_CALL_DEPTH`: the k-th derivative of f(g(h(...))) grows like depth^k terms, so
sin(sin(...(z))) 15 deep would keep derive busy for minutes); then, while building, the length of a
number literal (`MAX_LITERAL`), the size of a constant exponent (`MAX_EXPONENT`) and of exact
powers. Every message is one line saying what is wrong and how to fix it.
"""
from __future__ import annotations

import ast
import math
import re
from collections.abc import Iterable, Mapping

import sympy as sp

from levitron.scene.plates import expression as scene_side

from .doubles import DOUBLE_MAX, DOUBLE_TINY, DoubleRangeError, as_double

MAX_LENGTH = scene_side.MAX_FORMULA   # characters of formula text
MAX_NODES = 1000       # nodes of the syntax tree
MAX_DEPTH = 60         # nesting depth of the expression tree (chains of + - * / do not count)
MAX_CALL_DEPTH = scene_side.MAX_CALL_DEPTH   # function calls nested in function calls
MAX_LITERAL = 40       # characters of one number literal
MAX_EXPONENT = 100     # |constant exponent|
MAX_POWER_BITS = 4096  # bits of an exact rational power computed at parse time

_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


class ExpressionError(ValueError):
    """A formula was refused; the message quotes the offending part and says what is allowed."""


def _atan2(y, x):
    return sp.atan2(y, x)


# name -> (sympy constructor, number of positional arguments), for the names of the scene side
FUNCTIONS: dict[str, tuple[object, int]] = {
    name: (_atan2 if name == "atan2" else getattr(sp, name), arity)
    for name, arity in scene_side.FUNCTIONS.items()}

CONSTANTS: dict[str, sp.Expr] = {"pi": sp.pi, "E": sp.E}
assert tuple(CONSTANTS) == scene_side.CONSTANTS

NOT_SMOOTH = (sp.Abs, sp.sign, sp.Heaviside, sp.DiracDelta, sp.Piecewise, sp.floor, sp.ceiling)
_ABS_HINT = ("abs() is not supported: the model differentiates the formula and |x|'s derivatives "
             "(sign, a Dirac delta) cannot be generated; write it for the side where x > 0 (the top "
             "hovers at z > 0: z instead of abs(z), sqrt(z**2 + c**2) stays as it is)")

RESERVED = frozenset(FUNCTIONS) | frozenset(CONSTANTS) | {"abs", "Abs"}


def check_name(name: str) -> None:
    """Refuse a parameter name that could not be used in a formula (or would shadow a built-in)."""
    if not isinstance(name, str) or not _IDENT.match(name):
        raise ExpressionError(f"parameter name {name!r} is not allowed: use letters, digits and '_', "
                              "starting with a letter")
    if name in RESERVED:
        raise ExpressionError(f"parameter name {name!r} is the name of a built-in function or "
                              "constant: rename it")


def _quote(text: str, node: ast.AST | None) -> str:
    seg = ast.get_source_segment(text, node) if node is not None else None
    if seg is None:
        seg = text
    if len(seg) > 80:
        seg = seg[:77] + "..."
    return repr(seg)


class _Builder:
    def __init__(self, text: str, names: Mapping[str, sp.Symbol]):
        self.text = text
        self.names = names

    def fail(self, node: ast.AST | None, why: str) -> ExpressionError:
        return ExpressionError(f"{_quote(self.text, node)}: {why}")

    # ---- leaves
    def number(self, node: ast.Constant) -> sp.Expr:
        value = node.value
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            kind = type(value).__name__
            raise self.fail(node, f"a {kind} constant is not allowed; only real numbers are")
        seg = ast.get_source_segment(self.text, node) or repr(value)
        if len(seg) > MAX_LITERAL:
            raise self.fail(node, f"number literal longer than {MAX_LITERAL} characters")
        if isinstance(value, float) and not math.isfinite(value):
            raise self.fail(node, "number is not finite in double precision")
        if isinstance(value, int):
            return sp.Integer(value)
        # Exact decimal value of the literal as written (e.g. 0.1 -> 1/10), not of its double.
        cleaned = seg.replace("_", "")
        try:
            return sp.Rational(cleaned)
        except (TypeError, ValueError):
            return sp.Rational(repr(value))

    def name(self, node: ast.Name) -> sp.Expr:
        ident = node.id
        if ident.startswith("_"):
            raise self.fail(node, "names starting with '_' (dunder names) are not allowed")
        if ident in self.names:
            return self.names[ident]
        if ident in CONSTANTS:
            return CONSTANTS[ident]
        if ident in FUNCTIONS:
            raise self.fail(node, f"{ident} is a function: call it, e.g. {ident}(z)")
        declared = ", ".join(sorted(self.names)) or "(none)"
        raise self.fail(node, f"unknown name {ident!r}: declare it in [plate.params] "
                              f"(declared: {declared}; constants: pi, E)")

    # ---- the walk
    def build(self, node: ast.AST, depth: int) -> sp.Expr:
        if depth > MAX_DEPTH:
            raise self.fail(node, f"nested deeper than {MAX_DEPTH} levels")
        if isinstance(node, ast.Constant):
            return self.number(node)
        if isinstance(node, ast.Name):
            return self.name(node)
        if isinstance(node, ast.UnaryOp):
            if isinstance(node.op, ast.USub):
                return -self.build(node.operand, depth + 1)
            if isinstance(node.op, ast.UAdd):
                return self.build(node.operand, depth + 1)
            raise self.fail(node, f"operator {type(node.op).__name__} is not allowed "
                                  "(only + - * / ** and unary -)")
        if isinstance(node, ast.BinOp):
            return self.binop(node, depth)
        if isinstance(node, ast.Call):
            return self.call(node, depth)
        what = {
            ast.Attribute: "attribute access", ast.Subscript: "subscripts", ast.Lambda: "lambda",
            ast.ListComp: "comprehensions", ast.SetComp: "comprehensions",
            ast.DictComp: "comprehensions", ast.GeneratorExp: "comprehensions",
            ast.Compare: "comparisons", ast.BoolOp: "and/or", ast.IfExp: "conditionals",
            ast.NamedExpr: "assignment (:=)", ast.JoinedStr: "strings", ast.Starred: "unpacking (*)",
            ast.Tuple: "tuples", ast.List: "lists", ast.Dict: "dicts", ast.Set: "sets",
            ast.Await: "await", ast.Yield: "yield", ast.YieldFrom: "yield",
        }.get(type(node), type(node).__name__)
        raise self.fail(node, f"{what} not allowed in a formula (only numbers, names, + - * / **, "
                              "and the functions " + ", ".join(sorted(FUNCTIONS)) + ")")

    def binop(self, node: ast.BinOp, depth: int) -> sp.Expr:
        ops = {ast.Add: "+", ast.Sub: "-", ast.Mult: "*", ast.Div: "/", ast.Pow: "**"}
        kind = type(node.op)
        if kind not in ops:
            hint = " (use ** for powers)" if kind is ast.BitXor else ""
            raise self.fail(node, f"operator {type(node.op).__name__} is not allowed{hint}; "
                                  "only + - * / ** are")
        if kind is ast.Pow:
            base = self.build(node.left, depth + 1)
            expo = self.build(node.right, depth + 1)
            return self.power(node, base, expo)
        # Flatten a left-leaning chain of the same precedence class iteratively, so that a long
        # sum a + b + c + ... neither counts as deep nesting nor recurses once per term.
        group = (ast.Add, ast.Sub) if kind in (ast.Add, ast.Sub) else (ast.Mult, ast.Div)
        chain = []
        left = node
        while isinstance(left, ast.BinOp) and isinstance(left.op, group):
            chain.append((type(left.op), left.right))
            left = left.left
        acc = self.build(left, depth + 1)
        for op, right in reversed(chain):
            rhs = self.build(right, depth + 1)
            if op is ast.Add:
                acc = acc + rhs
            elif op is ast.Sub:
                acc = acc - rhs
            elif op is ast.Mult:
                acc = acc * rhs
            else:
                if rhs == 0:
                    raise self.fail(right, "division by zero")
                acc = acc / rhs
        return acc

    def power(self, node: ast.BinOp, base: sp.Expr, expo: sp.Expr) -> sp.Expr:
        if expo.is_number:
            if not expo.is_Rational:
                # Evaluating an arbitrary constant (exp(exp(...))) could be costly: refuse it.
                raise self.fail(node.right, "a constant exponent must be a rational number "
                                            "such as 2, -3/2 or 0.5")
            if abs(expo) > MAX_EXPONENT:
                raise self.fail(node.right, f"constant exponent larger than {MAX_EXPONENT} in "
                                            "magnitude")
            if base.is_Rational and expo.is_Rational:
                bits = max(abs(base.p), abs(base.q)).bit_length()
                if bits * abs(float(expo)) > MAX_POWER_BITS:
                    raise self.fail(node, "exact power too large to compute")
        if base == 0 and expo.is_number and expo.is_negative:
            raise self.fail(node, "division by zero")
        return sp.Pow(base, expo)

    def call(self, node: ast.Call, depth: int) -> sp.Expr:
        if not isinstance(node.func, ast.Name):
            raise self.fail(node.func, "only direct calls of the allowed functions are allowed "
                                       "(no attribute access or computed callee)")
        fname = node.func.id
        if fname in ("abs", "Abs"):
            raise self.fail(node, _ABS_HINT)
        if fname.startswith("_"):
            raise self.fail(node.func, "names starting with '_' (dunder names) are not allowed")
        if fname not in FUNCTIONS:
            raise self.fail(node.func, f"unknown function {fname!r}: allowed are "
                                       + ", ".join(sorted(FUNCTIONS)))
        if node.keywords:
            raise self.fail(node, "keyword arguments are not allowed")
        if any(isinstance(a, ast.Starred) for a in node.args):
            raise self.fail(node, "argument unpacking (*) is not allowed")
        func, arity = FUNCTIONS[fname]
        if len(node.args) != arity:
            raise self.fail(node, f"{fname} takes {arity} argument{'s' if arity > 1 else ''}, "
                                  f"got {len(node.args)}")
        args = [self.build(a, depth + 1) for a in node.args]
        return func(*args)


def _group(node: ast.AST):
    """The precedence group of a + - or * / operation (chains of one group do not nest), or None."""
    if isinstance(node, ast.BinOp):
        if isinstance(node.op, (ast.Add, ast.Sub)):
            return "add"
        if isinstance(node.op, (ast.Mult, ast.Div)):
            return "mul"
    return None


def _check_size(tree: ast.AST) -> None:
    """Refuse a tree nested deeper than MAX_DEPTH, with calls nested deeper than MAX_CALL_DEPTH or
    with more than MAX_NODES nodes (module docstring), before anything is built: one iterative
    pass over the expression nodes, no recursion."""
    count = 0
    stack = [(tree, 0, 0, None)]
    while stack:
        node, depth, calls, parent_group = stack.pop()
        group = _group(node)
        if group is None or group != parent_group:
            depth += 1
        if depth > MAX_DEPTH:
            raise ExpressionError(f"formula nested deeper than {MAX_DEPTH} levels: simplify it")
        if isinstance(node, ast.Call):
            calls += 1
            if calls > MAX_CALL_DEPTH:
                raise ExpressionError(f"formula nests function calls {calls} deep (limit "
                                      f"{MAX_CALL_DEPTH}): its derivatives would grow like "
                                      f"{calls}^k terms; simplify it")
        count += 1
        if count > MAX_NODES:
            raise ExpressionError(f"formula has more than {MAX_NODES} terms and operators: "
                                  "simplify it")
        stack.extend((child, depth, calls, group) for child in ast.iter_child_nodes(node)
                     if isinstance(child, ast.expr))


def _as_symbols(names: Mapping[str, sp.Symbol] | Iterable[str]) -> dict[str, sp.Symbol]:
    if isinstance(names, Mapping):
        table = dict(names)
    else:
        table = {n: sp.Symbol(n, real=True) for n in names}
    for key, sym in table.items():
        check_name(key)
        if not isinstance(sym, sp.Symbol):
            raise ExpressionError(f"name {key!r} must map to a sympy Symbol")
    return table


def parse_expression(text: str, names: Mapping[str, sp.Symbol] | Iterable[str]) -> sp.Expr:
    """Parse `text` into a sympy expression in the given names (a mapping name -> Symbol, or names).

    Raises ExpressionError (a ValueError) quoting the offending part of the text. The result is
    checked to be real-valued as written (no I, no zoo/nan/oo).
    """
    if not isinstance(text, str):
        raise ExpressionError(f"formula must be a string, got {type(text).__name__}")
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"formula is {len(text)} characters long: the limit is {MAX_LENGTH}")
    if not text.strip():
        raise ExpressionError("formula is empty: write e.g. \"z/sqrt(z**2 + a**2)\"")
    if "\x00" in text:
        raise ExpressionError("formula contains a NUL character")
    table = _as_symbols(names)
    # A cheap pre-check of bracket nesting, before the parser sees the text.
    depth = deepest = 0
    for ch in text:
        if ch in "([{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in ")]}":
            depth -= 1
    if deepest > MAX_DEPTH:
        raise ExpressionError(f"formula nests brackets {deepest} deep: the limit is {MAX_DEPTH}")
    try:
        tree = ast.parse(text.strip(), mode="eval")
    except SyntaxError as exc:
        col = (exc.offset or 1) - 1
        near = text.strip()[max(col - 10, 0):col + 10]
        raise ExpressionError(f"not a formula: {exc.msg} near {near!r}") from None
    except (MemoryError, RecursionError):
        raise ExpressionError("formula too complex to parse") from None
    _check_size(tree)
    builder = _Builder(text.strip(), table)
    try:
        expr = builder.build(tree.body, 0)
    except RecursionError:
        raise ExpressionError(f"formula nested too deeply (limit {MAX_DEPTH})") from None
    except ExpressionError:
        raise
    except (ValueError, TypeError, ArithmeticError) as exc:   # sympy on atan(log(0)), say
        why = (str(exc).strip().splitlines() or [type(exc).__name__])[0][:80]
        raise ExpressionError(f"{_quote(text, None)}: not a real, finite formula ({why}): fix "
                              "it") from None
    if expr.has(*NOT_SMOOTH):
        raise ExpressionError(f"{_quote(text, None)} becomes {expr} (sqrt(x**2) is |x| for real x): "
                              + _ABS_HINT.split(": ", 1)[1])
    if expr.has(sp.I, sp.zoo, sp.nan, sp.oo, -sp.oo, sp.AccumBounds):   # atan(log(0)) is a range
        raise ExpressionError(f"{_quote(text, None)}: the formula is not real and finite as "
                              f"written (it simplifies to {expr})")
    _check_constants(text, expr)
    return expr


def _check_constants(text: str, expr: sp.Expr) -> None:
    """Every number of the formula has a double, and every constant term (asin(2), exp(1000),
    (-8)**(1/3)) is real and within double range: C and CasADi would compute NaN or inf from it.
    Inner terms first, so exp(exp(exp(9))) stops at exp(exp(9)) before a huge evaluation."""
    for node in sp.postorder_traversal(expr):
        if isinstance(node, sp.Number):
            try:
                as_double(node)
            except DoubleRangeError as exc:
                raise ExpressionError(f"{_quote(text, None)}: {exc}; scale the formula (give the "
                                      "factor as a parameter in [plate.params])") from None
        elif node.is_number and not isinstance(node, sp.NumberSymbol) and node.args:
            try:
                value = sp.N(node, 30)
            except (OverflowError, ValueError, ArithmeticError):
                raise ExpressionError(f"{_quote(text, None)}: the constant {node} cannot be "
                                      "evaluated in double range: scale the formula") from None
            re_part, im_part = value.as_real_imag()
            if im_part != 0 or not re_part.is_finite:
                raise ExpressionError(f"{_quote(text, None)}: the constant {node} is not a real "
                                      f"number ({value}): fix the formula")
            if abs(re_part) > DOUBLE_MAX:
                raise ExpressionError(f"{_quote(text, None)}: the constant {node} = {str(sp.N(node, 4))} "
                                      "is beyond the range of a double: scale the formula")
            if 0 < abs(re_part) < DOUBLE_TINY:
                raise ExpressionError(f"{_quote(text, None)}: the constant {node} = {str(sp.N(node, 4))} "
                                      "is below the range of a double (it would be 0): scale the formula")
