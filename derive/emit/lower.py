"""Lower a symbolic Function to straight-line code that every backend prints the same way.

Two blocks, in order:
1. trig:  s_q = sin(q), c_q = cos(q) for every angle q the function uses (each computed once);
2. body:  P_k = Phi_k(z) of the plate for the orders k the function needs (the plate's own,
          possibly cancellation-free, forms: Plate.phi_derivs) and the outputs in terms of the
          inputs, parameters, s_q, c_q and P_k, with one pass of common subexpressions over the
          whole function, then every integer or half-integer power of a common base folded into
          one chain of multiplications (one sqrt and one division per base, no pow()).
Only what an output needs is kept, so generated C has no unused variables.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..spec import Function, ModelSpec
from ..symbols import B_FUNCS, Phi, Z, phi_orders


@dataclass
class Lowered:
    name: str
    doc: str
    n_in: int
    n_out: int
    shape: tuple
    inputs: list            # [(index, symbol)] of the inputs used
    params: list            # [(index, symbol)] of the parameters used
    trig: list              # [(symbol, "sin" | "cos", argument symbol)]
    body: list              # [(symbol, expr)] temporaries, P_k and powers, in dependency order
    outputs: list           # expressions, flattened row-major
    ops: int                # operation count (sympy count_ops over both blocks; sin/cos count 1)


def _used(assigns, outputs) -> set:
    """Free symbols of the outputs, followed back through the assignments."""
    need = set().union(*[sp.sympify(e).free_symbols for e in outputs]) if outputs else set()
    for sym, expr in reversed(assigns):
        if sym in need:
            need |= expr.free_symbols
    return need


def _prune(assigns, outputs):
    need = _used(assigns, outputs)
    kept = []
    for sym, expr in reversed(assigns):
        if sym in need:
            kept.append((sym, expr))
    return list(reversed(kept))


def _field_atoms(expr) -> set:
    """B_i(x, y, z) and its derivatives in expr (largest first: derivatives contain the function)."""
    found = {d for d in expr.atoms(sp.Derivative) if d.expr.func in B_FUNCS}
    found |= {f for f in expr.atoms(sp.Function) if f.func in B_FUNCS}
    return found


def _field_name(atom) -> str:
    if isinstance(atom, sp.Derivative):
        comp = str(atom.expr.func)
        return comp + "_d" + "".join(str(v) * int(n) for v, n in atom.variable_count)
    return str(atom.func)


_DERIV_CACHE: dict = {}


def _field_value(atom, B: sp.Matrix) -> sp.Expr:
    """The closed form of B_i or of one of its derivatives; derivatives are built one variable at a
    time and cached, so d^2 B_i/dx dy reuses dB_i/dx."""
    if B is None:
        raise ValueError(f"{atom} needs the plate's 3-D field, which this plate does not give")
    if not isinstance(atom, sp.Derivative):
        return B[B_FUNCS.index(atom.func)]
    i = B_FUNCS.index(atom.expr.func)
    variables = tuple(v for v, n in atom.variable_count for _ in range(int(n)))
    key = (sp.srepr(B[i]), variables)
    if key not in _DERIV_CACHE:
        parent = B[i] if len(variables) == 1 else _field_value(
            sp.Derivative(atom.expr, *variables[:-1]), B)
        _DERIV_CACHE[key] = sp.diff(parent, variables[-1])
    return _DERIV_CACHE[key]


def _toposort(assigns: list) -> list:
    """The assignments in an order where each follows everything it uses (stable: an assignment
    moves only as far as it must)."""
    defined = {s for s, _ in assigns}
    done, out, todo = set(), [], list(assigns)
    while todo:
        rest = []
        for sym, expr in todo:
            if (expr.free_symbols & defined) <= done:
                out.append((sym, expr))
                done.add(sym)
            else:
                rest.append((sym, expr))
        if len(rest) == len(todo):
            raise ValueError(f"cyclic assignments: {[s for s, _ in rest]}")
        todo = rest
    return out


def _power_name(base: sp.Symbol, e: sp.Rational) -> str:
    sign = "m" if e < 0 else "p"
    return f"{base}_{sign}{abs(e.p)}" + ("h" if e.q == 2 else "")


def _power(bs: sp.Symbol, k: sp.Rational, chain: dict, defs: list) -> sp.Symbol:
    """The symbol of bs**k, defined (appended to defs) from smaller links of bs's chain."""
    if k == 1:
        return bs
    if k in chain:
        return chain[k]
    sym = sp.Symbol(_power_name(bs, k), real=True)
    half = sp.Rational(1, 2)
    if k == half:
        expr = sp.sqrt(bs)
    elif k == -1:
        expr = 1 / bs
    elif k == -half:
        expr = sp.Mul(_power(bs, sp.Integer(-1), chain, defs), _power(bs, half, chain, defs),
                      evaluate=False)
    elif k.q == 2:
        h = half if k > 0 else -half
        expr = sp.Mul(_power(bs, k - h, chain, defs), _power(bs, h, chain, defs), evaluate=False)
    else:
        a = (abs(k) + 1) // 2 * (1 if k > 0 else -1)
        expr = sp.Mul(_power(bs, sp.Integer(a), chain, defs), _power(bs, k - a, chain, defs),
                      evaluate=False)
    chain[k] = sym
    defs.append((sym, expr))
    return sym


def _fold_powers(assigns: list, outputs: list) -> tuple[list, list]:
    """Every power b**e with e an integer or a half-integer becomes one multiplication of a chain
    shared by all powers of the same base b: s = sqrt(b) and r = 1/b (independent, so they overlap),
    t = b^(-1/2) = r*s, r^k = r^ceil(k/2) * r^floor(k/2) (a tree: depth log k), b^k likewise,
    b^(k+1/2) = b^k*s, b^-(k+1/2) = r^k*t. So each base costs at most one square root and one
    division however many powers of it the function uses, and no pow() call remains on the hot
    path (the other exponents, if any, are left to the printer)."""
    exprs = [e for _, e in assigns] + list(outputs)
    by_base: dict = {}
    for e in exprs:
        for pw in e.atoms(sp.Pow):
            b, x = pw.args
            if b.is_Number or not x.is_Rational or x.q not in (1, 2) or x == 1:
                continue
            by_base.setdefault(b, set()).add(x)
    if not by_base:
        return assigns, outputs
    named = {}                       # non-symbol base -> its own symbol
    new_defs = []                    # [(sym, expr)], placed by the topological sort
    repl, bases = {}, []
    for n, b in enumerate(sorted(by_base, key=sp.default_sort_key)):
        xs = sorted(by_base[b])
        if b.is_Symbol:
            bs = b
        else:
            bs = named[b] = sp.Symbol(f"b{n}", real=True)
            bases.append(bs)
        chain: dict = {}             # exponent (Rational) -> symbol
        for x in xs:
            repl[sp.Pow(bs, x)] = _power(bs, x, chain, new_defs)
    # chain expressions are built with evaluate=False so that b*b stays a product of two symbols
    def sub(e):
        return e.xreplace(named).xreplace(repl)
    base_of = {bs: b for b, bs in named.items()}
    new_defs += [(bs, base_of[bs].func(*[sub(a) for a in base_of[bs].args])) for bs in bases]
    assigns = [(s, sub(e)) for s, e in assigns]
    outputs = [sub(e) for e in outputs]
    return _toposort(assigns + new_defs), outputs


def _inline_aliases(assigns: list, outputs: list) -> tuple[list, list]:
    """Drop every assignment `a = b` of one symbol to another, writing b wherever a was."""
    alias, kept = {}, []
    for sym, expr in assigns:
        expr = expr.xreplace(alias) if alias else expr
        if expr.is_Symbol:
            alias[sym] = expr
        else:
            kept.append((sym, expr))
    return kept, [e.xreplace(alias) for e in outputs] if alias else list(outputs)


def _flatten_powers(assigns: list, outputs: list) -> tuple[list, list]:
    """(b**a)**x -> b**(a x) where a temporary is a power of a base (b**a, a rational), so that every
    power of b joins b's one chain."""
    of = {s: e.args for s, e in assigns if e.is_Pow and e.args[1].is_Rational}
    if not of:
        return assigns, outputs

    def sub(e):
        m = {}
        for pw in e.atoms(sp.Pow):
            b, x = pw.args
            if b in of and x.is_Rational and (of[b][1] * x).q in (1, 2):
                m[pw] = sp.Pow(of[b][0], of[b][1] * x)
        return e.xreplace(m) if m else e
    return [(s, sub(e)) for s, e in assigns], [sub(e) for e in outputs]


def _ops(assigns, outputs, n_trig: int) -> int:
    return int(sum(sp.count_ops(e) for _, e in assigns) + n_trig
               + sum(sp.count_ops(e) for e in outputs))


def lower(fn: Function, spec: ModelSpec) -> Lowered:
    outputs = [sp.sympify(e) for e in fn.outputs]
    # 1. trig symbols for the angles among the inputs
    angles = [v for v in fn.inputs if str(v) in ("phi", "theta", "psi", "vartheta", "zeta")]
    trig_map, trig = {}, []
    for a in angles:
        for f, tag in ((sp.sin, "s"), (sp.cos, "c")):
            sym = sp.Symbol(f"{tag}_{a}", real=True)
            trig_map[f(a)] = sym
            trig.append((sym, "sin" if tag == "s" else "cos", a))
    outputs = [e.xreplace(trig_map) for e in outputs]
    # 2. the plate: P_k = Phi_k(z) (the plate's own, possibly cancellation-free, forms)
    orders = sorted(set().union(*[phi_orders(e) for e in outputs])) if outputs else []
    P = {k: sp.Symbol(f"P{k}", real=True) for k in orders}
    outputs = [e.xreplace({Phi(k, Z): P[k] for k in orders}) for e in outputs]
    plate_syms, plate_exprs = [P[k] for k in orders], []
    if orders:
        derivs = spec.plate.phi_derivs(max(orders))
        plate_exprs = [derivs[k] for k in orders]
    # Phi_k at another height (the magnet's centre r + d n, top.moment_offset): Q<j>_<k>
    elsewhere = sorted({f for e in outputs for f in e.atoms(Phi)}, key=sp.default_sort_key)
    if elsewhere:
        heights = sorted({f.args[1] for f in elsewhere}, key=sp.default_sort_key)
        derivs = spec.plate.phi_derivs(max(int(f.args[0]) for f in elsewhere))
        qmap = {f: sp.Symbol(f"Q{heights.index(f.args[1])}_{int(f.args[0])}", real=True)
                for f in elsewhere}
        outputs = [e.xreplace(qmap) for e in outputs]
        for f, sym in qmap.items():
            plate_syms.append(sym)
            plate_exprs.append(derivs[int(f.args[0])].xreplace({Z: f.args[1]}))
    # a non-axisymmetric plate: B_i(x, y, z) and its derivatives -> the plate's closed forms
    field_atoms = sorted(set().union(*[_field_atoms(e) for e in outputs]) if outputs else set(),
                         key=sp.default_sort_key)
    if field_atoms:
        fmap = {}
        for atom in field_atoms:
            sym = sp.Symbol(_field_name(atom), real=True)
            fmap[atom] = sym
            plate_syms.append(sym)
            plate_exprs.append(_field_value(atom, spec.field3d))
        outputs = [e.xreplace(fmap) for e in outputs]
    # 3. one pass of common subexpressions over the whole function (plate and outputs together)
    nonzero = [i for i, e in enumerate(outputs) if e != 0]
    exprs = list(plate_exprs) + [outputs[i] for i in nonzero]
    repl, red = (sp.cse(exprs, symbols=sp.numbered_symbols("w"), order="none")
                 if exprs else ([], []))
    final = [sp.Integer(0)] * len(outputs)
    for i, e in zip(nonzero, red[len(plate_exprs):]):
        final[i] = e
    body = _toposort(list(repl) + list(zip(plate_syms, red[:len(plate_exprs)])))
    # 4. powers of a common base: one chain each, no pow()
    body, final = _flatten_powers(*_inline_aliases(body, final))
    body, final = _inline_aliases(*_fold_powers(_prune(body, final), final))
    body = _prune(body, final)
    need = _used(body, final)
    trig = [t for t in trig if t[0] in need]
    inputs = [(i, v) for i, v in enumerate(fn.inputs) if v in need or any(t[2] == v for t in trig)]
    params = [(i, v) for i, v in enumerate(spec.params) if v in need]
    return Lowered(fn.name, fn.doc, len(fn.inputs), len(final), fn.shape, inputs, params, trig,
                   body, final, _ops(body, final, len(trig)))
