"""The plate registry, scene side (pure Python: the runtime imports it, sympy never loads).

One module per plate kind in this package defines `KIND` (scene/plates/base.py says what a kind
declares). The derive side is derive/plate_fields/<kind>.py (the sympy builder), the runtime
side runtime/physics/plates/<kind>.py (the exact field); tests/scene/test_plate_registry.py checks that the three
registries have the same kinds. Adding a plate kind is one file on each side.

Functions over a scene's [plate] table (validated by scene/load.py), compound parts included:
`resolve` (SI parameters), `decisions` (the structural decisions, for the input hash),
`length_scale` (the plate's characteristic length) and `param_units` (the parameters' SI units).
"""
from __future__ import annotations

import importlib
import pkgutil

from ..checks import SceneError, check_keys
from .base import Context, PlateKind

_NOT_KINDS = ("base", "docs", "symmetry")   # the modules of this package that are not plate kinds


def _discover() -> dict[str, PlateKind]:
    kinds = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        if info.ispkg or info.name in _NOT_KINDS:
            continue
        kind = getattr(importlib.import_module(f"{__name__}.{info.name}"), "KIND", None)
        if isinstance(kind, PlateKind):
            if kind.name != info.name:
                raise ImportError(f"scene/plates/{info.name}.py declares kind {kind.name!r}: "
                                  "name the module after its kind")
            kinds[kind.name] = kind
    return kinds


KINDS: dict[str, PlateKind] = _discover()


def kind_of(table: dict, where: str = "plate") -> PlateKind:
    kind = table.get("kind")
    if not isinstance(kind, str) or kind not in KINDS:
        raise SceneError(f"{where}.kind = {kind!r} is unknown: use one of {', '.join(KINDS)}")
    return KINDS[kind]


def resolve(table: dict, moment: float | None) -> dict:
    """The plate's SI parameters by name (module docstring), after checking its keys."""
    kind = kind_of(table)
    check_keys(table, kind.allowed, "plate")
    return dict(kind.resolve(table, Context(moment, "plate", KINDS)))


def _parts(table: dict) -> list[dict]:
    return list(table["parts"]) if KINDS[table["kind"]].has_parts else []


def decisions(table: dict) -> dict:
    """Every structural decision of a validated [plate] table: {kind, <decision>: bool, parts}."""
    kind = KINDS[table["kind"]]
    out: dict = {"kind": kind.name}
    out.update({d.name: bool(d.test(table)) for d in kind.decisions})
    if kind.has_parts:
        out["parts"] = [decisions(p) for p in _parts(table)]
    return out


def length_names(table: dict, prefix: str = "plate_") -> list[str]:
    """The Scene.params names of the plate's lengths, compound parts included (plate_p<i>_<key>)."""
    kind = KINDS[table["kind"]]
    names = [prefix + key for key in kind.length_keys]
    for i, part in enumerate(_parts(table)):
        names += length_names(part, f"{prefix}p{i}_")
    return names


def param_units(table: dict, prefix: str = "plate_") -> dict[str, str]:
    """The SI unit of each of the plate's Scene.params names that has one (lengths "m", the kind's
    `units`), compound parts included; an expression plate's own parameters have none."""
    kind = KINDS[table["kind"]]
    out = {prefix + key: unit for key, unit in kind.units.items()}
    out.update({name: "m" for name in length_names(table, prefix) if name.startswith(prefix)})
    for i, part in enumerate(_parts(table)):
        out.update(param_units(part, f"{prefix}p{i}_"))
    return out


def length_scale(table: dict, params: dict) -> float:
    """The plate's characteristic length: its largest length parameter (SI or scene units), or 1.0
    for a plate without lengths (an expression plate, a dimensionless scene)."""
    lengths = [abs(float(params[n])) for n in length_names(table) if n in params]
    lengths = [v for v in lengths if v > 0]
    return max(lengths) if lengths else 1.0
