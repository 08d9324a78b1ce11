"""One trajectory from the hover height: the launch state, the run, its summary (invariants, flight in
air) and its plot.

Public surface: DEFAULT_TILT, initial_state, simulate. Names load lazily (PEP 562), so importing
the package costs nothing.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "DEFAULT_TILT": "run",
    "initial_state": "run",
    "simulate": "run",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
