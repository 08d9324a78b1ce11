"""Linear stability of the spinning top at its relative equilibrium, by two routes (thesis 3.3).

The spin interval sigma for which the top, hovering on the axis at z_s with its axis vertical
(thesis 3.3.4, 3.3.5), is linearly (spectrally) stable:
* route "discriminant" (runtime/physics/routes/ray_algebra.py, thesis 3.3.9-3.3.16): exact rational arithmetic on
  the ray polynomial and a Sturm count of N(t); this route's interval is the one reported;
* route "eigenvalues" (runtime/physics/routes/eigen_route.py): the eigenvalues of the generated full model's
  Jacobian (or the 8-D transverse matrix) on the imaginary axis, to a perturbation bound.
z_s comes from the one equilibrium finder (runtime/physics/equilibrium/finder.py). No sympy here.
"""
from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence

import numpy as np

from levitron.scene.plates.symmetry import symmetry
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus.friction import without_friction
from levitron.runtime.ui.validate import height as valid_height
from levitron.runtime.words import si
from levitron.runtime.physics.routes.eigen_route import (
    full_equilibrium_state,
    spin_intervals_eigen,
    transverse_block,
    transverse_matrix,
)
from levitron.runtime.physics.routes.ray_algebra import RayCoefficients, spin_intervals_discriminant
from levitron.runtime.physics.routes.result import (  # noqa: F401  (StabilityResult's home)
    StabilityResult,
    approximations_at_z_c as _approximations,
    relative_gap,
)


def model_callables(model, p: np.ndarray | None = None) -> tuple[Callable, Callable, list[str]]:
    """(onaxis(z), full_jac(state), full states) of a loaded runtime.model.load.Model, fast; p: a
    parameter vector other than the scene's (order: model.param_names)."""
    p = model.p if p is None else p
    onaxis = eqm.model_onaxis(model, p)
    part = model.part("full")
    jfast = model.fast("full_jac", p)
    n = part.nx
    return onaxis, (lambda x: jfast(x).reshape(n, n)), list(part.states)


def analyse(onaxis: Callable[[float], Sequence[float]], m: float, g: float, A: float, C: float,
            mu: float, scale: float, full_jac: Callable[[np.ndarray], np.ndarray] | None = None,
            states: Sequence[str] | None = None, z_s: float | None = None,
            agree_rtol: float = 1e-6, eigen: bool = True,
            span: tuple[float, float] | None = None) -> StabilityResult:
    """Spin interval of linear stability at the stable height, by both routes (thesis 3.3).

    z_s: the lowest vertically stable equilibrium (thesis 3.3.3; runtime/physics/equilibrium/finder.py, the one
    finder), unless given. full_jac(state) -> 12x12 is the generated model's Jacobian (route
    "eigenvalues" on the full model); without it the 8-D matrix `transverse_matrix` is used. The
    reported spin_interval is the exact route's ("discriminant"); routes_agree says whether the
    eigenvalue route matches it to agree_rtol. Approximations: thesis 3.3.22/3.3.23 at z_c.
    eigen=False skips the eigenvalue route (eigenvalues and routes_agree None; the interval, z_s
    and reason are the same): for callers that need the interval only, such as a map's linear
    picture, which then need not load scipy.linalg.
    """
    timings = {}
    t0 = time.perf_counter()
    rep = eqm.survey(onaxis, scale, span).report(m, g, mu)
    timings["equilibria"] = time.perf_counter() - t0
    approximations = _approximations(onaxis, rep.z_c, rep.max_mass, g, A, C)
    if z_s is None:
        if not rep.stable:
            return StabilityResult(None, None, [], None, approximations, rep.no_hover_reason(m),
                                   None, timings)
        z_s = rep.stable[0].z
    ph = np.asarray(onaxis(z_s), float)
    t0 = time.perf_counter()
    c = RayCoefficients.from_physics(ph[1], ph[2], ph[3], m, A, C, mu)
    disc = spin_intervals_discriminant(c)
    timings["discriminant"] = time.perf_counter() - t0

    if not eigen:
        eig = None
    else:
        eig = _eigen_route(ph, m, A, C, mu, z_s, disc, full_jac, states, timings)
    return _verdict(z_s, ph, mu, disc, eig, approximations, timings, agree_rtol)


def _eigen_route(ph, m: float, A: float, C: float, mu: float, z_s: float, disc, full_jac, states,
                 timings: dict):
    """The spin intervals of route "eigenvalues" (see `analyse`), probed inside the exact ones."""
    t0 = time.perf_counter()
    if full_jac is not None:
        st = list(states)

        def jac(sig):
            return transverse_block(full_jac(full_equilibrium_state(st, z_s, C, sig)), st)
    else:
        def jac(sig):
            return transverse_matrix(ph[1], ph[2], ph[3], m, A, C, mu, sig)
    rho = C / A
    sigma_scale = math.sqrt(abs(mu * ph[1]) / A) / rho if ph[1] != 0 else 1.0
    probes = [math.sqrt(a * b) for a, b in disc if 0 < a and b < math.inf]
    eig = spin_intervals_eigen(jac, sigma_scale, probes)
    timings["eigenvalues"] = time.perf_counter() - t0
    return eig


def _verdict(z_s: float, ph, mu: float, disc, eig, approximations, timings: dict,
             agree_rtol: float) -> StabilityResult:
    """The StabilityResult of `analyse` from the routes' intervals (eig None: not run)."""
    vertical = mu * ph[3] > 0
    bounded = [iv for iv in disc if iv[1] < math.inf and iv[0] > 0]
    agree = None if eig is None else relative_gap(disc, eig) <= agree_rtol
    reason = None
    interval = None
    if not vertical:
        reason = (f"z_s = {si(z_s, 'm')} is not vertically stable (mu Phi_3 = {si(mu * ph[3], 'N/m', '.3g')} <= 0, "
                  "thesis 3.3.3)")
    elif not bounded:
        reason = (f"at z_s = {si(z_s, 'm')} the top is vertically stable but no spin rate makes it "
                  "linearly stable: N(t) (thesis 3.3.11) never has four real roots; the height is "
                  "outside the stable band (see `«levitron=equilibrium»`)")
    else:
        interval = bounded[0]
        if len(bounded) > 1:
            reason = f"{len(bounded)} disjoint spin intervals; spin_interval is the lowest"
    return StabilityResult(z_s, interval, disc, eig, approximations, reason, agree, timings)


def onaxis_refusal(model, p: np.ndarray | None = None) -> str | None:
    """Why the spin interval from the on-axis potential (thesis 3.3, both routes here: the 8-D
    transverse matrix and the full Jacobian probed inside the discriminant's intervals) does not
    hold for this model's plate with parameters p, or None where it does: a plate of two-fold
    symmetry (side_x != side_y) has an x^2 - y^2 part of the field (scene/plates/symmetry.py)."""
    sym = symmetry(model.scene.data["plate"], model.pvals(p))
    if sym.onaxis_stability:
        return None
    return (f"the plate has {sym.name} symmetry (side_x != side_y): the spin interval from the on-axis "
            "potential (thesis 3.3) does not hold for it; make the rectangle square (side = ...) or "
            "run the full model (`levitron simulate «spin» ...`)")


def stability_of(model, mass: float | None = None, p: np.ndarray | None = None,
                 z_s: float | None = None, height: float | None = None,
                 eigen: bool = True) -> StabilityResult:
    """The StabilityResult of a loaded model's top (another mass if given; parameters p, default the
    scene's), with the eigenvalue route on the generated full Jacobian when the model has one.

    z_s: an equilibrium height of that top, to skip the search. height: analyse instead the top
    that hovers at this height, of mass m(z) = -mu Phi_2(z) / g (thesis 3.3.2 solved for m; the
    stable band's rule, docs/contract.md); a UserError where no top hovers there (m(z) <= 0).
    In air the friction rates are set to 0: the interval is the ideal top's (runtime/physics/apparatus/friction.py).
    Over a tilted base (plate.tilt) the equilibrium is off the axis and found there
    (runtime/physics/apparatus/tilted_stability.py, route "eigenvalues" only): a z_s given (a level hover
    height) and eigen are not used. With the moment off the axis (top.moment_tilt != 0) the steady
    motion is periodic: route "Floquet" (runtime/physics/apparatus/moment_tilt.py). A UserError for a
    plate whose symmetry does not carry the analysis (`onaxis_refusal`)."""
    height = None if height is None else valid_height(height)      # the one check of a height
    if "base_tilt" in model.param_names:
        if height is not None:
            raise UserError("«height» analyses a top on the axis of a level base: over a tilted base "
                            "(plate.tilt) give the mass («set» top.mass=...) instead")
        from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis
        p = without_friction(model, model.with_params({} if mass is None else {"m": float(mass)}, p))
        if model.pvals(p).get("moment_tilt", 0.0) != 0:     # a periodic orbit: route "Floquet"
            from levitron.runtime.physics.apparatus.moment_tilt import floquet_analysis
            return floquet_analysis(model, p)
        return tilted_analysis(model, p)
    why = onaxis_refusal(model, p)
    if why is not None:
        raise UserError(why)
    if height is not None:
        if mass is not None or z_s is not None:
            raise ValueError("stability_of: height excludes mass and z_s")
        P = eqm.params_of(model, p)
        m_z = eqm.hover_mass(eqm.model_onaxis(model, p), P["g"], P["mu"], float(height))
        if not (math.isfinite(m_z) and m_z > 0):
            raise UserError(f"no top hovers at z = {si(height, 'm')}: the field there holds no mass "
                            f"(m(z) = -mu Phi_2(z)/g = {si(m_z, 'kg', '.3g')} <= 0, thesis 3.3.2); pick a height "
                            "inside the stable band (`«levitron=equilibrium»` gives it)",
                            param="height", value=float(height), unit="m",
                            hint="pick a height inside the stable band")
        return stability_of(model, mass=m_z, p=p, z_s=float(height), eigen=eigen)
    p = without_friction(model, model.with_params({} if mass is None else {"m": float(mass)}, p))
    P = eqm.params_of(model, p)
    full_jac = states = None
    if model.has_function("full_jac") and "p_zeta" in model.part("full").states:
        onaxis, full_jac, states = model_callables(model, p)     # (the Tait-Bryan states)
    else:
        onaxis = eqm.model_onaxis(model, p)
    with eqm.naming_the_formula(model):
        res = analyse(onaxis, P["m"], P["g"], P["A"], P["C"], P["mu"], eqm.scale_of(model, p),
                      full_jac, states, z_s=z_s, eigen=eigen, span=eqm.span_of(model))
    res.mass = P["m"]
    return res
