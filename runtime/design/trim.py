"""Trim by the launch odds: the mass to add or take off so that most launches by hand float.

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
import dataclasses
from collections.abc import Sequence

import numpy as np

from levitron.runtime.design import launch_design as ld
from levitron.runtime.design import paired_fresh
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.design.trim_answer import Trim
from levitron.runtime.errors import UserError
from levitron.runtime.physics.equilibrium import finder as eqm
from levitron.runtime.physics.equilibrium.bands import edge_note
from levitron.runtime.physics.stability.analysis import stability_of
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
    return _with_resonance(model, Trim(model.param("m"), (lo, hi), design, limits, widest, warnings,
                                       Units.of_scene(model.scene)))


def _with_resonance(model, t: Trim) -> Trim:
    """The trim with the resonance advice (resonance_advice) at the mass it tells the person to set
    (the scene's where it says no change), first among its warnings, in place of the launches' own
    warning of a resonance at the best mass (said once, of the mass the person sets)."""
    spin = mc.parse_input("spin", t.design.inputs["spin"])
    sets = t.mass if t.no_change else t.advice
    said = [resonance_advice(model, m, spin, t.design.success_time) for m in dict.fromkeys((sets, t.advice))]
    if not any(said):
        return t
    refined = {a[1] for a in said if a}
    design = dataclasses.replace(t.design, warnings=[w for w in t.design.warnings if w not in refined])
    return dataclasses.replace(t, design=design, warnings=([said[0][0]] if said[0] else []) + t.warnings)


def resonance_advice(model, mass: float, spin, success_time: float) -> tuple[str, str] | None:
    """Where the hand's spins (a spreads.Dist) of a top of `mass` include, or in air slow down
    through, an explosive resonance (the launch's own warning: runtime/scan/launch_inputs.py
    resonance_warnings, the resonance it names), one sentence saying on which side of it to launch,
    and the warning it refines; None where none is crossed. Milliseconds: the modes at a few spins.
    In air below it (a top launched above slows down through it), else on the side of the hand's
    mean; the aim keeps the hand's spread (2 sd, or half a uniform's width) clear of it and inside
    the window, else only less wobble is left."""
    from levitron.runtime.physics.stability.answer import resonances_of
    from levitron.runtime.scan.launch_inputs import resonance_warnings
    try:
        res = stability_of(model, mass=mass, eigen=False)
    except UserError:              # no window to speak of: the launch's own answer says why
        return None
    air = model.pvals().get("k_spin", 0.0) > 0
    warned = resonance_warnings(model, res, spin, 1 / model.pvals()["k_spin"] if air else None, success_time)
    if not warned:
        return None
    named = [r.spin for r in resonances_of(model, res) or () if si(r.spin, "rad/s") in warned[0]]
    if not named:                  # (not reached: the warning names one) its own words stand
        return warned[0], warned[0]
    r = named[0]
    mean = 0.5 * (spin.a + spin.b) if spin.kind == "uniform" else spin.a
    margin = max({"normal": 2 * spin.b, "uniform": 0.5 * (spin.b - spin.a)}.get(spin.kind, 0.0), 0.01 * r)
    lo, hi = res.spin_interval
    first = "below" if air or mean < r else "above"
    order = [first] if air else [first, "above" if first == "below" else "below"]
    fit = [(side, aim) for side in order if lo < (aim := r - margin if side == "below" else r + margin) < hi]
    if fit:
        side, aim = fit[0]
        why = "; a top launched above it slows down through it in flight" if air and mean >= r else ""
        act = (f"launch {side} it (the hand's mean at {si(aim, 'rad/s')} or {'less' if side == 'below' else 'more'}"
               f"{why}), or with less wobble")
    else:
        act = f"the window {si_span(lo, hi, 'rad/s')} leaves this hand no room beside it: launch with less wobble"
    return (f"at {si(mass, 'kg')} the hand's spins cross the explosive resonance at {si(r, 'rad/s')}, where a "
            f"launch tolerates less tilt: {act}"), warned[0]


def _widest(model, lo: float, hi: float, design, request: mc.Request, pool) -> tuple[dict, list[dict]]:
    """The widest linear spin window over the band's masses, with its launch odds on the first
    min(n, SIDE_N) of the design's fresh draws, paired with the advice's (paired_fresh.paired_side;
    in `pool`), and the window of every mass."""
    limits = spin_limits(model, np.linspace(lo, hi, LIMIT_POINTS))
    widths = [(r["spin_interval"][1] - r["spin_interval"][0]) if r["spin_interval"] else -np.inf
              for r in limits]
    widest = dict(limits[int(np.argmax(widths))])
    m = ld.side_n(design.n)
    fresh = mc.Request(dict(design.inputs), m, design.seed + ld.FRESH, design.success_time,
                       design.t_end, request.integrator, request.tol, request.workers, request.scheduler)
    side = ld.odds_at(model.ref, ["top.mass"], [widest["mass"]], fresh, pool)
    widest["launch_odds"] = paired_fresh.paired_side({**design.launch_odds, **design.paired}, side)
    return widest, limits
