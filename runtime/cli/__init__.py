"""The `levitron` command: argparse, one module per command (commands/), one-line errors.

Public surface: main. Names load lazily (PEP 562), so importing the package costs nothing.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "main": "main",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
