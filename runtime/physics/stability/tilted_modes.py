"""The linear modes of the top over a tilted base, its magnet aligned: at the relative equilibrium off
the axis (runtime/physics/apparatus/tilted_equilibrium.py).

Over a base tilted by t the top still has a relative equilibrium: it hovers off the plate's axis,
its own axis tilted, spinning about it at a fixed point of the lab (the position and the angles do
not depend on the spin; the angular momenta scale with it). zeta stays cyclic there, so Routh's
reduction of runtime/physics/stability/modes.py holds unchanged: the ten variables q = (x, y, z, phi,
vartheta), p = (p_x, ..., p_vartheta) at p_zeta = C sigma, the equilibrium a critical point of H,
the linearisation xdot = Jsym S x with J the generated `full_jac` at the equilibrium (zeta's column
and p_zeta's row dropped: tilted_stability.reduced_jacobian, which checks that they vanish) and
S = -Jsym J its Hessian (friction set to 0 first). The modes are read from J exactly as on the axis
(LinearSystem.modes: each pair +-i omega, its energy (Krein) sign v^H S v, its sense the
circulation about the vertical against the spin's), and named by the same rule (modes.py `_names`):
the tilt mixes the bounce into the transverse modes by O(t), so the names hold while the tilt is
small against the window's margins; the spin interval over the tilted base is
tilted_stability.tilted_analysis's (route "eigenvalues" on the same Jacobian). No sympy here.
"""
from __future__ import annotations

import numpy as np

from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus.friction import without_friction
from levitron.runtime.physics.stability.modes import STATES, LinearSystem, Modes
from levitron.runtime.ui.human import Units
from levitron.runtime.ui.validate import spin_rate


class TiltedSystem(LinearSystem):
    """LinearSystem at the relative equilibrium over the tilted base (module docstring): the same
    states and modes, the Jacobian at the equilibrium off the axis."""

    def __init__(self, model, p: np.ndarray, eq, params: np.ndarray, spin_sign: float):
        P = model.pvals(p)
        self.model, self.p, self.P, self.eq = model, p, P, eq
        self.z_s = float(eq.position[2])
        self.m, self.A, self.C, self.mu = P["m"], P["A"], P["C"], P["mu"]
        h = len(STATES) // 2
        self.Jsym = np.block([[np.zeros((h, h)), np.eye(h)], [-np.eye(h), np.zeros((h, h))]])
        self.full = True
        self.source = "full_jac (generated) at the relative equilibrium over the tilted base"
        self.hessian_source = "Jsym^-1 J"
        self._hess = None
        self.states = list(eq.states)
        self.keep = [self.states.index(s) for s in STATES]
        self._jac = model.fast("full_jac", params)
        self.spin_sign = spin_sign

    def state(self, sigma: float) -> np.ndarray:
        return self.eq.at_spin(sigma)


def tilted_base_modes(model, spin: float, p: np.ndarray | None = None) -> Modes:
    """The modes (module docstring) at `spin` of the model's top at parameters p (the scene's), over
    its tilted base with the magnet aligned; a UserError where the equilibrium does not exist."""
    from levitron.runtime.physics.apparatus.tilted_equilibrium import NoEquilibrium, TiltedTop
    from levitron.runtime.physics.apparatus.tilted_stability import tilted_analysis
    sigma = spin_rate(spin)
    p = without_friction(model, model.p if p is None else p)
    P = model.pvals(p)
    if P.get("moment_tilt", 0.0) != 0 or P.get("moment_offset", 0.0) != 0 or P.get("base_tilt", 0.0) == 0:
        raise UserError("these are the modes over a tilted base with the magnet aligned: "
                        "runtime/physics/stability/modes.py and rotating_modes.py give the others")
    res = tilted_analysis(model, p)
    if not res.z_s:
        raise UserError(f"no linear modes: the top has no equilibrium over the tilted base ({res.reason})")
    level = LinearSystem(model, res.equilibrium["z_level"], model.with_params({"base_tilt": 0.0}, p), "jacobian")
    top = TiltedTop(model, p, res.equilibrium["z_level"])
    try:
        eq = top.hamilton(P["base_tilt"], sigma)
    except NoEquilibrium as exc:
        raise UserError(f"no linear modes at this spin: {exc}") from None
    ls = TiltedSystem(model, p, eq, top.params_at(P["base_tilt"]), level.spin_sign)
    modes = ls.modes(sigma)
    J = ls.jacobian(sigma)
    residual = float(np.linalg.norm(ls.Jsym @ ls.hessian(sigma, J) - J) / np.linalg.norm(J))
    return Modes(sigma, ls.z_s, modes, all(m.krein != 0 for m in modes), res.spin_interval, ls.source,
                 ls.hessian_source, residual, Units.of_scene(model.scene))
