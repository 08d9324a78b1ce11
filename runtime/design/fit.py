"""Fitting scene keys to measurements: weighted least squares with exact Jacobians (thesis 3.3).

    minimise  sum_i ((q_i(x) - value_i) / sigma_i)^2    over scene keys x in a box

Each row of the data (CSV: quantity, value, sigma[, overrides]) is one measured quantity of the
scene with optional overrides of other keys (e.g. the height measured for each of several masses:
`top.mass=0.05`). A quantity is one of QUANTITIES, evaluated by the CasADi Functions of
runtime/physics/stability/differentiable.py started from the exact float routes at the current x; its exact
derivative is d q / d p (implicit function theorem) times d p / d x (runtime/design/scene_keys.py).
Gauss-Newton with Levenberg-Marquardt damping, in the keys scaled to their box. Standard errors
from the Jacobian at the optimum, cov = (J^T J)^-1 (J weighted by 1/sigma). A rank-deficient
Jacobian (relative singular value below RANK_RTOL, with the keys on a log scale) is refused,
naming the keys the data cannot separate: e.g. heights alone fix only mu x strength (thesis 2.2:
only mu rho enters the dynamics).
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from levitron.runtime.physics.stability import differentiable as diffable
from levitron.runtime.errors import UserError
from levitron.runtime.design.fit_answer import Fit, FitResult  # noqa: F401 (FitResult: its old name)
from levitron.runtime.design.scene_keys import KeyMap, Vary, key_value, with_values
from levitron.runtime.ui import progress
from levitron.runtime.ui.human import Units
from levitron.runtime.design.measurements import Row, check_rows

RANK_RTOL = 1e-8
MAX_ITER = 60
POOR_P = 1e-3        # a fit is poor when P(chi2_dof >= chi2) < POOR_P
POOR_SIGMA = 3.0     # ... or, with no degree of freedom left, a residual beyond 3 sigma


# the CasADi Function (runtime/physics/stability/differentiable.py FUNCTIONS) that gives each quantity
FUNCTION_OF = {"z_s": "z_s", "stiffness": "z_s", "z_c": "z_c", "max_mass": "z_c",
               "sigma_lo": "spin", "sigma_hi": "spin"}
WARM_RESIDUAL = 1e-10   # a warm Newton is accepted when its normalised residual is below this
WARM_RTOL = 1e-9        # ... and the warm fit when the cold routes agree with it at the optimum
PREDICTED = 0.1         # ... and lands within this fraction of its predicted change of the prediction
PROGRESS_SITES = 20     # float-route starts for more sites than this show a progress bar


class _Problem:
    """Residuals and Jacobian of the rows at x (module docstring).

    Rows with the same overrides share one site: one parameter vector, whose quantities come from
    one column of a mapped CasADi Function (`CasadiStability.batch`: every site in one call). The
    rootfinders start from the exact float routes (cold) at the first evaluation, and then from
    the roots at the last accepted x moved to first order (warm, `accept`), which costs a Newton
    step instead of a float-route survey. A warm root whose residual or sign is off, or that lands
    farther from the prediction than PREDICTED of the predicted change (another branch: a critical
    spin that jumped to the cubic's third root), is restarted cold; `fit` checks the warm optimum
    against a cold evaluation (`evaluate(x, cold=True)`)."""

    def __init__(self, model, rows: Sequence[Row], varies: Sequence[Vary]):
        self.model, self.rows, self.varies = model, list(rows), list(varies)
        self.cs = diffable.CasadiStability(model)
        keys = {v.key for v in varies}
        self.maps = {}
        for r in self.rows:
            bad = [k for k, _ in r.overrides if k in keys]
            if bad:
                raise UserError(f"«fit»: a row overrides the varied key {bad[0]}: vary it or fix it")
            if r.overrides not in self.maps:
                scene = with_values(model.scene, dict(r.overrides))
                self.maps[r.overrides] = KeyMap(scene, model.param_names, varies)
        self.sites = list(self.maps)
        index = {s: j for j, s in enumerate(self.sites)}
        self.site_of = [index[r.overrides] for r in self.rows]
        self.needs: dict[str, list[int]] = {}
        for r, j in zip(self.rows, self.site_of):
            self.needs.setdefault(FUNCTION_OF[r.quantity], set()).add(j)
        if "spin" in self.needs:            # the spins' starts come from the hover height
            self.needs.setdefault("z_s", set()).update(self.needs["spin"])
        self.needs = {name: sorted(js) for name, js in self.needs.items()}
        self.use_warm = True
        self.warm: dict = {}          # (function, site) -> roots at the last accepted x
        self._pending: dict = {}

    def accept(self) -> None:
        """The last evaluation's x is accepted: its roots start the next evaluation."""
        self.warm.update(self._pending)

    def _run(self, name: str, js: list[int], guesses, P):
        """(outputs (n_out x len(js)), d outputs / d p (n_out x len(p) x len(js)), residuals) of
        Function `name` at sites js from the guesses (one list per site), in one CasADi call."""
        F = self.cs.batch(name, len(js))
        G = np.array(guesses, float).T
        out = F(*[G[i:i + 1] for i in range(G.shape[0])], P[:, js])
        n = self.cs.functions[name].n_out()
        Y = np.vstack([np.asarray(out[i], float).reshape(1, -1) for i in range(n)])
        D = np.stack([np.asarray(out[n + i], float) for i in range(n)])
        return Y, D, np.asarray(out[2 * n], float).reshape(-1)

    def _predict(self, name: str, j: int, p) -> np.ndarray:
        """The roots at p to first order from those at the last accepted x (their d / d p)."""
        roots, droots, p_last = self.warm[name, j]
        return roots + droots @ (p - p_last)

    @staticmethod
    def _warm_ok(name: str, Y, R) -> np.ndarray:
        """Per site: the warm Newton converged (finite, residual below WARM_RESIDUAL) to a root of
        the kind the float routes give: a stable hover (stiffness > 0), 0 < sigma_lo < sigma_hi,
        z_c > 0."""
        ok = np.all(np.isfinite(Y), axis=0) & (R <= WARM_RESIDUAL)
        if name == "z_s":
            ok &= (Y[0] > 0) & (Y[1] > 0)
        elif name == "spin":
            ok &= (Y[0] > 0) & (0 < Y[1]) & (Y[1] < Y[2])
        else:
            ok &= Y[0] > 0
        return ok

    def evaluate(self, x, cold: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(model values, weighted residuals, weighted Jacobian d r / d log x); cold: every
        rootfinder started from the float routes (as at the first evaluation)."""
        kms = [self.maps[s] for s in self.sites]
        P = np.array([km.exact(x)[1] for km in kms]).T          # len(p) x sites
        starts: dict[int, diffable.Starts] = {}
        results, missing, self._pending = {}, set(), {}
        hover: dict[int, float] = {}       # site -> z_s from a warm root this evaluation
        for name in ("z_s", "z_c", "spin"):
            js = self.needs.get(name)
            if not js:
                continue
            F = self.cs.functions[name]
            k = F.n_in() - 1
            Y = np.full((F.n_out(), len(self.sites)), np.nan)
            D = np.full((F.n_out(), P.shape[0], len(self.sites)), np.nan)
            warm = [] if cold or not self.use_warm or name == "spin" else \
                [j for j in js if (name, j) in self.warm]
            if warm:
                pred = np.array([self._predict(name, j, P[:, j]) for j in warm]).T
                Yw, Dw, Rw = self._run(name, warm, list(np.where(pred > 0, pred, np.array(
                    [self.warm[name, j][0] for j in warm]).T).T), P)
                ok = self._warm_ok(name, Yw, Rw)
                last = np.array([self.warm[name, j][0] for j in warm]).T
                ok &= np.all(np.abs(Yw[:k] - pred) <= PREDICTED * np.abs(pred - last)
                             + WARM_RTOL * np.abs(pred), axis=0)
                good = [j for j, o in zip(warm, ok) if o]
                Y[:, good], D[:, :, good] = Yw[:, ok], Dw[:, :, ok]
                warm = good
                if name == "z_s":
                    hover.update({j: float(Y[0, j]) for j in good})
            todo = [j for j in js if j not in set(warm)]
            new = [j for j in todo if j not in starts and not (name == "spin" and j in hover)]
            with progress.task("fit: float-route starts", total=len(new),
                               quiet=len(new) <= PROGRESS_SITES) as tick:
                for j in new:
                    starts[j] = diffable.starts(self.model, P[:, j])
                    tick()
            cold_js, guesses = [], []
            for j in todo:
                # the critical spins: the float route's first bounded interval at the hover
                # height, at a warm z_s too (a warm spin root could follow another interval)
                g = diffable.guesses(name, starts[j]) if j in starts else \
                    diffable.spin_guesses(self.model, P[:, j], hover[j])
                if g is None:
                    missing.add((name, j))
                else:
                    cold_js.append(j)
                    guesses.append(g)
            if cold_js:
                Yc, Dc, _ = self._run(name, cold_js, guesses, P)
                Y[:, cold_js], D[:, :, cold_js] = Yc, Dc
            for j in js:
                if (name, j) not in missing:
                    self._pending[name, j] = (Y[:k, j].copy(), D[:k, :, j].copy(), P[:, j].copy())
            results[name] = (F, Y, D)
        vals, res, jac = [], [], []
        for i, (r, j) in enumerate(zip(self.rows, self.site_of)):
            name = FUNCTION_OF[r.quantity]
            if (name, j) in missing:
                raise UserError(f"«fit»: at {kms[j].describe(x)} row {i + 1} ({r.quantity}) does "
                                "not exist (no stable hover or spin interval there): narrow the "
                                "«vary» bounds or check the data")
            F, Y, D = results[name]
            o = F.index_out(r.quantity)
            dpdlogx = P[:, j][:, None] * kms[j].E                # d p_j / d log x_k (monomial law)
            vals.append(Y[o, j])
            res.append((Y[o, j] - r.value) / r.sigma)
            jac.append(D[o, :, j] @ dpdlogx / r.sigma)
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


def _gauss_newton(prob: _Problem, x, lo, hi, keys):
    """Levenberg-Marquardt in log x from x: (x, values, r, J, cost, iterations)."""
    vals, r, J = prob.evaluate(x)
    prob.accept()
    why = _confounded(J, keys)
    if why is not None:
        raise UserError(f"«fit» refused: {why}")
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
            prob.accept()
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
        raise UserError(f"«fit»: Gauss-Newton {status} after {it} iterations at "
                        f"{', '.join(f'{k} = {v:.6g}' for k, v in zip(keys, x))}: check the data's "
                        "values and units, or start nearer (set the keys in the scene) or "
                        "narrow the «vary» box")
    return x, vals, r, J, cost, it


def fit(model, rows: Sequence[Row], varies: Sequence[Vary]) -> Fit:
    """Least squares over the varied keys (module docstring), from the scene's values. The
    iterations start their rootfinders warm (`_Problem`); the optimum is checked by a cold
    evaluation there, and a disagreement beyond WARM_RTOL reruns the fit cold throughout."""
    if not varies:
        raise UserError("«fit» needs at least one «vary» KEY=LO:HI")
    rows = check_rows(rows)
    prob = _Problem(model, rows, varies)
    keys = [v.key for v in varies]
    lo, hi = np.array([v.lo for v in varies]), np.array([v.hi for v in varies])
    x = np.array([key_value(model.scene.data, k) for k in keys])
    x = np.where((x >= lo) & (x <= hi), x, 0.5 * (lo + hi))
    start = dict(zip(keys, map(float, x)))
    x0 = x
    x, vals, r, J, cost, it = _gauss_newton(prob, x0, lo, hi, keys)
    try:
        checked = prob.evaluate(x, cold=True)
    except UserError:
        checked = None
    if checked is not None and np.allclose(checked[0], vals, rtol=WARM_RTOL, atol=0) \
            and np.allclose(checked[2], J, rtol=1e-6, atol=1e-9 * np.max(np.abs(J))):
        vals, r, J = checked
        cost = float(r @ r)
    else:
        prob.use_warm = False
        x, vals, r, J, cost, it = _gauss_newton(prob, x0, lo, hi, keys)
    status = "converged"
    why = _confounded(J, keys)
    if why is not None:
        raise UserError(f"«fit» refused at the optimum: {why}")
    cov_log = np.linalg.inv(J.T @ J)                        # of log x
    stderr = np.abs(x) * np.sqrt(np.diag(cov_log))
    at_bound = [k for k, v, a, b in zip(keys, x, lo, hi) if v in (a, b)]
    warnings = [f"{k} = {v:.6g} is at the {'lower' if v == a else 'upper'} bound of «vary» "
                f"{k}={a:.10g}:{b:.10g}: at the bound: widen «vary»"
                for k, v, a, b in zip(keys, x, lo, hi) if k in at_bound]
    poor = poor_fit(cost, len(rows) - len(keys), r)
    if poor:
        warnings.append(poor)
    return Fit(
        parameters={k: {"value": float(v), "stderr": float(s), "at_bound": k in at_bound}
                    for k, v, s in zip(keys, x, stderr)},
        residuals=[{"quantity": row.quantity, "value": row.value, "model": float(m),
                    "sigma": row.sigma, "normalized": float(res),
                    "overrides": dict(row.overrides)} for row, m, res in zip(rows, vals, r)],
        chi2=cost, dof=len(rows) - len(keys), iterations=it, solver_status=status, start=start,
        covariance=cov_log * np.outer(x, x), warnings=warnings, scene=model.scene.name,
        units=Units.of_scene(model.scene))


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
                f"{worst:.3g} sigma: check the data, their sigmas and the «vary» bounds")
    if worst <= POOR_SIGMA:
        return None
    return (f"the fit is poor: chi2 = {chi2:.4g} with 0 degrees of freedom (the keys could match every "
            f"row), largest residual {worst:.3g} sigma: check the data and the «vary» bounds")
