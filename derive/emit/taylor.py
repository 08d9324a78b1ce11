"""Taylor's method for a lowered right-hand side: the Taylor coefficients of the solution in C.

For dx/dt = f(x), the coefficients x^[j] of x(t0 + h) = sum_j x^[j] h^j follow from x^[0] = x(t0)
and x^[n+1] = f(x)^[n] / (n + 1), where f(x)^[n] is the n-th coefficient of f along the
solution. That needs f as a tape of elementary operations, each with its recurrence over the
coefficients of its operands (automatic differentiation in Taylor mode; Jorba & Zou, Experiment.
Math. 14, 2005, section 2.2; the method heyoka compiles, runtime/bench/heyoka.py):

    lin   u = c + sum k_i a_i          u^[n] = sum k_i a_i^[n]                      (n >= 1)
    mul   u = a b                      u^[n] = sum_{j=0..n} a^[j] b^[n-j]
    inv   u = 1 / a                    u^[n] = -u^[0] sum_{j=1..n} a^[j] u^[n-j]
    sqrt  u = a^(1/2)                  u^[n] = (a^[n] - sum_{j=1..n-1} u^[j] u^[n-j]) / (2 u^[0])
    pow   u = a^e (e a constant)       u^[n] = sum_{j=0..n-1} (e (n-j) - j) a^[n-j] u^[j] / (n a^[0])
    exp   u = e^a                      u^[n] = sum_{j=1..n} j a^[j] u^[n-j] / n
    log   u = log a                    u^[n] = (a^[n] - sum_{j=1..n-1} j u^[j] a^[n-j] / n) / a^[0]
    sin, cos  s = sin a, c = cos a     s^[n] = sum j a^[j] c^[n-j] / n, c^[n] = -sum j a^[j] s^[n-j] / n

(each from differentiating the definition: a u' = e a' u for pow, u' = a' u for exp, ...);
tan is sin / cos, sinh, cosh and tanh are written with exp. The constants of f (what depends on
the parameters only) are computed once, as scalars; only what depends on the state becomes a
series. Degree 0 of every node is the node's plain value, so
x^[1] is f(x) as the rhs computes it, to its rounding (tests/derive/test_taylor.py).

The generated C (derive/emit/c/templates/model.c.j2):

    int <part>_taylor(const double *in, const double *p, int order, double *out)

writes x_k^[j] to out[k (order + 1) + j], j = 0 .. order, and returns 0, or -1 for an order
outside 1 .. TAYLOR_MAX_ORDER (nothing written). runtime/csrc/integrators.c's LEV_TAYLOR steps with it.

Emitted for the reduced model (thesis eq. 3.2.12): four states and a short tape, where the method
takes a few long steps and its cost, about nodes x order^2 / 2 multiply-adds a step, is small. A
right-hand side with a function outside the table above gets no Taylor function (``taylor_tape``
raises Unsupported, derive records none, and the runtime names the integrators to use instead).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .lower import Lowered

# out's and the nodes' capacity; runtime/csrc/integrators.h's LEV_TAYLOR_MAX_ORDER caps the order at
# the same number (tests/derive/test_taylor.py): ceil(-ln tol / 2 + 1) <= 32 down to tol 1e-26 (TOL_MIN 1e-15: 19)
TAYLOR_MAX_ORDER = 32
PARTS = ("reduced",)       # the parts that get a Taylor function


class Unsupported(ValueError):
    """The right-hand side has an operation without a Taylor recurrence here."""


@dataclass
class Tape:
    name: str
    n: int                                  # states
    inputs: list                            # [(index, symbol)] of the states the rhs reads
    params: list                            # [(index, symbol)]
    consts: list = field(default_factory=list)     # [(symbol, expr)]: scalars, in order
    nodes: list = field(default_factory=list)      # [(name, op, args)]: series, in order
    outputs: list = field(default_factory=list)    # per state: ("c", expr) | ("s", coef, name)

    @property
    def mults_per_degree(self) -> int:
        """Nonlinear nodes (each costs about n multiply-adds at degree n)."""
        return sum(1 for _, op, _ in self.nodes if op != "lin")


class _Builder:
    def __init__(self, low: Lowered, n_states: int):
        self.tape = Tape(low.name.rsplit("_", 1)[0] + "_taylor", n_states, low.inputs, low.params)
        self.series: dict = {sym: f"x{i}" for i, sym in low.inputs}   # symbol -> series name
        self.ref: dict = {}          # series-valued body symbol -> its Ref
        self.const_of: dict = {}     # constant expr -> its symbol
        self.memo: dict = {}         # (op, args) -> node name
        self.k = 0

    # constants
    def const(self, expr) -> sp.Expr:
        """A scalar: a number as it is, anything else as a named constant computed once."""
        expr = sp.sympify(expr)
        if expr.is_Number or expr.is_Symbol:
            return expr
        sym = self.const_of.get(expr)
        if sym is None:
            sym = self.const_of[expr] = sp.Symbol(f"k{len(self.const_of)}", real=True)
            self.tape.consts.append((sym, expr))
        return sym

    def is_series(self, expr) -> bool:
        return any(s in self.series or s in self.ref for s in sp.sympify(expr).free_symbols)

    # nodes
    def node(self, op: str, *args) -> str:
        key = (op, args)
        name = self.memo.get(key)
        if name is None:
            name = self.memo[key] = f"u{self.k}"
            self.k += 1
            self.tape.nodes.append((name, op, args))
        return name

    def plain(self, ref) -> str:
        """The series of a Ref without its coefficient (a lin node when it has one)."""
        coef, name = ref
        return name if coef is None else self.node("lin", ((coef, name),), sp.Integer(0))

    # expressions -> Ref = (coefficient expr or None, series name)
    def expr(self, e):
        e = sp.sympify(e)
        if e in self.series:
            return (None, self.series[e])
        if e in self.ref:
            return self.ref[e]
        if e.is_Add:
            return self.add(e.args)
        if e.is_Mul:
            return self.mul(e.args)
        if e.is_Pow:
            return self.pow(*e.args)
        if isinstance(e, (sp.exp, sp.log)) and len(e.args) == 1:
            return (None, self.node(type(e).__name__, self.plain(self.expr(e.args[0]))))
        if isinstance(e, (sp.sin, sp.cos)):
            a = self.plain(self.expr(e.args[0]))
            s, c = self.node("sin", a), self.node("cos", a)
            return (None, s if isinstance(e, sp.sin) else c)
        if isinstance(e, sp.tan):
            return self.expr(sp.sin(e.args[0]) / sp.cos(e.args[0]))
        if isinstance(e, (sp.sinh, sp.cosh, sp.tanh)):
            return self.expr(e.rewrite(sp.exp))
        raise Unsupported(f"{type(e).__name__}(...) has no Taylor recurrence in derive/emit/taylor.py")

    def add(self, args):
        c, terms = [], []
        for a in args:
            if not self.is_series(a):
                c.append(a)
                continue
            coef, name = self.expr(a)
            terms.append((coef, name))
        c0 = self.const(sp.Add(*c)) if c else sp.Integer(0)
        if len(terms) == 1 and c0 == 0:
            return terms[0]
        return (None, self.node("lin", tuple(terms), c0))

    def mul(self, args):
        k, refs = [], []
        for a in args:
            if self.is_series(a):
                refs.append(self.expr(a))
            else:
                k.append(a)
        coefs = [c for c, _ in refs if c is not None] + k
        name = refs[0][1]
        for _, other in refs[1:]:
            name = self.node("mul", *sorted((name, other)))
        coef = self.const(sp.Mul(*coefs)) if coefs else None
        return (None if coef == 1 else coef, name)

    def pow(self, b, e):
        if not self.is_series(b):
            return self.expr(sp.exp(e * sp.log(b)))       # c^(series)
        if self.is_series(e):
            return self.expr(sp.exp(e * sp.log(b)))
        if e.is_Integer and int(e) >= 1:
            a = self.plain(self.expr(b))
            return (None, self._ipow(a, int(e)))
        a = self.plain(self.expr(b))
        if e == -1:
            return (None, self.node("inv", a))
        if e == sp.Rational(1, 2):
            return (None, self.node("sqrt", a))
        return (None, self.node("pow", a, self.const(e)))

    def _ipow(self, a: str, k: int) -> str:
        if k == 1:
            return a
        half = self._ipow(a, k // 2)
        sq = self.node("mul", half, half)
        return sq if k % 2 == 0 else self.node("mul", *sorted((sq, a)))


def taylor_tape(low: Lowered) -> Tape:
    """The tape of a lowered `<part>_rhs` (module docstring); Unsupported if an operation has no
    recurrence here."""
    b = _Builder(low, low.n_out)
    for s, fn, a in low.trig:                       # s_q, c_q of an angle among the states
        b.ref[s] = b.expr((sp.sin if fn == "sin" else sp.cos)(a))
    for sym, e in low.body:
        if b.is_series(e):
            b.ref[sym] = b.expr(e)
        else:
            b.tape.consts.append((sym, e))
    for e in low.outputs:
        e = sp.sympify(e)
        if b.is_series(e):
            coef, name = b.expr(e)
            b.tape.outputs.append(("s", coef, name))
        else:
            b.tape.outputs.append(("c", e))
    return b.tape


def c_lines(tape: Tape, printer) -> list[str]:
    """The body of `<part>_taylor` (module docstring): constants, degree 0, the loop over degrees."""
    P = printer.doprint
    L = ["int n;", "if (order < 1 || order > LEV_TAYLOR_MAX_ORDER) return -1;"]
    for i in range(tape.n):
        L.append(f"double *x{i} = out + {i} * (order + 1);")
    if tape.nodes:
        L.append("double " + ", ".join(f"{name}[LEV_TAYLOR_MAX_ORDER + 1]" for name, _, _ in tape.nodes) + ";")
    L += [f"const double {s} = {P(e)};" for s, e in tape.consts]
    for i in range(tape.n):
        L.append(f"x{i}[0] = in[{i}];")
    L.append("/* degree 0: the values */")
    for name, op, args in tape.nodes:
        L.append(f"{name}[0] = {_degree0(op, args, P)};")
    L += _reciprocals(tape)
    outs = []
    for i, o in enumerate(tape.outputs):
        if o[0] == "c":
            L.append(f"x{i}[1] = {P(o[1])};")
            L.append(f"for (n = 2; n <= order; n++) x{i}[n] = 0.0;")
        else:
            outs.append((i, o))
            L.append(f"x{i}[1] = {_scaled(o[1], o[2] + '[0]', P)};")
    L.append("for (n = 1; n < order; n++) {")
    body = []
    if any(op in ("pow", "exp", "log", "sin", "cos") for _, op, _ in tape.nodes):
        body.append("const double r = 1.0 / n;")
    if outs:
        body.append("const double r1 = 1.0 / (n + 1);")
    by_key = {(op, args): name for name, op, args in tape.nodes}
    body += [f"{name}[n] = {_degree_n(name, op, args, P, by_key)};" for name, op, args in tape.nodes]
    body += [f"x{i}[n + 1] = {_scaled(o[1], o[2] + '[n]', P)} * r1;" for i, o in outs]
    L += ["    " + line for line in body]
    L += ["}", "return 0;"]
    return L


def _reciprocals(tape: Tape) -> list[str]:
    """The reciprocals of degree-0 values the recurrences multiply by (lev_tay_sqrt's 1 / (2 u[0]),
    lev_tay_pow's and lev_tay_log's 1 / a[0]), once per expansion."""
    lines = []
    for name, op, args in tape.nodes:
        if op == "sqrt":
            lines.append(f"const double h_{name} = 0.5 / {name}[0];")
        elif op in ("pow", "log"):
            lines.append(f"const double ia_{name} = 1.0 / {args[0]}[0];")
    return lines


def _scaled(coef, term: str, P) -> str:
    return term if coef is None else f"{P(coef)} * {term}"


def _degree0(op: str, args, P) -> str:
    if op == "lin":
        terms, c0 = args
        s = " + ".join(_scaled(k, f"{a}[0]", P) for k, a in terms)
        return s if c0 == 0 else f"{P(c0)} + {s}"
    a = args[0]
    return {"mul": lambda: f"{args[0]}[0] * {args[1]}[0]", "inv": lambda: f"1.0 / {a}[0]",
            "sqrt": lambda: f"sqrt({a}[0])", "pow": lambda: f"pow({a}[0], {P(args[1])})",
            "exp": lambda: f"exp({a}[0])", "log": lambda: f"log({a}[0])",
            "sin": lambda: f"sin({a}[0])", "cos": lambda: f"cos({a}[0])"}[op]()


def _degree_n(name: str, op: str, args, P, by_key: dict) -> str:
    """Degree n >= 1 of a node: its recurrence (the lev_tay_* helpers of model.c.j2)."""
    if op == "lin":
        return " + ".join(_scaled(k, f"{a}[n]", P) for k, a in args[0])
    a = args[0]
    if op == "mul":
        if args[0] == args[1]:
            return f"lev_tay_sqr({a}, n)"
        return f"lev_tay_mul({args[0]}, {args[1]}, n)"
    if op == "inv":
        return f"lev_tay_inv({a}, {name}, n)"
    if op == "sqrt":
        return f"lev_tay_sqrt({a}, {name}, h_{name}, n)"
    if op == "pow":
        return f"lev_tay_pow({a}, {name}, {P(args[1])}, ia_{name}, r, n)"
    if op == "log":
        return f"lev_tay_log({a}, {name}, ia_{name}, r, n)"
    if op in ("sin", "cos"):
        partner = by_key[("cos" if op == "sin" else "sin", args)]
        return f"lev_tay_{op}({a}, {partner}, r, n)"
    return f"lev_tay_{op}({a}, {name}, r, n)"
