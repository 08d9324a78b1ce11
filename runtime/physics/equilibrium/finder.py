"""The one equilibrium finder: vertical equilibria, z_c and the largest mass (thesis 3.3.1-3.3.3).

On the invariant set (top on the axis, axis vertical, thesis 3.2.1) the potential is
U(z) = m g z + mu Phi_1(z) (thesis 3.3.1), so the equilibria are the roots of
    F(z) = m g + mu Phi_2(z) = 0   on z > 0          (thesis 3.3.2)
and they are vertically stable where U'' = F' = mu Phi_3(z) > 0 (3.3.3). The hovering mass
m(z) = -mu Phi_2(z)/g is largest at z_c, a zero of Phi_3, and max_mass = m(z_c).

How the roots are found, however close: runtime/physics/equilibrium/root_survey.py (every command uses it).
All lengths scale with `scale_of(model)` (the plate's size), never a fixed number: scenes may be
dimensionless. The heights searched are scale * [1e-4, 1e4]. No sympy here.
"""
from __future__ import annotations

from collections.abc import Callable
from contextlib import contextmanager

import numpy as np

from levitron.scene import plates
from levitron.scene.plates.expression import formulas, z_range

from levitron.runtime.physics.equilibrium import bands as _bands
from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium.report import Equilibrium, EquilibriumReport
from levitron.runtime.physics.equilibrium.root_survey import NonFiniteModel, OnAxis, Survey, survey


# ------------------------------------------------------------------------ model adapters

def params_of(model, p: np.ndarray | None = None) -> dict:
    """{parameter name: value} of a loaded model (p: another parameter vector, manifest order)."""
    return model.pvals(p)


def scale_of(model, p: np.ndarray | None = None) -> float:
    """THE length of a scene every height search scales with: the plate registry's length scale
    (scene.plates.length_scale) at the parameter values p, 1.0 for a plate without lengths."""
    return plates.length_scale(model.scene.data["plate"], params_of(model, p))


def span_of(model) -> tuple[float, float] | None:
    """The heights the scene says its plate's formula holds at (plate.z_range of an expression
    plate, intersected over a compound plate's parts), or None: the whole search (z_grid)."""
    plate = model.scene.data["plate"]
    spans = [s for s in (z_range(t, "plate") for t in [plate, *(plate.get("parts") or [])]) if s]
    if not spans:
        return None
    lo, hi = max(s[0] for s in spans), min(s[1] for s in spans)
    if not lo < hi:
        raise UserError(f"the parts' plate.z_range do not overlap ({spans}): give ranges that share heights")
    return lo, hi


def model_onaxis(model, p: np.ndarray | None = None) -> Callable[[float], np.ndarray]:
    """z -> [Phi_0..Phi_K](z) of a loaded model (its generated `onaxis`, the one ctypes path)."""
    return model.fast("onaxis", p).at


# ------------------------------------------------------------------ convenience and model level

def vertical_equilibria(onaxis: OnAxis, m: float, g: float, mu: float, scale: float) -> list[Equilibrium]:
    """All roots of m g + mu Phi_2(z) = 0 on z > 0 (thesis 3.3.2; the finder of root_survey.py)."""
    return survey(onaxis, scale).equilibria(m, g, mu)


def critical_height(onaxis: OnAxis, g: float, mu: float, scale: float) -> tuple[float | None, float | None]:
    """(z_c, max_mass) of the finder (root_survey.py; thesis 3.3.2-3.3.3)."""
    return survey(onaxis, scale).critical(g, mu)


def hover_mass(onaxis: OnAxis, g: float, mu: float, z: float) -> float:
    """m(z) = -mu Phi_2(z) / g, the mass that hovers at height z (thesis 3.3.2 solved for m)."""
    return -mu * float(onaxis(z)[2]) / g


def analyse(onaxis: OnAxis, m: float, g: float, A: float, C: float, mu: float,
            scale: float, span: tuple[float, float] | None = None) -> EquilibriumReport:
    """Everything of thesis 3.3.1-3.3.3 and the bands (runtime/physics/equilibrium/bands.py) for one top and plate."""
    return _report(survey(onaxis, scale, span), m, g, A, C, mu, bands=True)


def _report(sv: Survey, m: float, g: float, A: float, C: float, mu: float, bands: bool) -> EquilibriumReport:
    rep = sv.report(m, g, mu)
    if bands:
        rep.stable_bands, rep.adiabatic_bands = _bands.bands_of(
            sv.onaxis, sv.zs, [sv.rows[z] for z in sv.zs], rep.z_c, g, A, C, mu)
    return rep


TOP_PARAMS = ("m", "mu")       # the top's: m g + mu Phi_2 = 0 keeps them out of Phi (thesis 3.3.2)
KEPT_SURVEYS = 64              # plates (parameter vectors but the top's) whose survey a model keeps


def plate_survey(model, p: np.ndarray | None = None) -> Survey:
    """survey() of a loaded model's plate at the parameters p, kept per model and keyed on p but
    the top's mass and moment: the on-axis functions Phi_k are the plate's alone (thesis 3.3.1:
    U = m g z + mu Phi_1), so a launch Monte Carlo, whose tops differ in m and mu only, surveys its
    plate once, not once a launch. Each call gets its own copy, so that what one top's root search
    adds to it (a pole found between knots) stays with that top: every answer is a fresh survey's."""
    q = np.array(model.p if p is None else p, float)
    for name in TOP_PARAMS:
        if name in model.param_names:
            q[model.param_names.index(name)] = 0.0
    kept = model.__dict__.setdefault("_plate_surveys", {})
    key = q.tobytes()
    sv = kept.get(key)
    if sv is None:
        with naming_the_formula(model):
            sv = survey(model_onaxis(model, p), scale_of(model, p), span_of(model))
        if len(kept) < KEPT_SURVEYS:
            kept[key] = sv
    return Survey(sv.onaxis, sv.scale, sv.top, list(sv.zs), dict(sv.rows), list(sv.singularities),
                  list(sv.barriers), list(sv.extrema), dict(sv.columns))


def equilibria_of(model, p: np.ndarray | None = None, bands: bool = False) -> EquilibriumReport:
    """Equilibria, z_c, max_mass and singularities of a loaded model's top and plate (parameters p,
    default the scene's; thesis 3.3.2-3.3.3); with bands=True also the stable and adiabatic bands.
    A model whose on-axis functions are nowhere finite is a UserError naming the scene's formula."""
    P = params_of(model, p)
    sv = plate_survey(model, p)
    with naming_the_formula(model):
        return _report(sv, P["m"], P["g"], P["A"], P["C"], P["mu"], bands)


@contextmanager
def naming_the_formula(model):
    """A NonFiniteModel raised inside becomes a UserError naming the scene's formula(s)."""
    try:
        yield
    except NonFiniteModel as exc:
        where = "; ".join(formulas(model.scene.data["plate"])) or f"scene '{model.scene.name}'"
        raise UserError(f"{where}: {exc}; fix the formula or its [plate.params]") from None


class NoHover(UserError):
    """The top has no vertically stable hover height (hover_height): a fact about the design,
    which a launch counts as probability 0 rather than as bad input."""


def hover_height(model, p: np.ndarray | None = None) -> float:
    """z_s: the lowest vertically stable equilibrium (thesis 3.3.2-3.3.3); a one-line UserError
    naming the reason when there is none."""
    key = np.asarray(model.p if p is None else p, float).tobytes()
    known = model.__dict__.setdefault("_hover_heights", {})     # per model: p -> z_s (or None)
    if key in known and known[key] is not None:
        return known[key]
    rep = equilibria_of(model, p)
    if len(known) < 4096:
        known[key] = rep.stable[0].z if rep.stable else None
    if not rep.stable:
        m = params_of(model, p)["m"]
        raise NoHover(f"scene '{model.scene.name}' has no vertically stable hover height: "
                      f"{rep.no_hover_reason(m)} (see `«levitron=equilibrium»`)")
    return rep.stable[0].z
