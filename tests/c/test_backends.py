"""sympy (lambdify), generated C and CasADi agree at 1,000 seeded random states to 1e-12 relative.

The sympy route substitutes the plate's Phi_k straight into the derived expressions (no common
subexpressions, no lowering), so it checks the emitters independently. Relative errors are taken
against the size of each output component over the sample (max |value| of that component), so a
component that happens to be near zero at one state is judged against the size of its terms.
"""
import numpy as np
import pytest
import sympy as sp

from levitron.derive.geometry import build_plate
from levitron.scene.load import load_scene
from levitron.derive.spec import build_spec
from levitron.derive.symbols import B_FUNCS, Phi, X, Y, Z
from levitron.runtime.model.load import load_model

N = 1000


def random_states(names, rng, n=N):
    X = np.empty((n, len(names)))
    for j, name in enumerate(names):
        if name in ("x", "y"):
            X[:, j] = rng.uniform(-0.02, 0.02, n)
        elif name == "z":
            X[:, j] = rng.uniform(0.05, 0.25, n)
        elif name in ("phi", "vartheta", "theta"):
            X[:, j] = rng.uniform(-0.6, 0.6, n) + (0.9 if name == "theta" else 0.0)
        elif name in ("zeta", "psi"):
            X[:, j] = rng.uniform(-np.pi, np.pi, n)
        elif name in ("p_x", "p_y", "p_z"):
            X[:, j] = rng.uniform(-0.003, 0.003, n)
        elif name == "p_zeta" or name == "p_psi":
            X[:, j] = rng.uniform(-3e-4, 3e-4, n)
        else:
            X[:, j] = rng.uniform(-1e-4, 1e-4, n)
    return X


_DIFFS: dict = {}


def field_derivative(sub, d):
    """sympy's exact derivative d (e.g. d^2 B_x / dx dz) of the field sub[B_i(X, Y, Z)], taken one
    variable at a time, each step sp.diff of the one before and remembered: the second
    derivatives of the Jacobian start from the first ones of the right-hand side."""
    expr = sub[d.expr]
    for v, n in d.variable_count:
        for _ in range(n):
            if (expr, v) not in _DIFFS:
                _DIFFS[expr, v] = sp.diff(expr, v)
            expr = _DIFFS[expr, v]
    return expr


def numpy_printer():
    """lambdify's own printer for "numpy", but printing each sum's terms in the order sympy holds
    them (order='none') rather than sorting them first: the same expressions, printed in half the
    time (the sort was most of lambdify's time on ring_magnet and square)."""
    from sympy.printing.numpy import NumPyPrinter
    return NumPyPrinter({"fully_qualified_modules": False, "inline": True,
                         "allow_unknown_functions": True, "user_functions": {}, "order": "none"})


def sympy_functions(model):
    scene = model.scene
    plate = build_plate(scene.data["plate"])
    spec = build_spec(scene.name, plate, model.manifest.field_order, scene.coordinates, scene.needs)
    out = {}
    for f in spec.functions:
        exprs = [sp.sympify(e) for e in f.outputs]
        kmax = max([k for e in exprs for k in [int(a.args[0]) for a in e.atoms(Phi)]] or [0])
        derivs = plate.phi_derivs(kmax)
        exprs = [e.xreplace({Phi(k, Z): derivs[k] for k in range(kmax + 1)}) for e in exprs]
        if spec.field3d is not None:      # the exact 3-D field, differentiated by sympy here
            sub = {f(X, Y, Z): spec.field3d[i] for i, f in enumerate(B_FUNCS)}
            # each derivative of B_i that occurs, evaluated once for all outputs, and each one of
            # second order as sympy's derivative of the first-order one (shared by every function
            # of the scene): the derivatives of e.subs(sub).doit(), in a third of the time
            atoms = set().union(*[e.atoms(sp.Derivative) for e in exprs])
            dmap = {d: field_derivative(sub, d) for d in atoms}
            exprs = [e.xreplace(dmap).xreplace(sub).doit() for e in exprs]
        fn = sp.lambdify([list(f.inputs), list(spec.params)], exprs, "numpy", printer=numpy_printer())
        out[f.name] = fn
    return out


CASES = [("thesis", "tait-bryan"), ("thesis", "euler-zxz"), ("ring_magnet", "tait-bryan"),
         ("square", "tait-bryan"), ("loop", "tait-bryan")]


def model_for(derived_model, scene: str, coords: str):
    """The scene's model in `coords`: generated/<scene> when these are the scene's own coordinates
    (the golden test, tests/derive/test_generated.py, proves generated/ is byte for byte what derive
    writes, so a second derivation here would check the same files), else a fresh derivation."""
    override = f"model.coordinates=\"{coords}\""
    if coords == load_scene(scene).coordinates:
        return load_model(load_scene(scene, [override]))
    return derived_model(scene, override)


@pytest.mark.parametrize("scene,coords", CASES)
def test_backends_agree_at_random_states(derived_model, scene, coords):
    model = model_for(derived_model, scene, coords)
    funcs = sympy_functions(model)
    rng = np.random.default_rng(20261121)
    for name in model.manifest.functions:
        if name in ("onaxis", "field"):
            names = ["z"] if name == "onaxis" else ["x", "y", "z"]
        else:
            names = model.manifest.parts[name.split("_")[0]].states
        X = random_states(names, rng)
        ref = np.array([np.broadcast_to(np.asarray(v, dtype=float), (N,))
                        for v in funcs[name](list(X.T), list(model.p))]).T
        c_out = np.array([model.call(name, x) for x in X])
        ca_fn = model.casadi(name)
        ca_out = np.asarray(ca_fn(X.T, np.tile(model.p[:, None], (1, N)))).T
        scale = np.maximum(np.max(np.abs(ref), axis=0), 1e-300)
        for label, got in (("C", c_out), ("CasADi", ca_out)):
            rel = np.max(np.abs(got - ref) / scale)
            assert rel < 1e-12, f"{name} via {label}: max relative deviation {rel:.2e}"
