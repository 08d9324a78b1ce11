"""The physics of the ideal top and of a top in air: equilibria and the stable band, linear stability
by two routes, CasADi stability functions, exact fields, friction.

Public surface: equilibria_of, hover_height, stability_of, without_friction. Names load lazily (PEP
562), so importing the package costs nothing.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "equilibria_of": "equilibrium",
    "hover_height": "equilibrium",
    "stability_of": "stability",
    "without_friction": "friction",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
