"""A generated model, loaded and verified: the manifest and every file's hash, the C library compiled
and cached, the CasADi functions; scenes loaded with one-line errors.

Public surface: Model, load_model, read_manifest. Names load lazily (PEP 562), so importing the
package costs nothing.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "Model": "load",
    "load_model": "load",
    "read_manifest": "manifest",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
