"""Linear stability of the spinning top at its relative equilibrium, by two routes (thesis 3.3).

The spin interval sigma for which the top, hovering on the axis at z_s with its axis vertical
(thesis 3.3.4, 3.3.5), is linearly (spectrally) stable:
* route "discriminant" (runtime/physics/ray_algebra.py, thesis 3.3.9-3.3.16): exact rational arithmetic on
  the ray polynomial and a Sturm count of N(t); this route's interval is the one reported;
* route "eigenvalues" (runtime/physics/eigen_route.py): the eigenvalues of the generated full model's
  Jacobian (or the 8-D transverse matrix) on the imaginary axis, to a perturbation bound.
z_s comes from the one equilibrium finder (runtime/physics/equilibrium.py). No sympy here.
"""
from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from levitron.runtime.physics import equilibrium as eqm
from levitron.runtime.errors import UserError
from levitron.runtime.physics.friction import without_friction
from levitron.runtime.physics.eigen_route import (
    full_equilibrium_state,
    spin_intervals_eigen,
    transverse_block,
    transverse_matrix,
)
from levitron.runtime.physics.ray_algebra import (
    RayCoefficients,
    spin_intervals_discriminant,
    thesis_approximations,
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


@dataclass
class StabilityResult:
    z_s: float | None
    spin_interval: tuple[float, float] | None
    discriminant: list[tuple[float, float]]
    eigenvalues: list[tuple[float, float]] | None
    approximations: dict
    reason: str | None
    routes_agree: bool | None
    timings: dict
    mass: float | None = None        # kg: the top analysed (stability_of's `height`: the one hovering there)

    def as_dict(self) -> dict:
        def pair(iv):
            return None if iv is None else [float(iv[0]), float(iv[1])]

        def first(ivs):
            return pair(ivs[0]) if ivs else None

        si = pair(self.spin_interval)
        hz = None if si is None else [v / (2 * math.pi) for v in si]
        rpm = None if hz is None else [v * 60 for v in hz]
        return {
            "z_s": self.z_s,
            "spin_interval": si,
            "spin_interval_hz": hz,
            "spin_interval_rpm": rpm,
            "routes": {"discriminant": first(self.discriminant),
                       "eigenvalues": first(self.eigenvalues) if self.eigenvalues is not None else None},
            "all_intervals": {"discriminant": [pair(v) for v in self.discriminant],
                              "eigenvalues": None if self.eigenvalues is None
                              else [pair(v) for v in self.eigenvalues]},
            "routes_agree": self.routes_agree,
            "approximations": self.approximations,
            "reason": self.reason,
            "timings_s": self.timings,
        }


def relative_gap(a: Sequence[tuple[float, float]], b: Sequence[tuple[float, float]]) -> float:
    """Largest relative difference between matching interval end points (inf if counts differ)."""
    if len(a) != len(b):
        return math.inf
    gap = 0.0
    for (a0, a1), (b0, b1) in zip(a, b):
        for u, v in ((a0, b0), (a1, b1)):
            if u != v:
                gap = max(gap, abs(u - v) / max(abs(u), abs(v)))
    return gap


def _approximations(onaxis, z_c, max_mass, g, A, C) -> dict:
    """Thesis 3.3.22/3.3.23 at z_c for the top of mass m(z_c) that hovers there."""
    out = {"sigma1": None, "sigma2": None, "z_c": z_c, "mass_at_z_c": max_mass, "g21": None,
           "note": "thesis eqs. 3.3.22/3.3.23 (printed as squares) at z_c, for the top of mass "
                   "m(z_c) that hovers there; rad/s"}
    if z_c is not None and max_mass is not None and max_mass > 0:
        ph = onaxis(z_c)
        out.update(thesis_approximations(ph[1], ph[2], g, max_mass, A, C))
        for k in ("sigma1", "sigma2"):
            v = out[k]
            out[k + "_hz"] = None if v is None else v / (2 * math.pi)
    return out


def analyse(onaxis: Callable[[float], Sequence[float]], m: float, g: float, A: float, C: float,
            mu: float, scale: float, full_jac: Callable[[np.ndarray], np.ndarray] | None = None,
            states: Sequence[str] | None = None, z_s: float | None = None,
            agree_rtol: float = 1e-6, eigen: bool = True,
            span: tuple[float, float] | None = None) -> StabilityResult:
    """Spin interval of linear stability at the stable height, by both routes (thesis 3.3).

    z_s: the lowest vertically stable equilibrium (thesis 3.3.3; runtime/physics/equilibrium.py, the one
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
        reason = f"z_s = {z_s:.6g} m is not vertically stable (mu Phi_3 = {mu * ph[3]:.3g} N/m <= 0, thesis 3.3.3)"
    elif not bounded:
        reason = (f"at z_s = {z_s:.6g} m the top is vertically stable but no spin rate makes it "
                  "linearly stable: N(t) (thesis 3.3.11) never has four real roots; the height is "
                  "outside the stable band (see `levitron equilibrium`)")
    else:
        interval = bounded[0]
        if len(bounded) > 1:
            reason = f"{len(bounded)} disjoint spin intervals; spin_interval is the lowest"
    return StabilityResult(z_s, interval, disc, eig, approximations, reason, agree, timings)


def stability_of(model, mass: float | None = None, p: np.ndarray | None = None,
                 z_s: float | None = None, height: float | None = None,
                 eigen: bool = True) -> StabilityResult:
    """The StabilityResult of a loaded model's top (another mass if given; parameters p, default the
    scene's), with the eigenvalue route on the generated full Jacobian when the model has one.

    z_s: an equilibrium height of that top, to skip the search. height: analyse instead the top
    that hovers at this height, of mass m(z) = -mu Phi_2(z) / g (thesis 3.3.2 solved for m; the
    stable band's rule, docs/contract.md); a UserError where no top hovers there (m(z) <= 0).
    In air the friction rates are set to 0: the interval is the ideal top's (runtime/physics/friction.py)."""
    if height is not None:
        if mass is not None or z_s is not None:
            raise ValueError("stability_of: height excludes mass and z_s")
        P = eqm.params_of(model, p)
        m_z = eqm.hover_mass(eqm.model_onaxis(model, p), P["g"], P["mu"], float(height))
        if not (math.isfinite(m_z) and m_z > 0):
            raise UserError(f"no top hovers at z = {height:.6g} m: the field there holds no mass "
                            f"(m(z) = -mu Phi_2(z)/g = {m_z:.3g} kg <= 0, thesis 3.3.2); pick a height "
                            "inside the stable band (`levitron equilibrium` gives it)")
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
