"""levitron_api: the public Python API of the levitron toolchain (docs/api.md).

    import levitron_api as lev
    study = lev.load("thesis_stable", {"top.mass": 0.051})
    study.equilibria().z_c                     # m
    study.stability().spin_interval            # rad/s
    study.functions()["spin"]                  # casadi.Function, named inputs and outputs
    study.optimize("spin-range", {"top.mass": (0.0505, 0.0524)}, ["stiffness>=0.5"]).optimum

Numbers are named by their scene keys (`top.mass`, `plate.hole`); the one mapping to the generated
parameter vector is runtime/scene_keys.py. Every method returns a typed dataclass whose fields
carry their units in the docstrings, a short `repr`, and scipy-style `success` and `message`. Bad
arguments raise levitron_api.UserError (one line: what is wrong, how to fix it). The command line
(`levitron ...`) calls the same functions.
"""
from __future__ import annotations

from runtime.design import DesignResult
from runtime.errors import UserError
from runtime.fit import FitResult
from runtime.scan import ScanResult

from .results import Equilibria, Equilibrium, LaunchOdds, Simulation, Stability
from .study import Study, load

__all__ = ["DesignResult", "Equilibria", "Equilibrium", "FitResult", "LaunchOdds", "ScanResult",
           "Simulation", "Stability", "Study", "UserError", "load"]
