"""One trajectory from the hover height: the launch state, the run, its summary (invariants, flight in
air) and its plot.

Public surface: DEFAULT_TILT, initial_state, simulate. Names load lazily (PEP 562), so importing
the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "DEFAULT_TILT": "run",
    "initial_state": "run",
    "simulate": "run",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
