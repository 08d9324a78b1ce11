"""The answer to "which scene keys reproduce these measurements?": `Fit`, one type for every face
(`optimize --fit DATA.csv --json` is its `as_json()`, `Study.fit` returns it; docs/contract.md
`optimize`, fits; thesis 3.3 for the quantities). runtime/design/fit.py computes it.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Fit:
    """A least-squares fit (docs/contract.md `optimize`, fits).

    parameters: scene key -> {value, stderr, at_bound} (the key's unit); residuals: per row
    {quantity, value, model, sigma, normalized = (model - value) / sigma}; chi2 = sum normalized^2
    with dof = rows - keys; iterations of Gauss-Newton; solver_status; covariance (the keys'
    units squared, order `keys`) = diag(x) (J^T J)^-1 diag(x) of the weighted Jacobian in log x,
    correlation its normalised form; warnings: plain sentences (a key at its --vary bound, a poor
    fit: p-value below fit.POOR_P, or with dof = 0 a residual beyond fit.POOR_SIGMA); scene: its name."""

    parameters: dict[str, dict[str, float]]
    residuals: list[dict]
    chi2: float
    dof: int
    iterations: int
    solver_status: str
    start: dict[str, float]
    covariance: np.ndarray | None = None
    warnings: list[str] = field(default_factory=list)
    scene: str = ""

    @property
    def keys(self) -> list[str]:
        return list(self.parameters)

    @property
    def correlation(self) -> np.ndarray | None:
        if self.covariance is None:
            return None
        d = np.sqrt(np.diag(self.covariance))
        return self.covariance / np.outer(d, d)

    @property
    def success(self) -> bool:
        """scipy-style: Gauss-Newton converged (a failure raises a UserError instead)."""
        return self.solver_status == "converged"

    @property
    def message(self) -> str:
        return "; ".join([f"Gauss-Newton {self.solver_status} in {self.iterations} iterations: chi2 "
                          f"{self.chi2:.4g} with {self.dof} degrees of freedom", *self.warnings])

    def __repr__(self) -> str:
        keys = ", ".join(f"{k}={v['value']:.6g}+-{v['stderr']:.2g}" for k, v in self.parameters.items())
        return (f"Fit({keys}, chi2={self.chi2:.4g}, dof={self.dof}, success={self.success}, "
                f"warnings={len(self.warnings)})")

    def as_json(self) -> dict:
        """docs/contract.md's `optimize --fit --json` (SI)."""
        cov, cor = self.covariance, self.correlation
        return {"objective": self.chi2, "objective_name": "chi2",
                "success": self.success, "message": self.message, "warnings": self.warnings,
                "keys": self.keys,
                "covariance": None if cov is None else cov.tolist(),
                "correlation": None if cor is None else cor.tolist(),
                "optimum": {k: v["value"] for k, v in self.parameters.items()},
                "parameters": self.parameters, "residuals": self.residuals, "dof": self.dof,
                "solver_status": self.solver_status, "iterations": self.iterations,
                "start": self.start,
                "verification": {"float_route": self.chi2, "grid_best": None, "grid_points": 0,
                                 "note": "fits are checked by the rank of the Jacobian and the "
                                         "float routes at the optimum (each row's start)"},
                "scene": self.scene}


FitResult = Fit      # its former name, kept for scripts that import it
