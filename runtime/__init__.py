"""The levitron runtime: numerics on generated models, in one subpackage per idea (README, "What is
where"; tests/house/test_layers.py keeps their layers). `lazy_surface` gives each subpackage's
`__init__` its public names, loaded on first use (PEP 562), so importing a package costs nothing."""
from __future__ import annotations

import importlib


def lazy_surface(package: str, exports: dict[str, str]):
    """(__getattr__, __dir__, __all__) of a package whose public name N lives in the module
    package.exports[N]."""
    def __getattr__(name: str):
        if name not in exports:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(f"{package}.{exports[name]}"), name)

    def __dir__():
        return sorted(set(exports) | set(vars(importlib.import_module(package))))

    return __getattr__, __dir__, sorted(exports)
