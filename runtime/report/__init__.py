"""The self-contained HTML report and the thesis's figures.

Public surface: build. Names load lazily (PEP 562), so importing the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "build": "page",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
