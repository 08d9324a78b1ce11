"""A trajectory and the region it must stay in: the data every integrator backend returns
(runtime/integrate/run.py; thesis 3.1)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Box:
    """The region the state must stay in: z_lo <= x[iz] <= z_hi and hypot(x[ix], x[iy]) <= r_max.

    Indices of absent coordinates are -1 (the reduced model has no x, y)."""
    iz: int
    z_lo: float
    z_hi: float
    ix: int = -1
    iy: int = -1
    r_max: float = math.inf

    def excess(self, x: np.ndarray) -> float:
        """> 0 iff x is outside (the largest violated margin); the same test as the C code."""
        g = -math.inf
        if self.iz >= 0:
            g = max(g, x[self.iz] - self.z_hi, self.z_lo - x[self.iz])
        if math.isfinite(self.r_max) and (self.ix >= 0 or self.iy >= 0):
            r = math.hypot(x[self.ix] if self.ix >= 0 else 0.0, x[self.iy] if self.iy >= 0 else 0.0)
            g = max(g, r - self.r_max)
        return g


@dataclass
class Result:
    """One trajectory. X[i] is the state at t[i]; x_final at t_final is the last (finite) state."""
    t: np.ndarray
    X: np.ndarray
    status: str
    message: str
    rhs_evals: int | None
    wall_s: float
    t_final: float
    x_final: np.ndarray
    method: str = ""
    backend: str = ""
    steps: int = 0
    rejected: int = 0
    jac_evals: int = 0
    iterations: int = 0
    energy: np.ndarray | None = None
    energy0: float | None = None
    energy_max_dev: float | None = None
    details: dict = field(default_factory=dict)
    # integrate's `quadrature`: W(t) = the integral of its integrand along the run, at the samples
    # t (and work_final at t_final), integrated inside the run as one more state; None without
    work: np.ndarray | None = None
    work_final: float | None = None

    @property
    def ok(self) -> bool:
        return self.status == "completed"
