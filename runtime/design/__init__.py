"""CasADi design and fitting on scene keys: IPOPT on exact derivatives, fits with standard errors, the
strength that puts a top at a height, scene writing.

Public surface: Constraint, Design (DesignResult its old name), Fit (FitResult its old name), Vary,
fit, optimize. Names load lazily (PEP 562), so importing the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "Constraint": "constraints",
    "Design": "design_answer",
    "DesignResult": "design_answer",
    "Fit": "fit_answer",
    "FitResult": "fit_answer",
    "Vary": "scene_keys",
    "fit": "fit",
    "optimize": "optimize",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
