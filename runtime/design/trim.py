"""Trim by the launch odds: the mass to add or take off so that most launches by hand float (issue 26).

The stable band (thesis 3.3: the heights z where the top of mass m(z) = -mu Phi_2(z)/g, eq. 3.3.2,
has a spin interval of linear stability) fixes the masses that can hover at all, [m_lo, m_hi] at the
scene's temperature. Inside it the linear spin window (sigma_lo, sigma_hi) of each mass (the
discriminant route, thesis 3.3.15-3.3.19) is widest near an edge of the band, where a spread of
0.2 % in mass or strength puts part of the launches outside the band: advice by the window alone
fails there. The trim is therefore the launch-odds design (runtime/design/launch_design.py) over
top.mass in the band, with the same launch spread as `levitron launch`; beside it, the window of
every mass and the odds at the widest window, so the two pieces of advice can be compared. The
answer is runtime/design/trim_answer.py's Trim.
"""
from __future__ import annotations

import contextlib
from collections.abc import Sequence

import numpy as np

from levitron.runtime.design import launch_design as ld
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.design.trim_answer import Trim
from levitron.runtime.errors import UserError
from levitron.runtime.physics import equilibrium as eqm
from levitron.runtime.physics.bands import edge_note
from levitron.runtime.physics.stability import stability_of
from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.ui.human import Units
from levitron.runtime.words import si, si_span

LIMIT_POINTS = 41        # masses at which the spin window is drawn, the band's edges included


def spin_limits(model, masses: Sequence[float]) -> list[dict]:
    """The spin interval of linear stability of each mass at its stable height (the discriminant
    route; None where it has none): the curve the widest-window advice reads."""
    out = []
    for m in masses:
        res = stability_of(model, mass=float(m), eigen=False)
        iv = res.spin_interval
        out.append({"mass": float(m), "z_s": res.z_s,
                    "spin_interval": None if iv is None else [float(iv[0]), float(iv[1])]})
    return out


def trim(model, request: mc.Request) -> Trim:
    """The trim of the module docstring for the loaded model (its temperature and --set included)."""
    band = eqm.equilibria_of(model, bands=True).stable_band
    if band is None:
        raise UserError(f"{model.scene.name}: no mass can hover over this plate (no stable band), so "
                        "there is nothing to trim; `«levitron=equilibrium»` says why")
    lo, hi = band.mass
    with contextlib.ExitStack() as stack:      # one pool of workers for every Monte Carlo of the trim
        pool = ld.kept_pool(stack, request, request.n)
        design = ld.maximize_launch_odds(model, [Vary("top.mass", lo, hi)], request,
                                         where="the masses that hover (the stable band)", pool=pool)
        widest, limits = _widest(model, lo, hi, design, request, pool)
    warnings = []
    note = edge_note(band, eqm.span_of(model) is not None)
    if note:
        warnings.append(f"the masses that hover, {si_span(lo, hi, 'kg')}: {note}")
    if not lo <= model.param("m") <= hi:
        warnings.append(f"the scene's top ({si(model.param('m'), 'kg')}) is outside the masses that can "
                        f"hover, {si_span(lo, hi, 'kg')}: as written it does not float at all")
    return Trim(model.param("m"), (lo, hi), design, limits, widest, warnings, Units.of_scene(model.scene))


def _widest(model, lo: float, hi: float, design, request: mc.Request, pool) -> tuple[dict, list[dict]]:
    """The widest linear spin window over the band's masses, with its launch odds on the design's
    fresh draws (in `pool`), and the window of every mass."""
    limits = spin_limits(model, np.linspace(lo, hi, LIMIT_POINTS))
    widths = [(r["spin_interval"][1] - r["spin_interval"][0]) if r["spin_interval"] else -np.inf
              for r in limits]
    widest = dict(limits[int(np.argmax(widths))])
    fresh = mc.Request(dict(design.inputs), design.n, design.seed + ld.FRESH, design.success_time,
                       design.t_end, request.integrator, request.tol, request.workers, request.scheduler)
    widest["launch_odds"] = ld.odds_dict(ld.odds_at(model.ref, ["top.mass"], [widest["mass"]], fresh, pool))
    return widest, limits
