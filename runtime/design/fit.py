"""Fitting scene keys to measurements: weighted least squares with exact Jacobians (thesis 3.3).

    minimise  sum_i ((q_i(x) - value_i) / sigma_i)^2    over scene keys x in a box

Each row of the data (CSV: quantity, value, sigma[, overrides]) is one measured quantity of the
scene with optional overrides of other keys (e.g. the height measured for each of several masses:
`top.mass=0.05`). A quantity is one of QUANTITIES, evaluated by the CasADi Functions of
runtime/physics/stability_casadi.py started from the exact float routes at the current x; its exact
derivative is d q / d p (implicit function theorem) times d p / d x (runtime/design/scene_keys.py).
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

from runtime.physics import stability_casadi as sc
from runtime.errors import UserError
from runtime.design.scene_keys import KeyMap, Vary, key_value, with_values
from runtime.ui.validate import real

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


COLUMNS = ("quantity", "value", "sigma", "overrides")
MIN_SIGMA = 1e-150      # the weighted residuals (value / sigma) are squared: stay in double range
MAX_ROWS = 10_000


def check_row(row, where: str) -> Row:
    """The one check of a measurement, for CSV rows (read_rows) and the API's Row lists (fit):
    a known quantity, a finite value, a finite sigma >= MIN_SIGMA, overrides of distinct scene keys
    to finite numbers."""
    if not isinstance(row, Row):
        raise UserError(f"{where}: {row!r} is not a runtime.design.fit.Row (quantity, value, sigma, overrides)")
    if row.quantity not in QUANTITIES:
        raise UserError(f"{where}: quantity {row.quantity!r}: use one of {', '.join(QUANTITIES)}")
    value = real(row.value, f"{where}: value")
    sigma = real(row.sigma, f"{where}: sigma", positive=True)
    if sigma < MIN_SIGMA or abs(value) / sigma > 1 / MIN_SIGMA:
        raise UserError(f"{where}: sigma = {sigma:g} is too small for value {value:g} (the squared "
                        f"residuals would leave double range): give sigma >= {MIN_SIGMA:g} and "
                        f"|value| / sigma <= {1 / MIN_SIGMA:g}")
    over, seen = [], set()
    for item in row.overrides:
        if not (isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str)):
            raise UserError(f"{where}: override {item!r}: give (scene key, number) pairs")
        key = item[0].strip()
        if key in seen:
            raise UserError(f"{where}: the override {key} is given twice: give each key once")
        seen.add(key)
        over.append((key, real(item[1], f"{where}: override {key}")))
    return Row(row.quantity, value, sigma, tuple(over))


def check_rows(rows, where: str = "--fit") -> list[Row]:
    """check_row of every row; at least one row, at most MAX_ROWS."""
    if isinstance(rows, (str, bytes)) or not hasattr(rows, "__iter__"):
        raise UserError(f"{where}: give a CSV path or a list of runtime.design.fit.Row")
    rows = list(rows)
    if not rows:
        raise UserError(f"{where}: no data rows")
    if len(rows) > MAX_ROWS:
        raise UserError(f"{where}: {len(rows)} rows is too many (at most {MAX_ROWS})")
    return [check_row(r, f"{where} row {i + 1}") for i, r in enumerate(rows)]


def read_rows(path: str | Path) -> list[Row]:
    """The rows of a CSV file with header quantity,value,sigma[,overrides]; overrides are
    `key=value` pairs separated by ';'. UserError naming the line on any problem: an unknown or
    repeated column, a line with more fields than the header, a key overridden twice."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise UserError(f"--fit {path}: cannot be read ({exc}): give a CSV file") from None
    lines = [(n, line) for n, line in enumerate(text.splitlines(), start=1)
             if line.strip() and not line.lstrip().startswith("#")]
    try:
        table = list(csv.reader(line for _, line in lines))
    except csv.Error as exc:
        raise UserError(f"--fit {path}: not a CSV file ({exc})") from None
    header = [h.strip() for h in table[0]] if table else []
    if not {"quantity", "value", "sigma"} <= set(header):
        raise UserError(f"--fit {path}: the header must name quantity,value,sigma[,overrides]")
    unknown = [h for h in header if h not in COLUMNS]
    if unknown:
        raise UserError(f"--fit {path}: unknown column {unknown[0]!r}: the columns are "
                        f"{','.join(COLUMNS)} (put per-row scene keys into overrides: key=value;...)")
    repeated = sorted({h for h in header if header.count(h) > 1})
    if repeated:
        raise UserError(f"--fit {path}: the column {repeated[0]!r} appears twice in the header")
    rows = []
    for (n, _), fields in zip(lines[1:], table[1:]):
        if len(fields) > len(header):
            raise UserError(f"--fit {path} line {n}: {len(fields)} fields for {len(header)} columns: "
                            "remove the extra ones (a ',' inside overrides? separate them by ';')")
        rec = dict(zip(header, (f.strip() for f in fields)))
        try:
            value, sigma = float(rec.get("value", "")), float(rec.get("sigma", ""))
        except ValueError:
            raise UserError(f"--fit {path} line {n}: value and sigma must be numbers") from None
        over = []
        for item in filter(None, (s.strip() for s in rec.get("overrides", "").split(";"))):
            key, eq, v = item.partition("=")
            try:
                if not eq:
                    raise ValueError(item)
                over.append((key.strip(), float(v)))
            except ValueError:
                raise UserError(f"--fit {path} line {n}: override {item!r}: write key=number") from None
        rows.append(check_row(Row(rec.get("quantity", ""), value, sigma, tuple(over)),
                              f"--fit {path} line {n}"))
    return check_rows(rows, f"--fit {path}")


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
        """(model values, weighted residuals, weighted Jacobian d r / d log x). Rows with the same
        overrides share one parameter vector: its starts, values and each quantity's Jacobian are
        computed once per evaluation (1000 rows at a few masses cost a few rows)."""
        vals, res, jac = [], [], []
        sites: dict = {}          # overrides -> (p, starts, values, {quantity: d q / d p})
        for i, r in enumerate(self.rows):
            km = self.maps[r.overrides]
            if r.overrides not in sites:
                _, p = km.exact(x)
                st = sc.starts(self.model, p)
                sites[r.overrides] = (p, st, self.cs.values(p, st), {})
            p, st, v, jacs = sites[r.overrides]
            if r.quantity not in v:
                raise UserError(f"--fit: at {km.describe(x)} row {i + 1} ({r.quantity}) does not "
                                "exist (no stable hover or spin interval there): narrow the --vary "
                                "bounds or check the data")
            if r.quantity not in jacs:
                jacs[r.quantity] = self.cs.jacobian(r.quantity, p, st)
            dqdp = jacs[r.quantity]
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
    rows = check_rows(rows)
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
