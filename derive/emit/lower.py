"""Lower a symbolic Function to straight-line code that every backend prints the same way.

Three blocks, in order:
1. trig:  s_q = sin(q), c_q = cos(q) for every angle q the function uses (each computed once);
2. phi:   P_k = Phi_k(z) of the plate for the orders k the function needs, common subexpressions
          shared (the plate's own, possibly cancellation-free, forms: Plate.phi_derivs);
3. main:  the outputs in terms of the inputs, parameters, s_q, c_q and P_k, common subexpressions
          shared.
Only what an output needs is kept, so generated C has no unused variables.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..spec import Function, ModelSpec
from ..symbols import B_FUNCS, Phi, X, Y, Z, phi_orders


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
    phi: list               # [(symbol, expr)] temporaries and P_k of the plate block
    main: list              # [(symbol, expr)] temporaries of the main block
    outputs: list           # expressions, flattened row-major
    ops: int                # operation count (sympy count_ops over all blocks; sin/cos count 1)


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
    # 2. the plate block
    orders = sorted(set().union(*[phi_orders(e) for e in outputs])) if outputs else []
    P = {k: sp.Symbol(f"P{k}", real=True) for k in orders}
    outputs = [e.xreplace({Phi(k, Z): P[k] for k in orders}) for e in outputs]
    plate_syms, plate_exprs = [P[k] for k in orders], []
    if orders:
        derivs = spec.plate.phi_derivs(max(orders))
        plate_exprs = [derivs[k] for k in orders]
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
    phi_assigns = []
    if plate_exprs:
        repl, red = sp.cse(plate_exprs, symbols=sp.numbered_symbols("u"), order="none")
        phi_assigns = list(repl) + list(zip(plate_syms, red))
    # 3. the main block
    nonzero = [i for i, e in enumerate(outputs) if e != 0]
    repl, red = sp.cse([outputs[i] for i in nonzero], symbols=sp.numbered_symbols("w"), order="none")
    final = [sp.Integer(0)] * len(outputs)
    for i, e in zip(nonzero, red):
        final[i] = e
    main = _prune(list(repl), final)
    need_main = _used(main, final)
    trig = [t for t in trig if t[0] in need_main]
    phi_assigns = _prune(phi_assigns, [s for s in plate_syms if s in need_main])
    need_all = need_main | _used(phi_assigns, [s for s, _ in phi_assigns])
    inputs = [(i, v) for i, v in enumerate(fn.inputs) if v in need_all or any(t[2] == v for t in trig)]
    params = [(i, v) for i, v in enumerate(spec.params) if v in need_all]
    ops = (sum(sp.count_ops(e) for _, e in phi_assigns) + len(trig)
           + sum(sp.count_ops(e) for _, e in main) + sum(sp.count_ops(e) for e in final))
    return Lowered(fn.name, fn.doc, len(fn.inputs), len(final), fn.shape, inputs, params, trig,
                   phi_assigns, main, final, int(ops))
