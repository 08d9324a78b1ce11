"""How numbers, progress and pictures reach a person: units per scene, progress on stderr, matplotlib
with one style, provenance of every answer.

Public surface: Units, lines, pyplot, save_figure, sig. Names load lazily (PEP 562), so importing
the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "Units": "human",
    "lines": "human",
    "pyplot": "plotting",
    "save_figure": "plotting",
    "sig": "human",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
