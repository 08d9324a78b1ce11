"""Fitting scene keys to measurements: weighted least squares with exact Jacobians (thesis 3.3).

    minimise  sum_i ((q_i(x) - value_i) / sigma_i)^2    over scene keys x in a box

Each row of the data (CSV: quantity, value, sigma[, overrides]) is one measured quantity of the
scene with optional overrides of other keys (e.g. the height measured for each of several masses:
`top.mass=0.05`). A quantity is one of QUANTITIES, evaluated by the CasADi Functions of
runtime/stability_casadi.py started from the exact float routes at the current x; its exact
derivative is d q / d p (implicit function theorem) times d p / d x (runtime/scene_keys.py).
Gauss-Newton with Levenberg-Marquardt damping, in the keys scaled to their box. Standard errors
from the Jacobian at the optimum, cov = (J^T J)^-1 (J weighted by 1/sigma). A rank-deficient
Jacobian (relative singular value below RANK_RTOL, with the keys on a log scale) is refused,
naming the keys the data cannot separate: e.g. heights alone fix only mu x strength (thesis 2.2:
only mu rho enters the dynamics).
"""
from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import stability_casadi as sc
from .errors import UserError
from .scene_keys import KeyMap, Vary, key_value, with_values

QUANTITIES = {"z_s": "m", "stiffness": "N/m", "sigma_lo": "rad/s", "sigma_hi": "rad/s",
              "z_c": "m", "max_mass": "kg"}
RANK_RTOL = 1e-8
MAX_ITER = 60
POOR_P = 1e-3        # a fit is poor when P(chi2_dof >= chi2) < POOR_P
POOR_SIGMA = 3.0     # ... or, with no degree of freedom left, a residual beyond 3 sigma


@dataclass(frozen=True)
class Row:
    """One measurement: quantity (QUANTITIES, SI unit), value, sigma (its standard deviation),
    overrides (scene key -> value for this row)."""

    quantity: str
    value: float
    sigma: float
    overrides: tuple[tuple[str, float], ...] = ()


def read_rows(path: str | Path) -> list[Row]:
    """The rows of a CSV file with header quantity,value,sigma[,overrides]; overrides are
    `key=value` pairs separated by ';'. UserError naming the line on any problem."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise UserError(f"--fit {path}: cannot be read ({exc}): give a CSV file") from None
    reader = csv.DictReader(line for line in text.splitlines() if line.strip()
                            and not line.lstrip().startswith("#"))
    need = {"quantity", "value", "sigma"}
    if reader.fieldnames is None or not need <= {f.strip() for f in reader.fieldnames}:
        raise UserError(f"--fit {path}: the header must name quantity,value,sigma[,overrides]")
    rows = []
    for n, rec in enumerate(reader, start=2):
        rec = {k.strip(): (v or "").strip() for k, v in rec.items() if k}
        q = rec["quantity"]
        if q not in QUANTITIES:
            raise UserError(f"--fit {path} line {n}: quantity {q!r}: use one of {', '.join(QUANTITIES)}")
        try:
            value, sigma = float(rec["value"]), float(rec["sigma"])
        except ValueError:
            raise UserError(f"--fit {path} line {n}: value and sigma must be numbers") from None
        if not (math.isfinite(value) and math.isfinite(sigma) and sigma > 0):
            raise UserError(f"--fit {path} line {n}: value must be finite and sigma > 0")
        over = []
        for item in filter(None, (s.strip() for s in rec.get("overrides", "").split(";"))):
            key, _, v = item.partition("=")
            try:
                over.append((key.strip(), float(v)))
            except ValueError:
                raise UserError(f"--fit {path} line {n}: override {item!r}: write key=number") from None
        rows.append(Row(q, value, sigma, tuple(over)))
    if not rows:
        raise UserError(f"--fit {path}: no data rows")
    return rows


@dataclass
class FitResult:
    """A least-squares fit (docs/contract.md `optimize`, fits).

    parameters: scene key -> {value, stderr, at_bound} (the key's unit); residuals: per row
    {quantity, value, model, sigma, normalized = (model - value) / sigma}; chi2 = sum normalized^2
    with dof = rows - keys; iterations of Gauss-Newton; solver_status; covariance (the keys'
    units squared, order `keys`) = diag(x) (J^T J)^-1 diag(x) of the weighted Jacobian in log x,
    correlation its normalised form; warnings: plain sentences (a key at its --vary bound, a poor
    fit: p-value below POOR_P, or with dof = 0 a residual beyond POOR_SIGMA)."""

    parameters: dict[str, dict[str, float]]
    residuals: list[dict]
    chi2: float
    dof: int
    iterations: int
    solver_status: str
    start: dict[str, float]
    covariance: np.ndarray | None = None
    warnings: list[str] = field(default_factory=list)

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
        return (f"FitResult({keys}, chi2={self.chi2:.4g}, dof={self.dof}, success={self.success}, "
                f"warnings={len(self.warnings)})")

    def as_dict(self) -> dict:
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
                                         "float routes at the optimum (each row's start)"}}


class _Problem:
    """Residuals and Jacobian of the rows at x (module docstring)."""

    def __init__(self, model, rows: Sequence[Row], varies: Sequence[Vary]):
        self.model, self.rows, self.varies = model, list(rows), list(varies)
        self.cs = sc.CasadiStability(model)
        keys = {v.key for v in varies}
        self.maps = {}
        for r in self.rows:
            bad = [k for k, _ in r.overrides if k in keys]
            if bad:
                raise UserError(f"--fit: a row overrides the varied key {bad[0]}: vary it or fix it")
            if r.overrides not in self.maps:
                scene = with_values(model.scene, dict(r.overrides))
                self.maps[r.overrides] = KeyMap(scene, model.param_names, varies)

    def evaluate(self, x) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(model values, weighted residuals, weighted Jacobian d r / d log x)."""
        vals, res, jac = [], [], []
        for i, r in enumerate(self.rows):
            km = self.maps[r.overrides]
            _, p = km.exact(x)
            st = sc.starts(self.model, p)
            v = self.cs.values(p, st)
            if r.quantity not in v:
                raise UserError(f"--fit: at {km.describe(x)} row {i + 1} ({r.quantity}) does not "
                                "exist (no stable hover or spin interval there): narrow the --vary "
                                "bounds or check the data")
            dqdp = self.cs.jacobian(r.quantity, p, st)
            dpdlogx = p[:, None] * km.E            # d p_j / d log x_k (monomial law)
            vals.append(v[r.quantity])
            res.append((v[r.quantity] - r.value) / r.sigma)
            jac.append(dqdp @ dpdlogx / r.sigma)
        return np.array(vals), np.array(res), np.array(jac)


def _confounded(J: np.ndarray, keys: list[str]) -> str | None:
    """None if J (columns: d r / d log x_k) has full column rank, else a message naming the keys."""
    if J.shape[0] < J.shape[1]:
        return (f"{J.shape[0]} data rows cannot determine {J.shape[1]} keys ({', '.join(keys)}): "
                "add rows or vary fewer keys")
    norms = np.linalg.norm(J, axis=0)
    for k, n in enumerate(norms):
        if n == 0:
            return f"the data do not depend on {keys[k]} at all: fix it (do not vary it)"
    _, s, Vt = np.linalg.svd(J / norms, full_matrices=False)
    if s[-1] > RANK_RTOL * s[0]:
        return None
    v = Vt[-1]
    v = v / np.max(np.abs(v))
    idx = [k for k in range(len(keys)) if abs(v[k]) > 0.05]
    scaling = " and ".join(f"{keys[k]} by e^({v[k]:+.3g} t)" for k in idx)
    return (f"the data cannot separate {', '.join(keys[k] for k in idx)}: scaling {scaling} leaves "
            "every residual unchanged, so only a combination is identified (e.g. mu x strength "
            "from heights alone, thesis 2.2); fix one of them or add data that tell them apart")


def fit(model, rows: Sequence[Row], varies: Sequence[Vary]) -> FitResult:
    """Least squares over the varied keys (module docstring), from the scene's values."""
    if not varies:
        raise UserError("--fit needs at least one --vary KEY=LO:HI")
    prob = _Problem(model, rows, varies)
    keys = [v.key for v in varies]
    lo, hi = np.array([v.lo for v in varies]), np.array([v.hi for v in varies])
    x = np.array([key_value(model.scene.data, k) for k in keys])
    x = np.where((x >= lo) & (x <= hi), x, 0.5 * (lo + hi))
    start = dict(zip(keys, map(float, x)))
    vals, r, J = prob.evaluate(x)
    why = _confounded(J, keys)
    if why is not None:
        raise UserError(f"--fit refused: {why}")
    lam, status, it = 1e-3, "max_iter", 0
    cost = float(r @ r)
    for it in range(1, MAX_ITER + 1):  # noqa: B007 (it: the iteration count reported)
        H, g = J.T @ J, J.T @ r
        step = -np.linalg.solve(H + lam * np.diag(np.diag(H)), g)       # in log x
        x_new = np.clip(x * np.exp(np.clip(step, -0.5, 0.5)), lo, hi)
        try:
            v_new, r_new, J_new = prob.evaluate(x_new)
            c_new = float(r_new @ r_new)
        except UserError:
            c_new = math.inf
        if c_new <= cost:
            done = cost - c_new <= 1e-14 * max(cost, 1e-300) or \
                np.max(np.abs(np.log(x_new / x))) < 1e-12
            x, vals, r, J, cost = x_new, v_new, r_new, J_new, c_new
            lam = max(lam / 10, 1e-12)
            if done:
                status = "converged"
                break
        else:
            lam *= 10
            if lam > 1e12:
                status = "converged" if np.linalg.norm(J.T @ r) <= 1e-8 * max(1.0, cost) else "stalled"
                break
    if status != "converged":
        raise UserError(f"--fit: Gauss-Newton {status} after {it} iterations at "
                        f"{', '.join(f'{k} = {v:.6g}' for k, v in zip(keys, x))}")
    why = _confounded(J, keys)
    if why is not None:
        raise UserError(f"--fit refused at the optimum: {why}")
    cov_log = np.linalg.inv(J.T @ J)                        # of log x
    stderr = np.abs(x) * np.sqrt(np.diag(cov_log))
    at_bound = [k for k, v, a, b in zip(keys, x, lo, hi) if v in (a, b)]
    warnings = [f"{k} = {v:.6g} is at the {'lower' if v == a else 'upper'} bound of --vary "
                f"{k}={a:.10g}:{b:.10g}: at the bound: widen --vary"
                for k, v, a, b in zip(keys, x, lo, hi) if k in at_bound]
    poor = poor_fit(cost, len(rows) - len(keys), r)
    if poor:
        warnings.append(poor)
    return FitResult(
        parameters={k: {"value": float(v), "stderr": float(s), "at_bound": k in at_bound}
                    for k, v, s in zip(keys, x, stderr)},
        residuals=[{"quantity": row.quantity, "value": row.value, "model": float(m),
                    "sigma": row.sigma, "normalized": float(res),
                    "overrides": dict(row.overrides)} for row, m, res in zip(rows, vals, r)],
        chi2=cost, dof=len(rows) - len(keys), iterations=it, solver_status=status, start=start,
        covariance=cov_log * np.outer(x, x), warnings=warnings)


def poor_fit(chi2: float, dof: int, normalized) -> str | None:
    """"the fit is poor: ..." when the data are not reproduced within their sigmas: P(chi2_dof >=
    chi2) < POOR_P, or (dof = 0: an exact fit was possible) a residual beyond POOR_SIGMA."""
    worst = float(np.max(np.abs(normalized))) if len(normalized) else 0.0
    if dof > 0:
        from scipy.stats import chi2 as chi2_dist
        p = float(chi2_dist.sf(chi2, dof))
        if p >= POOR_P:
            return None
        return (f"the fit is poor: chi2/dof = {chi2 / dof:.4g} (p = {p:.2g}), largest residual "
                f"{worst:.3g} sigma: check the data, their sigmas and the --vary bounds")
    if worst <= POOR_SIGMA:
        return None
    return (f"the fit is poor: chi2 = {chi2:.4g} with 0 degrees of freedom (the keys could match every "
            f"row), largest residual {worst:.3g} sigma: check the data and the --vary bounds")
