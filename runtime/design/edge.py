"""The edge of the spin objectives: a hover height approaching z_c, where the stiffness vanishes.

As z_s -> z_c (the top's mass -> max_mass, thesis 3.3.3) the vertical stiffness k = mu Phi_3(z_s)
vanishes and the ray cubic's constant term -4 c3^3 with it (thesis 3.3.13), so one critical spin
grows without bound. The stable interval does not follow it: at z_c (g31 = 0) the diverging
root is the root l = 0 of the thesis's cubic L(l) (3.3.16, a0 = 0), sigma^2 = g / (2 rho^2 l g21
alpha) (3.3.21), and the interval of linear stability lies between the two positive roots of L/l,
finite wherever g21^2 < 1/12 (thesis 3.3.15, 3.3.22-3.3.23; figure 3.7): thesis_stable
478.9-2531 rad/s at z_c, measured on every committed scene and for C/A from 0.1 to 2, the
diverging root opening a second interval beyond 1e25 rad/s. So the spin objectives need no
stiffness constraint. check_bounded stays as the guard for a scene where that reading fails (a
Sturm count at z_c, not the argument above). An optimum near the edge is
reported with its stiffness and a warning (VANISHING), and refused only where the interval at z_c,
continued from the optimum's, is unbounded above (then the objective has no maximum).
"""
from __future__ import annotations

import math

from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.errors import UserError
from levitron.runtime.words import si, si_unit

VANISHING = 1e-2     # k z_s / (m g) below this: the stiffness is vanishing (1% of the hover's scale m g / z_s)
UNBOUNDED = 1e6      # an interval end at z_c this many times the optimum's sigma_hi: no upper bound


def relative_stiffness(stiffness: float, mass: float, g: float, z_s: float) -> float:
    """k z_s / (m g): the vertical stiffness against the scale of a spring that holds the weight
    m g at the height z_s (thesis 3.3.3: k = mu Phi_3(z_s))."""
    return stiffness * z_s / (mass * g)


def warning(stiffness: float, mass: float, g: float, z_s: float, max_mass: float | None) -> str | None:
    """A sentence when the stiffness at the optimum is vanishing (VANISHING), else None."""
    rel = relative_stiffness(stiffness, mass, g, z_s)
    if rel >= VANISHING:
        return None
    margin = "" if max_mass is None else (f"; a top {(max_mass - mass) / mass:.2g} (relative) heavier "
                                          "no longer hovers")
    return (f"the optimum sits at vanishing stiffness: k = {si(stiffness, 'N/m', '.3g')}, {rel:.2g} of m g / z_s, "
            f"z_s = {si(z_s, 'm')} near z_c{margin}; add «constrain» stiffness>=K for a robust design")


def check_bounded(model, p, interval: tuple[float, float], where: str) -> None:
    """UserError when the spin interval, continued from `interval` to the top of mass m(z_c) at z_c
    (parameters p), is unbounded above: the objective then grows without bound towards z_c."""
    from levitron.runtime.physics.stability.analysis import stability_of
    P = eqm.params_of(model, p)
    rep = eqm.equilibria_of(model, p)
    if rep.z_c is None or rep.max_mass is None:
        return
    res = stability_of(model, mass=rep.max_mass, p=p, z_s=rep.z_c)
    lo = interval[0]
    at_edge = min(res.discriminant, key=lambda iv: abs(math.log(iv[0] / lo)) if iv[0] > 0 else math.inf,
                  default=None)
    if at_edge is not None and at_edge[1] > UNBOUNDED * interval[1]:
        raise UserError(f"the spin objective is unbounded at {where}: as the hover height nears "
                        f"z_c = {si(rep.z_c, 'm')} (mass {si(rep.max_mass, 'kg')}, g = {P['g']:.6g}) the stable "
                        f"interval from {si(at_edge[0], 'rad/s', '.4g')} has no upper end; add «constrain» "
                        f"stiffness>=K with K > 0 ({si_unit('N/m')})")
