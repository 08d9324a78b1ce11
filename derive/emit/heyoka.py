"""The heyoka backend of the emitter: the lowered right-hand side as heyoka expressions.

For the bench only (runtime/bench/heyoka.py): heyoka integrates the same graph the generated C
computes (derive/emit/lower.py: Hamilton's equations, thesis 2.3.9-2.3.16 / 3.2.12), handed over
through `heyoka.from_sympy`, in the bench's scaled states X_k = x_k / scale_k.
"""
from __future__ import annotations

import numpy as np


def lowered_rhs(scene, part_name: str):
    """The lowered `<part>_rhs` of the scene (derive's spec -> derive/emit/lower.py)."""
    from levitron.derive.build import field_order
    from levitron.derive.emit.lower import lower
    from levitron.derive.geometry import build_plate
    from levitron.derive.spec import build_spec
    order, _ = field_order(scene)
    spec = build_spec(scene.name, build_plate(scene.data["plate"]), order, scene.coordinates,
                      scene.needs, scene.friction, scene.tilted, scene.offset, scene.askew)
    fn = next(f for f in spec.functions if f.name == f"{part_name}_rhs")
    return lower(fn, spec)


def system(low, scale: np.ndarray):
    """heyoka's [(X_k, dX_k/dt)] in scaled states X_k = x_k / scale_k, parameters as par[i]."""
    import heyoka as hy
    import sympy as sp
    n = low.n_in
    X = hy.make_vars(*[f"X{i}" for i in range(n)])
    env = {v: X[i] * float(scale[i]) for i, v in low.inputs}
    env.update({v: hy.par[i] for i, v in low.params})
    for s, fn, a in low.trig:
        env[s] = (hy.sin if fn == "sin" else hy.cos)(env[a])
    for s, e in low.body:
        env[s] = hy.from_sympy(e, env)
    rhs = [hy.from_sympy(sp.sympify(e), env) / float(scale[i]) if e != 0 else hy.expression(0.0)
           for i, e in enumerate(low.outputs)]
    return list(zip(X, rhs))
