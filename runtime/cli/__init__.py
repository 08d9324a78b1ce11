"""The `levitron` command: argparse, one module per command (commands/), one-line errors.

Public surface: main. Names load lazily (PEP 562), so importing the package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "main": "main",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
