"""The typed manifest of a generated model (generated/<scene>/manifest.json), read and checked once.

    manifest = read_manifest(folder, fix)    # -> Manifest, or ArtefactError (one line)

Every key must be present with the right type; the sizes must agree with each other (n_out with
the shape, a part's functions with its states, onaxis with onaxis_K); the manifest's own digest
and the sha256 of every file it lists must hold (scene/digest.py). Any failure is one line
naming the file or key and how to fix it (`fix`, e.g. "run `make derive`").
"""
from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

from levitron.scene.digest import SELF_KEY, first_changed_file, manifest_digest

from levitron.runtime.errors import UserError


class ArtefactError(UserError):
    """A generated or cached model file is missing, malformed, or not what its manifest says."""


@dataclass(frozen=True)
class FunctionInfo:
    """One generated function `void name(const double *in, const double *p, double *out)`."""

    name: str
    doc: str
    n_in: int
    n_out: int
    shape: tuple[int, ...]
    ops: int
    casadi: str          # the file name of its CasADi Function in the same folder


@dataclass(frozen=True)
class TaylorInfo:
    """A part's Taylor function `int name(const double *in, const double *p, int order, double *out)`
    (derive/emit/taylor.py): out[k (order + 1) + j] for its n states, orders 1 .. max_order."""

    part: str
    function: str
    n: int
    max_order: int
    nodes: int


@dataclass(frozen=True)
class PartInfo:
    """One part of the model ("reduced", "full") and its state names in order."""

    name: str
    equations: str
    states: tuple[str, ...]


@dataclass(frozen=True)
class Manifest:
    generator: str
    note: str
    scene: str
    input_hash: str
    versions: Mapping[str, str]
    plate: str
    coordinates: str
    field_order: int
    field_order_choice: Mapping
    onaxis_K: int
    parameters: tuple[str, ...]
    parts: Mapping[str, PartInfo]
    functions: Mapping[str, FunctionInfo]
    taylor: Mapping[str, TaylorInfo]      # part -> its Taylor function (parts without one: absent)
    symbol_prefix: str                    # the C symbol of function `name` is symbol_prefix + name
    files: Mapping[str, str]
    manifest_sha256: str


_TOP = {"generator": str, "note": str, "scene": str, "input_hash": str, "versions": dict,
        "plate": str, "coordinates": str, "field_order": int, "field_order_choice": dict,
        "onaxis_K": int, "parameters": list, "parts": dict, "functions": dict, "taylor": dict,
        "symbol_prefix": str, "files": dict,
        SELF_KEY: str}
_FUNCTION = {"doc": str, "n_in": int, "n_out": int, "shape": list, "ops": int, "casadi": str}
_PART = {"equations": str, "states": list}
_TAYLOR = {"function": str, "n": int, "max_order": int, "nodes": int}
_KIND_OUT = {"rhs": lambda nx: nx, "energy": lambda nx: 1, "jac": lambda nx: nx * nx,
             "invariants": lambda nx: 2, "dissipation": lambda nx: 1, "axis": lambda nx: 3}


def _typed(value, typ) -> bool:
    return isinstance(value, typ) and not (typ is int and isinstance(value, bool))


class _Reader:
    def __init__(self, where: str, fix: str):
        self.where, self.fix = where, fix

    def fail(self, what: str):
        raise ArtefactError(f"{self.where}: {what}; {self.fix}")

    def table(self, node, spec: dict, prefix: str) -> dict:
        if not isinstance(node, dict):
            self.fail(f"{prefix.rstrip('.') or 'the manifest'} is not a JSON object")
        for key, typ in spec.items():
            if key not in node:
                self.fail(f"key '{prefix}{key}' is missing")
            if not _typed(node[key], typ):
                self.fail(f"key '{prefix}{key}' is not a {typ.__name__}")
        return node

    def names(self, items, key: str) -> tuple[str, ...]:
        if not all(isinstance(n, str) and n.isidentifier() for n in items):
            self.fail(f"key '{key}' must list identifiers")
        if len(set(items)) != len(items):
            self.fail(f"key '{key}' lists a name twice")
        return tuple(items)

    def file_name(self, name, key: str) -> str:
        if not isinstance(name, str) or not name or "/" in name or "\\" in name or name[0] == ".":
            self.fail(f"key '{key}' = {name!r} is not a plain file name")
        return name


def parse_manifest(data, where: str, fix: str) -> Manifest:
    """The typed Manifest of a manifest.json's parsed JSON; ArtefactError on the first problem."""
    r = _Reader(where, fix)
    d = r.table(data, _TOP, "")
    params = r.names(d["parameters"], "parameters")
    parts = {}
    for name, info in d["parts"].items():
        r.table(info, _PART, f"parts.{name}.")
        states = r.names(info["states"], f"parts.{name}.states")
        parts[name] = PartInfo(name, info["equations"], states)
    functions = {}
    for name, info in d["functions"].items():
        key = f"functions.{name}"
        r.table(info, _FUNCTION, key + ".")
        shape = info["shape"]
        if not all(_typed(n, int) and n > 0 for n in shape) or math.prod(shape) != info["n_out"]:
            r.fail(f"key '{key}.shape' = {shape} does not hold n_out = {info['n_out']} values")
        if info["n_in"] < 1 or info["n_out"] < 1:
            r.fail(f"key '{key}' has a size below 1")
        functions[name] = FunctionInfo(name, info["doc"], info["n_in"], info["n_out"], tuple(shape),
                                       info["ops"], r.file_name(info["casadi"], key + ".casadi"))
    _check_sizes(r, parts, functions, d["onaxis_K"])
    taylor = {}
    for part, info in d["taylor"].items():
        key = f"taylor.{part}"
        r.table(info, _TAYLOR, key + ".")
        if part not in parts or info["n"] != len(parts[part].states):
            r.fail(f"key '{key}' is for no part of {info['n']} states")
        if info["function"] != f"{part}_taylor" or info["max_order"] < 1:
            r.fail(f"key '{key}' names {info['function']!r} up to order {info['max_order']}")
        taylor[part] = TaylorInfo(part, info["function"], info["n"], info["max_order"], info["nodes"])
    if not (d["symbol_prefix"] + "f").isidentifier() or not d["symbol_prefix"].isascii():
        r.fail(f"key 'symbol_prefix' = {d['symbol_prefix']!r} does not begin a C identifier")
    files = {r.file_name(n, f"files.{n}"): h for n, h in d["files"].items()}
    if not all(isinstance(h, str) for h in files.values()):
        r.fail("key 'files' must map file names to sha256 strings")
    for f in functions.values():
        if f.casadi not in files:
            r.fail(f"key 'files' has no digest of {f.casadi}")
    return Manifest(
        generator=d["generator"], note=d["note"], scene=d["scene"], input_hash=d["input_hash"],
        versions=MappingProxyType(dict(d["versions"])), plate=d["plate"],
        coordinates=d["coordinates"], field_order=d["field_order"],
        field_order_choice=MappingProxyType(dict(d["field_order_choice"])), onaxis_K=d["onaxis_K"],
        parameters=params, parts=MappingProxyType(parts), functions=MappingProxyType(functions),
        taylor=MappingProxyType(taylor), symbol_prefix=d["symbol_prefix"], files=MappingProxyType(files),
        manifest_sha256=d[SELF_KEY])


def _check_sizes(r: _Reader, parts: dict, functions: dict, kmax: int) -> None:
    """Sizes that follow from each other (docs/INTERFACES.md): a part's functions take its state;
    rhs, energy and jac give nx, 1 and nx*nx values, invariants 2, dissipation 1 and axis 3;
    onaxis gives Phi_0..Phi_K; field gives B."""
    expected = {"onaxis": (1, kmax + 1), "field": (3, 3)}
    for part in parts.values():
        nx = len(part.states)
        expected.update({f"{part.name}_{k}": (nx, out(nx)) for k, out in _KIND_OUT.items()})
    for name, f in functions.items():
        if name in expected and (f.n_in, f.n_out) != expected[name]:
            r.fail(f"functions.{name} says n_in = {f.n_in}, n_out = {f.n_out}, but the model's "
                   f"states and onaxis_K make them {expected[name][0]}, {expected[name][1]}")


def read_manifest(folder: Path, fix: str, expect_hash: str | None = None) -> Manifest:
    """Read, type-check and verify folder/manifest.json and every file it lists.

    `fix` ends every message (what the user should do); `expect_hash` is the input hash the folder
    must be for (None: any)."""
    path = Path(folder) / "manifest.json"
    r = _Reader(str(path), fix)
    try:
        data = json.loads(path.read_text())
    except (FileNotFoundError, NotADirectoryError):
        r.fail("does not exist")
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        r.fail(f"is not readable JSON ({type(exc).__name__})")
    manifest = parse_manifest(data, str(path), fix)
    if manifest_digest(data) != manifest.manifest_sha256:
        r.fail("was edited (its content does not match its manifest_sha256)")
    if expect_hash is not None and manifest.input_hash != expect_hash:
        r.fail(f"is for input hash {manifest.input_hash[:16]}, not {expect_hash[:16]}")
    bad = first_changed_file(folder, dict(manifest.files))
    if bad is not None:
        name, how = bad
        state = ("is missing" if how == "missing"
                 else "differs from the sha256 in manifest.json (edited or truncated)")
        raise ArtefactError(f"{Path(folder) / name} {state}; {fix}")
    return manifest
