"""Fitting with CasADi on the generated functions (casadi rootfinder, thesis eq. 3.3.2).

`fit_equilibrium_height` answers the question the thesis leaves open: its plate's strength is not
given, only the equilibrium heights (thesis 3.3: 7.62 cm and 15.68 cm). Solve
m g + mu Phi_2(z*; p) = 0 (thesis eq. 3.3.2) for one parameter (by default the top's moment mu, so
that the product mu*strength is fitted) with a Newton rootfinder on the generated CasADi `onaxis`
function, whose derivatives CasADi supplies by automatic differentiation. The result is then
checked by the one equilibrium finder (runtime/physics/equilibrium/finder.py): z* must be among the equilibria at
the fitted value, and a value that is not physical (a mass, inertia or length <= 0) is refused.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from levitron.scene import plates

from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.errors import UserError
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.answer_view import html_table, text_repr
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.words import setting, si_unit

# parameters that must be positive
POSITIVE = ("m", "g", "A", "C")


def physical_problem(plate: dict, names: list[str], values: np.ndarray, param: str) -> str | None:
    """Why the fitted parameter vector is not physical, or None: a mass, inertia or g <= 0, a plate
    length < 0 (the plate registry's length keys) or a plate without size, or C > 2 A (no rigid
    body, thesis 2.1.13)."""
    v = float(values[names.index(param)])
    if not math.isfinite(v):
        return f"{param} = {v} is not a number"
    if param in POSITIVE and not v > 0:
        return f"{param} = {v:.6g}, but {param} must be > 0"
    lengths = plates.length_names(plate)
    if param in lengths and v < 0:
        return f"{param} = {v:.6g}, but a length must be >= 0"
    if lengths and param in lengths and not plates.length_scale(plate, dict(zip(names, values))) > 0:
        return f"{param} = {v:.6g} leaves the plate without size"
    A, C = (float(values[names.index(k)]) for k in ("A", "C"))
    if param in ("A", "C") and C > 2 * A:
        return f"{param} = {v:.6g}, but then C = {C:.6g} > 2 A = {2 * A:.6g} (no rigid body)"
    return None


def _key_route(model, key: str):
    """(x0, p(x) as CasADi, p(value) re-resolved) for a scene key (`plate.murho`, `top.moment`,
    `top.mass`): the one scene-key mapping of runtime/design/scene_keys.py (the resolver's own,
    as --vary uses it), on a box of +-0.1 % around the scene's value to measure its powers."""
    from levitron.runtime.design.scene_keys import KeyMap, Vary, key_value
    x0 = key_value(model.scene.data, key)
    if x0 == 0:
        raise UserError(f"«param» {key} = 0 in the scene: fit a key the scene sets to a nonzero number")
    lo, hi = sorted((0.999 * x0, 1.001 * x0))
    km = KeyMap(model.scene, model.param_names, [Vary.checked(key, lo, hi, f"«param» {key}")])
    return x0, (lambda x: km.p_casadi(ca.vertcat(x))), (lambda v: km.exact(np.array([v]))[1])


def _name_route(model, param: str):
    """(x0, p(x) as CasADi, p(value)) for a generated parameter name (`mu`, `plate_rho`)."""
    names = model.param_names
    if param not in names:
        raise UserError(f"«param» {param!r} is not a scene key (section.key, e.g. plate.murho or "
                        f"top.moment) and not a parameter of this model ({', '.join(names)})")
    i = names.index(param)

    def p_of(x):
        return ca.vertcat(*[x if j == i else ca.SX(float(v)) for j, v in enumerate(model.p)])

    def exact(v):
        pv = model.p.copy()
        pv[i] = v
        return pv
    return (float(model.p[i]) if model.p[i] != 0 else 1.0), p_of, exact


def fit_equilibrium_height(model, z_star: float, param: str = "mu") -> HeightFit:
    """The value of `param` for which the top hovers at z_star: m g + mu Phi_2(z_star) = 0.
    param: a scene key as --vary takes it (`plate.murho`, `top.moment`, `plate.remanence`,
    `top.mass`), or a generated parameter's name (`mu`, `plate_rho`; the default mu)."""
    names = model.param_names
    by_key = "." in str(param)
    x0, p_of, exact = _key_route(model, param) if by_key else _name_route(model, param)
    if not (z_star > 0 and math.isfinite(z_star)):
        raise UserError(f"{setting('fit_height', f'{z_star}')} must be a positive height "
                        f"({si_unit('m')}) above the plate")
    onaxis = model.casadi("onaxis")
    x = ca.SX.sym("x")
    p = p_of(x)
    mass, g, mu = (p[names.index(n)] for n in ("m", "g", "mu"))
    residual = mass * g + mu * onaxis(ca.SX(z_star), p)[2]           # thesis eq. 3.3.2
    F = ca.Function("equilibrium_residual", [x], [residual])
    solver = ca.rootfinder("fit", "newton", F, {"abstol": 1e-14, "max_iter": 50,
                                                "error_on_fail": False})
    value = float(solver(x0))
    stats = solver.stats()
    res = float(F(value)) if math.isfinite(value) else math.nan
    scale = float(model.p[names.index("m")] * model.p[names.index("g")])
    if param in ("m", "top.mass"):
        scale = abs(value * float(model.p[names.index("g")]))
    elif param == "g":
        scale = abs(value * float(model.p[names.index("m")]))
    if not (math.isfinite(res) and abs(res) <= 1e-10 * scale):
        raise UserError(f"no value of {param} puts the top at z* = {z_star:g}: the Newton "
                        f"rootfinder from {param} = {x0:.6g} did not converge; fit another "
                        "parameter or height")
    pv = exact(value)       # a scene key: re-resolved and validated (scene/load.py), else UserError
    why = None if by_key else physical_problem(model.scene.data["plate"], names, pv, param)
    if why is not None:
        raise UserError(f"no physical {param} puts the top at z* = {z_star:g}: the fit gives {why}; "
                        "fit another parameter or height")
    rep = eqm.equilibria_of(model, pv)
    found = [e for e in rep.equilibria if abs(e.z - z_star) <= 1e-8 * z_star]
    if not found:
        raise UserError(f"the fitted {param} = {value:.6g} solves m g + mu Phi_2(z*) = 0 but the "
                        f"equilibrium finder finds no equilibrium at z* = {z_star:g} (equilibria: "
                        f"{', '.join(f'{e.z:.6g}' for e in rep.equilibria) or 'none'})")
    murho = (float(pv[names.index("mu")] * pv[names.index("plate_rho")])
             if "plate_rho" in names and param != "plate.murho" else None)
    return HeightFit(z_star, param, value, res, found[0].vertically_stable,
                     [e.as_dict() for e in rep.equilibria],
                     {"solver": "casadi rootfinder newton",
                      **{k: v for k, v in stats.items() if isinstance(v, (int, float, bool, str))}},
                     murho, Units.of_scene(model.scene))


def height_fit_lines(r: dict, u: Units) -> list[str]:
    """The plain view of a height fit's JSON: the fitted value and the equilibrium it puts at z*,
    every equilibrium then, the rootfinder's residual."""
    fit = ", ".join(f"{k} = {sig(v, 6)}" for k, v in r["optimum"].items())
    roots = ", ".join(f"{u.length(e['z'])} ({'vertically stable' if e['vertically_stable'] else 'unstable'})"
                      for e in r.get("equilibria") or [])
    stable = "vertically stable" if r.get("z_star_vertically_stable") else "vertically unstable"
    return [f"fit: {fit} puts an equilibrium at {u.length(r['z_star'])} ({stable})",
            f"equilibria then: {roots}" if roots else "",
            f"solver: {r['solver_status']}, residual {u.value(r['residual_N'], 'N', 2)} ({r['objective']})",
            u.note]


@dataclass(frozen=True, repr=False)
class HeightFit:
    """The answer of `optimize --fit-height Z` and Study.fit_height(): the value of one parameter
    (`param`: a scene key or a generated parameter's name) that puts the top's equilibrium at
    z_star (m; thesis eq. 3.3.2), the residual m g + mu Phi_2(z*) (N) there, whether z* is
    vertically stable, every equilibrium at the fitted value, the rootfinder's stats; `murho`
    (A m^2 T m) the product the plate's field scales with, where the fit did not give it itself.
    `answer["key"]` reads as_json()'s keys (as the dict it was)."""
    z_star: float
    param: str
    value: float
    residual_N: float
    z_star_vertically_stable: bool
    equilibria: list
    stats: dict
    murho: float | None = None
    units: Units = field(default=Units(si=True), compare=False)

    @property
    def success(self) -> bool:
        """scipy-style: the rootfinder converged and z* is an equilibrium (a failure raises instead)."""
        return True

    def lines(self, units: Units | None = None, face: str | None = "api") -> list[str]:
        """The plain view (height_fit_lines of as_json: the one wording of every face), in `units`
        (default the scene's), worded for `face` (None: the markers kept)."""
        u = units or self.units
        return worded(height_fit_lines(self.as_json(), u), u, face)

    @property
    def message(self) -> str:
        return "; ".join(self.lines())

    def __repr__(self) -> str:
        return text_repr("HeightFit", [self.lines()[0], f"success={self.success}"])   # short: the answer first

    def _repr_html_(self) -> str:
        return html_table("Height fit", self.lines())

    def as_json(self) -> dict:
        """docs/contract.md's `optimize --fit-height` object (SI)."""
        optimum = {self.param: self.value, **({"murho": self.murho} if self.murho is not None else {})}
        return {"objective": "m g + mu Phi_2(z*) = 0 (thesis eq. 3.3.2)", "z_star": self.z_star,
                "optimum": optimum, "residual_N": self.residual_N, "solver_status": "converged",
                "z_star_vertically_stable": self.z_star_vertically_stable, "equilibria": self.equilibria,
                "stats": self.stats}

    def __getitem__(self, key: str):
        return self.as_json()[key]
