"""Integrators: one table of methods (methods.py), a step budget for every run, and one backend module
each (C, CasADi, scipy) behind `integrate`.

Public surface: Box, METHODS, Result, integrate, lookup, resolve. Names load lazily (PEP 562), so
importing the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "Box": "trajectory",
    "METHODS": "methods",
    "Result": "trajectory",
    "integrate": "run",
    "lookup": "methods",
    "resolve": "methods",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
