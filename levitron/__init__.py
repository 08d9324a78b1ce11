"""levitron: the public Python API of the levitron toolchain (docs/api.md).

    import levitron as lev
    study = lev.load("thesis_stable", {"top.mass": 0.051})
    study.equilibria().z_c                     # m
    study.stability().spin_interval            # rad/s
    study.functions()["spin"]                  # casadi.Function, named inputs and outputs
    study.optimize("spin-range", {"top.mass": (0.0505, 0.0524)}, ["stiffness>=0.5"]).optimum

Numbers are named by their scene keys (`top.mass`, `plate.hole`); the one mapping to the generated
parameter vector is runtime/design/scene_keys.py. Every method returns a typed dataclass whose fields
carry their units in the docstrings, a short `repr`, and scipy-style `success` and `message`. The
command line (`levitron ...`) calls the same functions.

Bad input raises `levitron.UserError` (runtime.errors.UserError: a one-line message saying what
is wrong and how to fix it, the line the command line prints); `levitron.SceneError` is the
scene reader's own (levitron.scene.checks), raised by `load_scene`-level helpers. Both are exported here.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

# levitron.runtime is levitron/runtime/: in a checkout a relative link to the top-level runtime/ (so are scene/,
# derive/, scenes/ and generated/: docs/INTERFACES.md "Layout"), in a wheel the folder itself
from levitron.runtime import lazy_surface as _lazy_surface


def _version() -> str:
    """The installed distribution's version (pyproject.toml), or "0+unknown" outside one."""
    from importlib.metadata import PackageNotFoundError, version
    try:
        return version("levitron")
    except PackageNotFoundError:
        return "0+unknown"


__version__ = _version()

# the public names, loaded on first use: `import levitron` (and `python -m levitron.derive`, the
# command line's start) costs no numpy, casadi or scipy; type checkers and IDEs read the imports
# below instead (the same names from the same modules: tests/house/test_types.py keeps them so)
_EXPORTS = {
    "Design": "results", "DesignResult": "results", "Equilibria": "results", "Equilibrium": "results",
    "Fit": "results", "FitResult": "results", "HeightFit": "results", "LaunchDesign": "results",
    "LaunchOdds": "results", "Propagator": "runtime.integrate.propagator",
    "Scan": "results", "ScanResult": "results",
    "SceneError": "scene.checks", "Simulation": "results", "Simulations": "results",
    "Stability": "results", "Study": "study", "Trim": "results", "UserError": "runtime.errors",
    "YieldDesign": "results",
    "load": "study", "plate_from_magpylib": "from_magpylib"}

if TYPE_CHECKING:
    from levitron.from_magpylib import plate_from_magpylib
    from levitron.results import (Design, DesignResult, Equilibria, Equilibrium, Fit, FitResult, HeightFit,
                                  LaunchDesign, LaunchOdds, Scan, ScanResult, Simulation, Simulations, Stability,
                                  Trim, YieldDesign)
    from levitron.runtime.errors import UserError
    from levitron.runtime.integrate.propagator import Propagator
    from levitron.scene.checks import SceneError
    from levitron.study import Study, load
else:
    __getattr__, __dir__, _ = _lazy_surface(__name__, _EXPORTS)

__all__ = ["Design", "DesignResult", "Equilibria", "Equilibrium", "Fit", "FitResult", "HeightFit", "LaunchDesign",
           "LaunchOdds", "Propagator", "Scan", "ScanResult", "SceneError", "Simulation", "Simulations", "Stability",
           "Study", "Trim", "UserError", "YieldDesign", "load", "plate_from_magpylib"]
