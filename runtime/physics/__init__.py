"""The physics of the ideal top and of a top in air, in rooms by idea (bottom to top; a room imports
only from itself and the rooms before it, tests/house/test_layers.py): field/ (exact fields, the
expansion's truncation error), plates/ (each plate kind's exact field), routes/ (the two routes of the
linear stability on the axis), equilibrium/ (where the top hovers, the stable band), apparatus/ (a
tilted base, a tilted magnet, air) and stability/ (the analysis over them all, the modes, the answer).

Public surface: equilibria_of, hover_height, stability_of, without_friction. Names load lazily (PEP
562), so importing the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "equilibria_of": "equilibrium.finder",
    "hover_height": "equilibrium.finder",
    "stability_of": "stability.analysis",
    "without_friction": "apparatus.friction",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
