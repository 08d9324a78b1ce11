"""The report's section on a launch in air (a scene with a spin decay time, derive/friction.py):
the flight against the adiabatic prediction tau ln(omega_0 / sigma_lo) (runtime/physics/apparatus/friction.py),
the launch odds with their 95 % Wilson interval and the launch spread used, what matters most
(runtime/scan/launch_odds.py monte_carlo), and the masses that hover (the stable band's mass window,
thesis 3.3.2-3.3.3) at the scene's temperature and TEMPERATURE_STEP degC either side, through both
magnets' temperature coefficients.
"""
from __future__ import annotations

import html
from pathlib import Path

from levitron.runtime.report.html_parts import table as _table
from levitron.runtime.ui.human import Units, sig, span

ODDS_N = 200             # launches of the report's odds: a sketch; `levitron launch` runs more
TEMPERATURE_STEP = 8.0   # degC either side of the scene's temperature


def mass_windows(model) -> list[dict]:
    """The stable band's mass window at the scene's temperature T and at T -/+ TEMPERATURE_STEP
    (mu scaled by launch_inputs.temperature_factor)."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.physics.equilibrium.bands import edge_note
    from levitron.runtime.scan.launch_inputs import temperature_factor
    from levitron.scene.keys import T_REF
    T0 = float(model.scene.data.get("temperature", T_REF))
    mu = model.param("mu")
    out = []
    for dT in (-TEMPERATURE_STEP, 0.0, TEMPERATURE_STEP):
        f = temperature_factor(model, T0 + dT)
        band = eqm.equilibria_of(model, model.with_params({"mu": mu * f}), bands=True).stable_band
        out.append({"temperature": T0 + dT, "factor": f, "mass": list(band.mass) if band else None,
                    "z": list(band.z) if band else None,
                    "note": edge_note(band, eqm.span_of(model) is not None)})
    return out


def hover_temperatures(model, step: float = 1.0, reach: float = 40.0) -> tuple[float | None, float | None]:
    """The temperatures (degC) nearest the scene's, below and above, at which its top stops
    hovering (its mass leaves the stable band's masses as the magnets' strength moves with the
    temperature: launch_inputs.temperature_factor), to `step` by a scan then bisection over
    +-`reach`; None where it still hovers at the end of the reach (or has no temperature
    coefficients)."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.scan.launch_inputs import temperature_factor
    from levitron.scene.keys import T_REF
    T0, mu, m = float(model.scene.data.get("temperature", T_REF)), model.param("mu"), model.param("m")

    def hovers(T: float) -> bool:
        band = eqm.equilibria_of(model, model.with_params({"mu": mu * temperature_factor(model, T)}),
                                 bands=True).stable_band
        return band is not None and band.mass[0] <= m <= band.mass[1]
    if not hovers(T0) or temperature_factor(model, T0 + reach) == 1.0:
        return None, None
    out = []
    for sign in (-1, 1):
        a, b = T0, None
        for k in range(1, int(reach / 4) + 1):          # scan in 4 degC steps, then bisect
            if not hovers(T0 + sign * 4 * k):
                a, b = T0 + sign * 4 * (k - 1), T0 + sign * 4 * k
                break
        while b is not None and abs(b - a) > step:
            mid = 0.5 * (a + b)
            a, b = (mid, b) if hovers(mid) else (a, mid)
        out.append(None if b is None else b)
    return out[0], out[1]


def sentence(line: str, end: str = ".") -> str:
    """A line of an answer's plain view as a sentence of the page: capitalised, closed by `end`."""
    return line[:1].upper() + line[1:] + end


def maker_summary(model, odds, band_mass, temps, u: Units) -> str:
    """What a maker decides on, first: the odds with their interval, the margins in mass to both
    edges of the masses that hover, and the temperatures at which the top stops hovering."""
    m = model.param("m")
    parts = [sentence(odds.lines(u, face=None)[0], "")]      # the answer's own headline (launch_answer.py)
    if band_mass is not None and band_mass[0] <= m <= band_mass[1]:
        parts.append(f"the top may lose {u.mass(m - band_mass[0])} or gain {u.mass(band_mass[1] - m)} and "
                     "still hover")
    else:
        parts.append("the top as written does not hover: `«levitron=trim»` gives the mass to set")
    cold, hot = temps
    if cold is not None or hot is not None:
        parts.append("it stops hovering " + " and ".join(
            t for t in (f"below about {sig(cold, 3)} degC" if cold is not None else "",
                        f"above about {sig(hot, 3)} degC" if hot is not None else "") if t))
    return "; ".join(parts) + "."


def odds_paragraph(odds, u: Units) -> str:
    """The report's answer on the launch odds (a LaunchOdds), in the answer's own words
    (runtime/scan/launch_answer.py launch_lines: the command line's plain view), its markers left
    for the page to word."""
    head, *rest = odds.lines(u, face=None)
    return "".join([f"<p class=\"answer\">{html.escape(sentence(head, ''))}: launches by hand, the "
                    "interval the score interval of Wilson 1927.</p>",
                    *(f"<p class=\"note\">{html.escape(sentence(line))}</p>" for line in rest),
                    "<p class=\"note\">`«levitron=launch»` runs more launches and takes other spreads.</p>"])


def resonance_text(model, odds) -> str:
    """Where the report's launches (the scene's top, its [launch] spin) cross an explosive resonance,
    the sentence saying which side of it to launch on (runtime/design/trim.py resonance_advice),
    as a paragraph; "" where none is crossed or no launch could run."""
    from levitron.runtime.design.trim import resonance_advice
    from levitron.runtime.scan.spreads import parse_dist
    if odds.reason:
        return ""
    advice = resonance_advice(model, model.param("m"), parse_dist("spin", odds["inputs"]["spin"]),
                              odds["success_time"])
    return "" if advice is None else f"<p>{html.escape(advice[0][0].upper() + advice[0][1:])}.</p>"


def section(model, run: dict, u: Units, tmp: Path, png) -> tuple[str, dict]:
    """The section's HTML and its facts (SI). run: the report's flight (simulate's answer)."""
    from levitron.runtime.integrate.verdict import stopped_early
    from levitron.runtime.scan import launch_odds as mc
    fl = run["flight"]
    facts = {"flight_time": fl["flight_time"] if fl["fell"] else None, "t_cross": fl["t_cross"],
             "fall_spin": fl["fall_spin"] if fl["fell"] else None}
    rows = [("launch", f"spin {u.rate(run['spin']['rad_s'])}, tilt {u.angle(run['tilt'])}")]
    if fl["fell"]:
        rows.append(("flight time (the run)", u.time(fl["flight_time"])))
    elif stopped_early(run["status"]):
        rows.append(("flight time (the run)", f"no verdict: the run stopped early ({run['status']}) "
                     f"after {u.time(run['t_survived'])}"))
    else:
        rows.append(("flight time (the run)", f"still floating after {u.time(run['t_survived'])}"))
    if fl["t_cross"]:
        diff = (f" ({sig(100 * (fl['flight_time'] - fl['t_cross']) / fl['t_cross'], 2)} % apart)"
                if fl["fell"] else "")
        rows.append(("adiabatic prediction tau ln(omega_0 / sigma_lo)", u.time(fl["t_cross"]) + diff))
    if fl["fell"]:
        rows.append(("spin at the fall", f"{u.rate(fl['fall_spin'])} (lower limit "
                     f"{u.rate(fl['spin_interval'][0])})" if fl["spin_interval"] else u.rate(fl["fall_spin"])))
    given, table = mc.table_settings(model.scene.data.get("launch", {}))
    odds = mc.monte_carlo(model, given, n=ODDS_N, seed=0, quiet=True)
    facts["odds"] = {k: odds[k] for k in ("probability", "probability_ci95", "n", "seed", "success_time",
                                          "t_end", "inputs")}
    facts["odds"]["ranking"] = [{"input": e["input"], "effect": e["effect"], "noise": e["noise"]}
                                for e in odds["ranking"]]
    windows = mass_windows(model)
    facts["mass_windows"] = windows
    facts["stops_hovering"] = dict(zip(("below", "above"), hover_temperatures(model)))
    facts["summary"] = maker_summary(model, odds, windows[1]["mass"], tuple(facts["stops_hovering"].values()), u)
    m = model.param("m")
    odds.plot(tmp / "odds.png")
    out = ["<h2>The real launch: in air</h2>", _table(rows),
           odds_paragraph(odds, u),
           resonance_text(model, odds),
           png(tmp / "odds.png"),
           "<h3>The masses that hover, and the temperature</h3>",
           _table([(f"{sig(w['temperature'], 3)} degC" + (" (the scene's)" if i == 1 else ""),
                    f"mass {span(*w['mass'], u.mass)}, heights {u.length_span(*w['z'])}"
                    + (f" ({w['note']})" if w["note"] else "")
                    + ("" if w["mass"][0] <= m <= w["mass"][1] else f"; the scene's {u.mass(m)} top does not hover")
                    if w["mass"] else "no stable band") for i, w in enumerate(windows)]),
           "<p class=\"note\">The magnets weaken as they warm (the scene's temperature coefficients); the "
           "masses that hover move with them: trim the top with washers at the temperature it flies in.</p>"]
    return "".join(out), facts

