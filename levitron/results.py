"""Typed results of the public API (SI units, thesis 3.3). Each answer lives beside the code that
computes it and is re-exported here: Equilibria (runtime/physics/equilibria.py, its Equilibrium
runtime/physics/equilibrium_report.py's), Simulation (runtime/simulate/simulation.py), Scan
(runtime/scan/scan_answer.py; ScanResult its old name), LaunchOdds (runtime/scan/launch_answer.py),
Stability (runtime/physics/stability_answer.py), Design (runtime/design/design_answer.py;
DesignResult its old name), Fit (runtime/design/fit_answer.py; FitResult its old name), Trim
(runtime/design/trim_answer.py).

Every result has a short `repr` with units (the scene's: a dimensionless scene shows none but
rad/time and time units; `units`, set by Study), and scipy-style `success` (bool) and `message` (one
sentence): for Stability,
whether a spin rate stabilises it (a stable spin interval exists); for LaunchOdds,
whether every sample has its verdict (a run that ended normally, or a top that cannot hover).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.design.design_answer import Design, DesignResult
from levitron.runtime.design.fit_answer import Fit, FitResult
from levitron.runtime.design.fit_height import HeightFit
from levitron.runtime.design.launch_design_answer import LaunchDesign
from levitron.runtime.design.trim_answer import Trim
from levitron.runtime.design.yield_answer import YieldDesign
from levitron.runtime.errors import UserError
from levitron.runtime.integrate.verdict import NO_HOVER
from levitron.runtime.physics.equilibria import Equilibria
from levitron.runtime.physics.equilibrium_report import Equilibrium
from levitron.runtime.physics.stability_answer import Stability
from levitron.runtime.scan.launch_answer import LaunchOdds
from levitron.runtime.scan.scan_answer import Scan, ScanResult
from levitron.runtime.simulate.simulation import NORMAL_ENDS, Simulation
from levitron.runtime.ui.human import Units, quantity, restate

_SI = Units(si=True)


__all__ = ["Design", "DesignResult", "Equilibria", "Equilibrium", "Fit", "FitResult", "HeightFit", "LaunchDesign",
           "LaunchOdds", "Scan", "ScanResult", "Simulation", "Simulations", "Stability", "Trim", "YieldDesign"]


@dataclass(frozen=True, repr=False)
class Simulations:
    """Many launches in one call of the C chunk driver (Study.simulate_many, runtime/scan/batch.py),
    each the run Study.simulate makes with the same options, as arrays of length n: levitating
    (bool: the run reached t_end), untested (a launch on the invariant set, which tests nothing, or
    a run that stopped early without a verdict: Study.simulate's levitating None), status
    (runtime/integrate/c_backend.py STATUS names),
    t_survived (s), rhs_evals (without simulate's dense-output evaluations), steps, z_s (m, each
    launch's hover height), final_states (n, len(states)), SI; inputs: the launch columns
    {spin (rad/s), tilt (rad), offset (m), azimuth (rad), and any varied scene keys}; wall_s (s,
    the whole call); details: t_end, integrator, tol, lanes (whether the lane variant ran);
    reason: per launch, why its top cannot hover (None where it can): such a launch is not run,
    its status "no_hover_height", levitating False, t_survived 0, z_s and final state NaN."""

    levitating: np.ndarray
    untested: np.ndarray
    status: np.ndarray
    t_survived: np.ndarray
    rhs_evals: np.ndarray
    steps: np.ndarray
    z_s: np.ndarray
    final_states: np.ndarray
    states: list
    inputs: dict
    wall_s: float
    details: dict = field(default_factory=dict)
    units: Units = field(default=_SI, repr=False, compare=False)   # how repr and message show numbers
    reason: np.ndarray | None = None

    # a launch's verdict: its run ended normally, or its top cannot hover (not run: no solver's failure)
    VERDICTS = NORMAL_ENDS + (NO_HOVER,)

    def __len__(self) -> int:
        return int(self.status.size)

    def final_state(self, i: int) -> dict:
        """Launch i's final state by name, as Study.simulate's final_state."""
        n = len(self)
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not -n <= i < n:
            raise UserError(f"final_state({i!r}): give a launch index from 0 to {n - 1} (or -1 for the last)")
        return {k: float(v) for k, v in zip(self.states, self.final_states[i])}

    @property
    def success(self) -> bool:
        """Every launch has its verdict: its run ended normally (reached t_end, or stopped when the
        top left the box), or its top cannot hover."""
        return bool(np.all(np.isin(self.status, self.VERDICTS)))

    @property
    def message(self) -> str:
        n = len(self)
        bad = np.flatnonzero(~np.isin(self.status, self.VERDICTS))
        if bad.size:
            kinds = ", ".join(sorted(set(self.status[bad].tolist())))
            return (f"{bad.size} of {n} runs did not end normally ({kinds}; the first: launch "
                    f"{int(bad[0])})")
        lev = int(np.sum(self.levitating & ~self.untested))
        no = np.flatnonzero(self.status == NO_HOVER)
        ran = n - no.size
        text = (f"{ran} runs ended normally; {lev} stayed up for the whole "
                f"{quantity(self.units, self.details.get('t_end'), 's')}") if ran else "no launch ran"
        if np.any(self.untested):
            text += f"; {int(np.sum(self.untested))} launched on the invariant set test nothing"
        if no.size:
            why = self.reason[no[0]] if self.reason is not None else None
            text += (f"; {no.size} cannot hover (the first, launch {int(no[0])}: "
                     f"{restate(why, self.units) if why else 'no stable hover height'})")
        return text

    def __repr__(self) -> str:
        n = len(self)
        lev = int(np.sum(self.levitating & ~self.untested))
        ts = self.t_survived
        no = int(np.sum(self.status == NO_HOVER))
        t_end = self.details.get("t_end")
        return (f"Simulations(n={n}, levitating={lev} of {n - int(np.sum(self.untested))} tested, "
                f"t_survived={np.min(ts):.6g}-{np.max(ts):.6g} of "
                f"{quantity(self.units, float('nan') if t_end is None else t_end, 's')}, "
                + (f"cannot hover={no}, " if no else "")
                + f"lanes={self.details.get('lanes')}, success={self.success})")
