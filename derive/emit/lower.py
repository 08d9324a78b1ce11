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
from ..symbols import Phi, Z, phi_orders


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
    phi_assigns = []
    if orders:
        derivs = spec.plate.phi_derivs(max(orders))
        repl, red = sp.cse([derivs[k] for k in orders], symbols=sp.numbered_symbols("u"), order="none")
        phi_assigns = list(repl) + [(P[k], e) for k, e in zip(orders, red)]
    # 3. the main block
    nonzero = [i for i, e in enumerate(outputs) if e != 0]
    repl, red = sp.cse([outputs[i] for i in nonzero], symbols=sp.numbered_symbols("w"), order="none")
    final = [sp.Integer(0)] * len(outputs)
    for i, e in zip(nonzero, red):
        final[i] = e
    main = _prune(list(repl), final)
    need_main = _used(main, final)
    trig = [t for t in trig if t[0] in need_main]
    phi_assigns = _prune(phi_assigns, [s for s in P.values() if s in need_main])
    need_all = need_main | _used(phi_assigns, [s for s, _ in phi_assigns])
    inputs = [(i, v) for i, v in enumerate(fn.inputs) if v in need_all or any(t[2] == v for t in trig)]
    params = [(i, v) for i, v in enumerate(spec.params) if v in need_all]
    ops = (sum(sp.count_ops(e) for _, e in phi_assigns) + len(trig)
           + sum(sp.count_ops(e) for _, e in main) + sum(sp.count_ops(e) for e in final))
    return Lowered(fn.name, fn.doc, len(fn.inputs), len(final), fn.shape, inputs, params, trig,
                   phi_assigns, main, final, int(ops))
