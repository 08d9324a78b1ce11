"""Typed results of the public API (SI units, thesis 3.3). Each answer lives beside the code that
computes it and is re-exported here: Equilibria (runtime/physics/equilibrium/answer.py, its Equilibrium
runtime/physics/equilibrium/report.py's), Simulation (runtime/simulate/simulation.py), Simulations
(runtime/scan/batch_answer.py, simulate_many's), Scan (runtime/scan/scan_answer.py; ScanResult its
old name), LaunchOdds (runtime/scan/launch_answer.py), Stability (runtime/physics/stability/answer.py),
Design (runtime/design/design_answer.py; DesignResult its old name), Fit (runtime/design/fit_answer.py;
FitResult its old name), Trim (runtime/design/trim_answer.py).

Every result has a short `repr` with units (the scene's: a dimensionless scene shows none but
rad/time and time units; `units`, set by Study), and scipy-style `success` (bool) and `message` (one
sentence): for Stability,
whether a spin rate stabilises it (a stable spin interval exists); for LaunchOdds,
whether every sample has its verdict (a run that ended normally, or a top that cannot hover).
"""
from __future__ import annotations

from levitron.runtime.design.design_answer import Design, DesignResult
from levitron.runtime.design.fit_answer import Fit, FitResult
from levitron.runtime.design.fit_height import HeightFit
from levitron.runtime.design.launch_design_answer import LaunchDesign
from levitron.runtime.design.trim_answer import Trim
from levitron.runtime.design.yield_answer import YieldDesign
from levitron.runtime.physics.equilibrium.answer import Equilibria
from levitron.runtime.physics.equilibrium.report import Equilibrium
from levitron.runtime.physics.stability.answer import Stability
from levitron.runtime.scan.batch_answer import Simulations
from levitron.runtime.scan.launch_answer import LaunchOdds
from levitron.runtime.scan.scan_answer import Scan, ScanResult
from levitron.runtime.simulate.simulation import Simulation

__all__ = ["Design", "DesignResult", "Equilibria", "Equilibrium", "Fit", "FitResult", "HeightFit", "LaunchDesign",
           "LaunchOdds", "Scan", "ScanResult", "Simulation", "Simulations", "Stability", "Trim", "YieldDesign"]
