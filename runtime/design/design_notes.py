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
- `below_noise_note`: a launch-odds design whose keys move the odds by less than the odds' own noise
  says that any value of its box does as well: the best and the worst search points differ by less
  than the half-width of the answer's 95 % Wilson interval, or every point ran all its launches and
  differs from the best in fewer than MIN_DISCORDANT of them (the paired test's level, paired_odds.py).
- `with_launch_notes`: both of the above, what `optimize --maximize launch-odds` and
  `Study.optimize("launch-odds", ...)` add to the search's LaunchDesign.
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


def below_noise_note(design) -> str | None:
    """One line where the LaunchDesign's keys move the odds less than their noise (module docstring):
    the search points' odds (design.evaluations, on the same draws) span less than the half-width of
    the answer's Wilson interval, or no point is told apart from the best by the paired test."""
    from levitron.runtime.design.paired_odds import MIN_DISCORDANT
    rows = [r for r in design.evaluations if r.get("probability") is not None]
    if len(rows) < 2:
        return None
    odds = [float(r["probability"]) for r in rows]
    spread = max(odds) - min(odds)
    lo, hi = design.launch_odds["probability_ci95"]
    per_point = int((design.work or {}).get("launches_per_point") or design.n)
    full = not any(r.get("stopped_early") or r.get("reason") for r in rows)
    if not (spread < 0.5 * (hi - lo) or (full and round(spread * per_point) < MIN_DISCORDANT)):
        return None
    keys = list(design.optimum)
    what = f"the key {keys[0]} moves" if len(keys) == 1 else f"the keys {', '.join(keys)} move"
    return (f"{what} the odds less than their noise ({design.n} launches): any value in the box "
            "does as well")


def with_launch_notes(model, design):
    """The LaunchDesign `design` of `model` with its notes: the resonance advice
    (`with_resonance_advice`), then the keys' noise (`below_noise_note`) last among its warnings."""
    design = with_resonance_advice(model, design)
    note = below_noise_note(design)
    if note is None:
        return design
    return dataclasses.replace(design, warnings=[*design.warnings, note])
