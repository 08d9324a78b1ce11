"""Many runs on the chunked C driver: stability maps (serial, local processes, dask) and the launch
Monte Carlo.

Public surface: ScanResult, monte_carlo, scan, wilson. Names load lazily (PEP 562), so importing
the package costs nothing.
"""
from __future__ import annotations

import importlib

_EXPORTS = {
    "ScanResult": "stability_map",
    "monte_carlo": "launch_odds",
    "scan": "stability_map",
    "wilson": "launch_odds",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
