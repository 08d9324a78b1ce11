"""Generated C and CasADi compute the same numbers: every generated function of
every scene in scenes/, and 200 random formula plates, at seeded random points.

Relative 1e-12 of the size of the terms (tests/helpers/termsize.py: the running error bound of the graph
over the unit roundoff, which is |value| where nothing cancels), as docs/contract.md asks near a
zero of the quantity. Before the fix the C of a formula with a whole-number constant of 2^63 or
more held an integer literal that gcc reduced modulo 2^64: about a third of the random plates carry
one and failed here by about |value|.

The 200 formula plates run the real parser, plate builder, spec (onaxis and field), lowering, C
printer and CasADi builder, in CHUNKS tests (pytest-xdist spreads them over its workers), each
compiled into one shared library (one compiler call, cached by content); two of them, and the
two formulas of the issue, are derived in full (the reduced model) and loaded as models, so the
template and the runtime's loading are covered too.
"""
from __future__ import annotations

import ctypes
import dataclasses

from pathlib import Path

import numpy as np
import pytest

from levitron.scene.paths import SCENES_DIR
from levitron.scene.load import load_scene
from tests.helpers.formula_grammar import formula_plates
from tests.helpers.termsize import assert_agree, values_and_sizes

SCENES = sorted(p.stem for p in SCENES_DIR.glob("*.toml"))
N_POINTS = 48
N_FORMULAS = 200
SEED = 20261201


def sample(names: list[str], scale: float, rng: np.random.Generator, n: int = N_POINTS) -> np.ndarray:
    """(len(names), n) random states around a hovering top over a plate of length `scale`."""
    cols = []
    for name in names:
        if name in ("x", "y"):
            cols.append(rng.uniform(-0.3, 0.3, n) * scale)
        elif name == "z":
            cols.append(rng.uniform(0.3, 2.5, n) * scale)
        elif name in ("phi", "vartheta", "theta", "psi", "zeta"):
            cols.append(rng.uniform(-np.pi, np.pi, n) if name in ("psi", "zeta")
                        else rng.uniform(-0.6, 0.6, n) + (0.9 if name == "theta" else 0.0))
        elif name in ("p_zeta", "p_psi", "p_phi"):
            cols.append(rng.uniform(-3e-3, 3e-3, n))
        else:
            cols.append(rng.uniform(-3e-3, 3e-3, n))
    return np.array(cols)


def input_names(model, name: str) -> list[str]:
    if name == "onaxis":
        return ["z"]
    if name == "field":
        return ["x", "y", "z"]
    return list(model.manifest.parts[name.rsplit("_", 1)[0]].states)


@pytest.mark.parametrize("scene", SCENES)
def test_every_function_of_every_scene_agrees(scene):
    from levitron.runtime.model.load import load_model
    model = load_model(load_scene(scene))
    rng = np.random.default_rng(SEED)
    scale = model.scene.length_scale
    for name in model.manifest.functions:
        X = sample(input_names(model, name), scale, rng)
        P = np.tile(model.p[:, None], (1, X.shape[1]))
        fn = model.casadi(name)
        ca_out = np.asarray(fn(X, P), dtype=float)
        c_out = np.array([model.call(name, X[:, j]) for j in range(X.shape[1])]).T
        walked, size = values_and_sizes(fn, X, P)
        assert_agree(f"{scene}/{name}: C vs CasADi", c_out, ca_out, size)
        assert_agree(f"{scene}/{name}: term-size walk vs CasADi", walked, ca_out, size)


# ---------------------------------------------------------------- random formula plates

def _lower_plate(table: dict):
    """The lowered onaxis and field functions of one formula plate (derive's own path)."""
    from levitron.derive.emit.lower import lower
    from levitron.derive.geometry import build_plate
    from levitron.derive.spec import build_spec
    spec = build_spec("f", build_plate(table), 2, "tait-bryan", [])
    return [str(s) for s in spec.params], [lower(f, spec) for f in spec.functions]


def _c_function(name: str, low, printer) -> str:
    """One function in the template's form (derive/emit/c/templates/model.c.j2)."""
    from levitron.derive.emit.c.emitter import body_lines
    lines = [f"void {name}(const double *in, const double *p, double *out)", "{",
             "    (void)in; (void)p;"]
    lines += [f"    const double {v} = in[{i}];" for i, v in low.inputs]
    lines += [f"    const double {v} = p[{i}];" for i, v in low.params]
    lines += [f"    {line}" for line in body_lines(low, printer)]
    return "\n".join(lines + ["}"])


CHUNKS = 4        # the 200 plates in 4 tests, which pytest-xdist spreads over the workers


def formula_library(chunk: int, folder: str):
    """Plates chunk, chunk + CHUNKS, ... of the 200 lowered, printed into one C file, compiled,
    and their CasADi Functions."""
    from levitron.derive.emit.c.printer import FMA_PRELUDE, LevitronCPrinter
    from levitron.derive.emit.casadi.builder import build_function
    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compile_shared
    plates = formula_plates(N_FORMULAS, SEED)[chunk::CHUNKS]
    lowered = [_lower_plate(t) for t in plates]
    printer = LevitronCPrinter()
    source = [FMA_PRELUDE, "#ifndef M_PI", "#define M_PI 3.14159265358979323846", "#endif"]
    cases = []
    for i, (params, lows) in enumerate(lowered):
        for low in lows:
            cname = f"f{i}_{low.name}"
            source.append(_c_function(cname, low, printer))
            cases.append((i, cname, low.name, params,
                          build_function(dataclasses.replace(low, name=cname), len(params))))
    src = Path(folder) / f"formulas{chunk}.c"
    src.write_text("\n\n".join(source) + "\n")
    lib = ctypes.CDLL(str(compile_shared([src], DEFAULT_FLAGS)))
    return plates, cases, lib


def test_the_random_formulas_carry_large_whole_numbers():
    plates = formula_plates(N_FORMULAS, SEED)
    assert len(plates) == N_FORMULAS
    big = sum(any(k in (p.get("phi0") or p.get("bz")) for k in ("2**6", "2**7", "1e19", "1e20", "18446",
                                                                   "92233", "12345678901"))
              for p in plates)
    assert big >= N_FORMULAS // 5, f"only {big} formulas carry a whole number >= 2^63"


@pytest.mark.parametrize("chunk", range(CHUNKS))
def test_random_formula_plates_agree(chunk, tmp_path):
    plates, cases, lib = formula_library(chunk, str(tmp_path))
    assert len(cases) == 2 * len(plates) and len(plates) == N_FORMULAS // CHUNKS
    rng = np.random.default_rng(SEED + chunk)
    dbl = ctypes.POINTER(ctypes.c_double)
    for i, cname, kind, params, fn in cases:
        table = plates[i]
        X = sample(["z"] if kind == "onaxis" else ["x", "y", "z"], 1.0, rng)
        pvals = {"m": 0.02, "g": 9.81, "A": 2.2e-6, "C": 1.32e-6, "mu": -1.0,
                 **{f"plate_{k}": v for k, v in table["params"].items()}}
        p = np.array([pvals[n] for n in params])
        P = np.tile(p[:, None], (1, X.shape[1]))
        ca_out = np.asarray(fn(X, P), dtype=float)
        cfun = getattr(lib, cname)
        c_out = np.empty_like(ca_out)
        for j in range(X.shape[1]):
            x = np.ascontiguousarray(X[:, j])
            out = np.empty(ca_out.shape[0])
            cfun(x.ctypes.data_as(dbl), p.ctypes.data_as(dbl), out.ctypes.data_as(dbl))
            c_out[:, j] = out
        assert np.isfinite(ca_out).all(), f"{table}: the grammar made a non-finite {kind}"
        _, size = values_and_sizes(fn, X, P)
        assert_agree(f"{table} {kind}: C vs CasADi", c_out, ca_out, size)


ISSUE_FORMULAS = [("b*1e20*z/sqrt(z**2 + c**2)", 1e20), ("b*2**64*z/sqrt(z**2 + c**2)", 2.0 ** 64)]


@pytest.mark.parametrize("formula,factor", ISSUE_FORMULAS)
def test_issue_formulas_derive_in_full_and_give_the_formula_field(formula, factor, derived_model, tmp_path):
    """B_z on the axis = -dPhi0/dz = -b K c^2 / (z^2 + c^2)^(3/2), in C and CasADi (before: C gave
    -1.46e7 against -1.886e8 for 1e20, and 0 for 2**64)."""
    scene = tmp_path / "big.toml"
    scene.write_text("\n".join([
        'name = "big"', "[top]", "mass = 0.02", "A = 2.2e-6", "C = 1.32e-6", "moment = -1.0",
        "[plate]", 'kind = "expression"', f'phi0 = "{formula}"', "[plate.params]", "b = 1e-12",
        "c = 0.05", "[model]", 'needs = ["reduced"]']) + "\n")
    model = derived_model(str(scene))
    for z in (0.02, 0.05, 0.11):
        want = -1e-12 * factor * 0.05 ** 2 / (z ** 2 + 0.05 ** 2) ** 1.5
        for backend in ("c", "casadi"):
            bz = model.call("field", [0.0, 0.0, z], backend=backend)[2]
            assert abs(bz - want) <= 1e-13 * abs(want), (backend, z, bz, want)
    rng = np.random.default_rng(SEED)
    for name in model.manifest.functions:
        X = sample(input_names(model, name), 0.05, rng)
        P = np.tile(model.p[:, None], (1, X.shape[1]))
        fn = model.casadi(name)
        c_out = np.array([model.call(name, X[:, j]) for j in range(X.shape[1])]).T
        _, size = values_and_sizes(fn, X, P)
        assert_agree(f"{formula} {name}", c_out, np.asarray(fn(X, P), dtype=float), size)


@pytest.mark.parametrize("index", [0, 1])
def test_random_formula_plates_derive_in_full(index, derived_model, tmp_path):
    """Two of the random plates through derive_scene, the template and the model loader."""
    table = formula_plates(N_FORMULAS, SEED)[index]
    key = "phi0" if "phi0" in table else "bz"
    lines = [f'name = "formula{index}"', "[top]", "mass = 0.02", "A = 2.2e-6", "C = 1.32e-6",
             "moment = -1.0", "[plate]", 'kind = "expression"', f'{key} = "{table[key]}"',
             "[plate.params]", *[f"{k} = {v!r}" for k, v in table["params"].items()], "[model]",
             'needs = ["reduced"]']
    scene = tmp_path / f"formula{index}.toml"
    scene.write_text("\n".join(lines) + "\n")
    model = derived_model(str(scene))
    rng = np.random.default_rng(SEED + index)
    for name in model.manifest.functions:
        X = sample(input_names(model, name), 1.0, rng)
        P = np.tile(model.p[:, None], (1, X.shape[1]))
        fn = model.casadi(name)
        c_out = np.array([model.call(name, X[:, j]) for j in range(X.shape[1])]).T
        _, size = values_and_sizes(fn, X, P)
        assert_agree(f"{table[key]} {name}", c_out, np.asarray(fn(X, P), dtype=float), size)
