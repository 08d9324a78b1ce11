"""How numbers, progress and pictures reach a person: units per scene, progress on stderr, matplotlib
with one style, provenance of every answer.

Public surface: Units, lines, pyplot, save_figure, sig. Names load lazily (PEP 562), so importing
the package costs nothing.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "Units": "human",
    "lines": "human",
    "pyplot": "plotting",
    "save_figure": "plotting",
    "sig": "human",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
