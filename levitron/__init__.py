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
scene reader's own (derive.scene), raised by `load_scene`-level helpers. Both are exported here.
"""
from __future__ import annotations

from levitron.derive.scene import SceneError
from levitron.runtime.design.optimize import DesignResult
from levitron.runtime.errors import UserError
from levitron.runtime.design.fit import FitResult
from levitron.runtime.scan.stability_map import ScanResult

from .results import Equilibria, Equilibrium, LaunchOdds, Simulation, Simulations, Stability
from .study import Study, load

__all__ = ["DesignResult", "Equilibria", "Equilibrium", "FitResult", "LaunchOdds", "ScanResult",
           "SceneError", "Simulation", "Simulations", "Stability", "Study", "UserError", "load"]
