"""The physics of the ideal top and of a top in air: equilibria and the stable band, linear stability
by two routes, CasADi stability functions, exact fields, friction.

Public surface: equilibria_of, hover_height, stability_of, without_friction. Names load lazily (PEP
562), so importing the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "equilibria_of": "equilibrium",
    "hover_height": "equilibrium",
    "stability_of": "stability",
    "without_friction": "friction",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
