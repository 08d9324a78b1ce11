"""What an IPOPT design says beside its optimum, so that the person who follows it is not misled.

- `mass_window_note`: mass-window widens the stable band (thesis 3.3.2-3.3.3: the masses
  m(z) = -mu Phi_2(z)/g over the heights where a spin interval exists), whatever mass it then
  holds; where the band at the optimum no longer holds the scene's own top, it says so in one line
  and names the trim that sets the top's mass to it.
- `barely_moves_note`: where the optimum improves on the scene as written by less than
  BARELY (relative) although the keys span their whole box, the keys barely move the objective:
  the design is not worth building for it.
- `with_resonance_advice`: a launch-odds design whose launches at the optimum cross an explosive
  resonance says on which side of it to launch (runtime/design/trim.py resonance_advice, as trim
  does), in place of the launches' own warning of it.
"""
from __future__ import annotations

import dataclasses

from levitron.runtime.words import si, si_span

BARELY = 0.01


def mass_window_note(band_mass, m: float) -> str | None:
    """One line where the band's masses (m_lo, m_hi) at the optimum do not hold the top's mass m."""
    if band_mass is None:
        return None
    lo, hi = band_mass
    if lo <= m <= hi:
        return None
    return (f"at the optimum the stable band holds {si_span(lo, hi, 'kg')}, not the scene's top "
            f"({si(m, 'kg')}): mass-window designs for whatever mass the band then holds; "
            "`«levitron=trim»` on the designed scene gives the mass to set")


def barely_moves_note(objective: str, value: float, scene_value: float | None) -> str | None:
    """One line where the optimum beats the scene as written by less than BARELY."""
    if scene_value is None or not scene_value > 0 or value <= 0:
        return None
    gain = (value - scene_value) / scene_value
    if gain >= BARELY:
        return None
    return (f"the optimum improves {objective} by only {100 * gain:.2g} % over the scene as written: "
            "these keys barely move it; vary others")


def with_resonance_advice(model, design):
    """The LaunchDesign `design` of `model` with, where the hand's spins at its optimum (the scene's
    keys set to it) cross an explosive resonance, the sentence saying which side of it to launch on
    first among its warnings, in place of the launches' own warning of that resonance."""
    from levitron.runtime.design.paired_odds import variant
    from levitron.runtime.design.trim import resonance_advice
    from levitron.runtime.scan import launch_odds as mc
    from levitron.runtime.scan.runners import model_for
    keys = list(design.optimum)
    at = model_for(*variant(model.ref, keys, [design.optimum[k] for k in keys]))
    advice = resonance_advice(at, at.param("m"), mc.parse_input("spin", design.inputs["spin"]),
                              design.success_time)
    if advice is None:
        return design
    return dataclasses.replace(design, warnings=[advice[0], *(w for w in design.warnings if w != advice[1])])
