"""The answer to "which scene keys reproduce these measurements?": `Fit`, one type for every face
(`optimize --fit DATA.csv --json` is its `as_json()`, `Study.fit` returns it; docs/contract.md
`optimize`, fits; thesis 3.3 for the quantities). runtime/design/fit.py computes it.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from levitron.runtime.design.launch_design_answer import warning_lines
from levitron.runtime.ui.answer_lines import as_written, keep_said, worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plain_text import NOTHING_SAID


def fit_lines(r: dict, u: Units) -> list[str]:
    """The plain view of a fit's JSON: the fitted keys with their standard errors, chi2 and the
    largest residual, the solver, the warnings."""
    fitted = ", ".join(f"{k} = {sig(v['value'], 6)} +- {sig(v['stderr'], 2)}" for k, v in r["parameters"].items())
    worst = max((abs(x.get("normalized", 0.0)) for x in r.get("residuals") or []), default=None)
    return [f"fit: {fitted}",
            f"chi2 {sig(r['objective'], 4)} with {r['dof']} degrees of freedom"
            + (f"; largest residual {sig(worst, 3)} sigma" if worst is not None else ""),
            f"solver: {r['solver_status']}, {r['iterations']} iterations", *warning_lines(r), u.note]


@dataclass(repr=False)
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
    units: Units = field(default=Units(si=True), repr=False, compare=False)   # the scene's: how lines show numbers
    said: Mapping = field(default_factory=lambda: NOTHING_SAID, repr=False, compare=False)  # warnings as written

    def __post_init__(self) -> None:
        keep_said(self, warnings=self.warnings)

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
    def status_message(self) -> str:
        """scipy-style, the JSON's `message`: how Gauss-Newton ended, chi2, then every warning."""
        return "; ".join([f"Gauss-Newton {self.solver_status} in {self.iterations} iterations: chi2 "
                          f"{self.chi2:.4g} with {self.dof} degrees of freedom", *self.warnings])

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (fit_lines of as_json: the one wording of every face), in `units` (a
        fit's keys are the scene's own numbers; default SI), worded for `face` (None: markers kept)."""
        u = units or self.units
        return worded(fit_lines(as_written(self.as_json(), self.said, self.units), u), u, face)

    @property
    def message(self) -> str:
        return "; ".join(self.lines())

    def __repr__(self) -> str:
        return text_repr("Fit", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table("Fit", self.lines())

    def as_json(self) -> dict:
        """docs/contract.md's `optimize --fit --json` (SI)."""
        cov, cor = self.covariance, self.correlation
        return {"objective": self.chi2, "objective_name": "chi2",
                "success": self.success, "message": self.status_message, "warnings": self.warnings,
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
