"""Fitting with CasADi on the generated functions (casadi rootfinder, thesis eq. 3.3.2).

`fit_equilibrium_height` answers the question the thesis leaves open: its plate's strength is not
given, only the equilibrium heights (thesis 3.3: 7.62 cm and 15.68 cm). Solve
m g + mu Phi_2(z*; p) = 0 (thesis eq. 3.3.2) for one parameter (by default the top's moment mu, so
that the product mu*strength is fitted) with a Newton rootfinder on the generated CasADi `onaxis`
function, whose derivatives CasADi supplies by automatic differentiation.
"""
from __future__ import annotations

import casadi as ca
import numpy as np

from .errors import UserError


def fit_equilibrium_height(model, z_star: float, param: str = "mu") -> dict:
    """The value of `param` for which the top hovers at z_star: m g + mu Phi_2(z_star) = 0."""
    names = list(model.manifest["parameters"])
    if param not in names:
        raise UserError(f"--param {param!r} is not a parameter of this model: use one of {names}")
    if not z_star > 0:
        raise UserError(f"--fit-height {z_star} must be a positive height (m) above the plate")
    i = names.index(param)
    onaxis = model.casadi("onaxis")
    x = ca.SX.sym(param)
    p = ca.vertcat(*[x if j == i else ca.SX(float(v)) for j, v in enumerate(model.p)])
    mass, g, mu = (p[names.index(n)] for n in ("m", "g", "mu"))
    residual = mass * g + mu * onaxis(ca.SX(z_star), p)[2]           # thesis eq. 3.3.2
    F = ca.Function("equilibrium_residual", [x], [residual])
    solver = ca.rootfinder("fit", "newton", F, {"abstol": 1e-14, "max_iter": 50})
    x0 = float(model.p[i]) if model.p[i] != 0 else 1.0
    value = float(solver(x0))
    res = float(F(value))
    scale = float(model.p[names.index("m")] * model.p[names.index("g")])
    ok = bool(np.isfinite(value) and abs(res) <= 1e-10 * scale)
    out = {"objective": "m g + mu Phi_2(z*) = 0 (thesis eq. 3.3.2)", "z_star": z_star,
           "optimum": {param: value}, "residual_N": res,
           "solver_status": "converged" if ok else "failed",
           "stats": {"solver": "casadi rootfinder newton", **{k: v for k, v in solver.stats().items()
                                                              if isinstance(v, (int, float, bool, str))}}}
    if "plate_rho" in names:
        rho = value if param == "plate_rho" else float(model.p[names.index("plate_rho")])
        mu_v = value if param == "mu" else float(model.p[names.index("mu")])
        out["optimum"]["murho"] = mu_v * rho
    return out
