"""Benchmarks (`make bench`, never timed tests): work-precision against heyoka and the other backends,
maps, design, launches.

No public names: each module runs as `python -m runtime.bench.<name>`.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
