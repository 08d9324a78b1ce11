"""A generated model, loaded and verified: the manifest and every file's hash, the C library compiled
and cached, the CasADi functions; scenes loaded with one-line errors.

Public surface: Model, load_model, read_manifest. Names load lazily (PEP 562), so importing the
package costs nothing.
"""
from __future__ import annotations

from levitron.runtime import lazy_surface

_EXPORTS = {
    "Model": "load",
    "load_model": "load",
    "read_manifest": "manifest",
}

__getattr__, __dir__, __all__ = lazy_surface(__name__, _EXPORTS)
