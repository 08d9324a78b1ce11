"""CasADi design and fitting on scene keys: IPOPT on exact derivatives, fits with standard errors, the
strength that puts a top at a height, scene writing.

Public surface: Constraint, DesignResult, FitResult, Vary, fit, optimize. Names load lazily (PEP
562), so importing the package costs nothing.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "Constraint": "constraints",
    "DesignResult": "optimize",
    "FitResult": "fit",
    "Vary": "scene_keys",
    "fit": "fit",
    "optimize": "optimize",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
