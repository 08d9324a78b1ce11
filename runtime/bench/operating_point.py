"""The scene's own operating point of `levitron bench` (runtime/bench/work_precision.py's module
docstring): its top at its hover height z_s (thesis 3.3.2-3.3.3), spinning at the geometric mean of
its linear stability interval (thesis 3.3), perturbed by DELTA, and the time scales of the motion
there (T_fast, the run's length)."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.physics.routes.eigen_route import transverse_matrix
from levitron.runtime.physics.stability.analysis import stability_of
from levitron.runtime.simulate.start import initial_state, state_scales

DELTA = 0.01            # the perturbation: tilt DELTA rad, offset DELTA z_s, lift 2 DELTA z_s
SPIN_PERIODS = 32       # the length of a run


@dataclass(frozen=True)
class Setup:
    """The scene's own operating point and time scales (see the module docstring)."""
    p: np.ndarray
    z_s: float
    spin: float
    spin_basis: str
    spin_interval: tuple[float, float] | None
    t_fast: float
    t_end: float

    def as_dict(self) -> dict:
        return {"z_s": self.z_s, "spin": self.spin, "spin_basis": self.spin_basis,
                "spin_interval": None if self.spin_interval is None else list(self.spin_interval),
                "t_fast": self.t_fast, "t_end": self.t_end, "delta": DELTA,
                "spin_periods": SPIN_PERIODS}


def setup(model, p: np.ndarray | None = None) -> Setup:
    """The operating point of the scene's own top (thesis 3.3.2-3.3.3 and 3.3; module docstring)."""
    p = np.array(model.p if p is None else p, dtype=float)
    P = eqm.params_of(model, p)
    name = model.scene.name
    z_s = eqm.hover_height(model, p)
    res = stability_of(model, p=p, z_s=z_s)
    ph = np.asarray(model.onaxis(z_s, p), float)
    if res.spin_interval is not None:
        lo, hi = res.spin_interval
        spin, basis = math.sqrt(lo * hi), "geometric mean of the linear stability interval"
    elif "full" in model.parts:
        raise UserError(f"scene '{name}' has no stable spin interval, and bench runs the scene's top "
                        f"inside it: {res.reason}")
    else:
        rho = P["C"] / P["A"]
        spin = math.sqrt(abs(P["mu"] * ph[1]) / P["A"]) / rho
        basis = ("g1 = 1 (thesis 3.3.10): the scene's top has no stable interval; the reduced model "
                 "does not depend on it")
    if not (spin > 0 and math.isfinite(spin)):
        raise UserError(f"scene '{name}': no finite spin to bench at (spin {spin})")
    rates = [spin]
    k = P["mu"] * ph[3]
    if k > 0:
        rates.append(math.sqrt(k / P["m"]))
    lam = np.linalg.eigvals(transverse_matrix(ph[1], ph[2], ph[3], P["m"], P["A"], P["C"], P["mu"], spin))
    rates.append(float(np.abs(lam).max()))
    t_fast = 2 * math.pi / max(r for r in rates if math.isfinite(r))
    return Setup(p, z_s, spin, basis, res.spin_interval, t_fast, SPIN_PERIODS * 2 * math.pi / spin)


def start(model, part_name: str, su: Setup):
    """(part, x0, state scales) of the bench run of one part from the Setup's operating point."""
    part = model.part(part_name)
    pv = eqm.params_of(model, su.p)
    if part_name == "full":
        x0 = initial_state(part, su.z_s, su.spin, DELTA, DELTA * su.z_s, su.p)
    else:
        x0 = initial_state(part, su.z_s, su.spin, 0.0, 0.0, su.p)
    x0[part.states.index("z")] *= 1 + 2 * DELTA
    return part, x0, state_scales(part, su.z_s, su.spin, pv)
