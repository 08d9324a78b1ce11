"""One self-contained HTML page about a scene: what a plate designer sends to a colleague.

    html, facts = build(model)      # facts: the numbers on the page (SI)

The page holds the scene (its parameters), the vertical equilibria and the stable band (thesis
3.3.2-3.3.3, with the equilibrium figure), the spin interval of linear stability (thesis 3.3), a
small stability map (8 spins x 6 tilts, one slow period each: a sketch, not a converged map) and the
trajectory of a typical launch (the geometric mean of the spin interval, tilt 0.01 rad). Figures
are embedded as base64 PNG; the page refers to nothing outside itself (no scripts, no links, no
fonts), so it opens anywhere, offline.
"""
from __future__ import annotations

import html
import math
import os
import re
import tempfile
from pathlib import Path

import numpy as np

from levitron.scene import plates

from levitron.runtime.physics.equilibrium.answer import Equilibria
from levitron.runtime.report.html_parts import p as _p, png as _png, table as _table
from levitron.runtime.ui import progress, reference
from levitron.runtime.ui.atomic import sweep
from levitron.runtime.ui.human import SI_SYMBOLS, Units, sig, span
from levitron.runtime.ui.plain_text import shown
from levitron.runtime.words import render
from levitron.runtime.physics.stability.answer import Stability

MAP_SPINS, MAP_TILTS = 8, 6
LAUNCH_TILT = 0.01            # rad
LAUNCH_PERIODS = 3            # the launch runs this many slow periods

THESIS = "thesis"
THESIS_NAME = "thesis: K. F. Lüskow, Theory and Modeling of Gyroscopes, Greifswald 2011"
SCRATCH = re.compile(r"levitron-report-(\d+)-")   # the figures' scratch folder, owner pid in its name
AIR_SAMPLES = 16000           # samples of the flight in air (the animation's trace resolves the precession)

CSS = """body{font-family:system-ui,sans-serif;max-width:60em;margin:2em auto;padding:0 1em;color:#222}
h1{font-size:1.6em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse}td,th{padding:.2em .8em;text-align:left;border-bottom:1px solid #eee}
.answer{font-size:1.15em;font-weight:600}img{max-width:100%}.note{color:#666;font-size:.9em}
pre.toml{background:#f6f6f6;border:1px solid #ddd;padding:.6em;overflow-x:auto}"""


# the page's parts that analyse the level base over a tilted one (on the axis, thesis 3.3.2)
LEVEL_SECTIONS = ("equilibria and the stable band", "the set-up drawing")


def tilted_note(eq: dict, u: Units) -> str:
    """The page's line over a tilted base (plate.tilt): what answers for which base."""
    return (f"The base is tilted by {u.angle(eq['tilt'])}: the top hovers {u.length(eq['offset'])} off the "
            "axis, downhill. The spin interval, the stability map, the launch and the launch odds are "
            "the tilted base's (started at that equilibrium; the odds' launches aimed at the level hover "
            f"point); the {' and '.join(LEVEL_SECTIONS)} are the level base's (on the axis).")


def build(model, provenance: dict | None = None) -> tuple[str, dict]:
    """The page and the facts it shows (SI numbers, for --json); provenance: the block of
    runtime/ui/provenance.py, shown at the foot of the page (its command rebuilds the page). The
    scene's overrides (model.scene.overrides) are listed on the page; workers load model.ref."""
    from levitron.runtime.physics.apparatus.friction import has_friction
    from levitron.runtime.report import real_launch, rebuild, setup_drawing
    from levitron.runtime.report.figures import figure_3_5
    from levitron.runtime.simulate.setup_shape import setup_of
    from levitron.runtime.scan import stability_map as sc
    from levitron.runtime.scan.physics import slow_period, spins_around
    from levitron.runtime.simulate import animation
    from levitron.runtime.simulate.run import simulate

    scene = model.scene
    overrides = list(scene.overrides)
    u = Units.of_scene(scene)
    P = model.pvals()
    air = "full" in model.parts and has_friction(model) and P.get("k_spin", 0) > 0
    facts: dict = {"scene": scene.name, "units": "SI" if u.si else "dimensionless"}
    parts = [f"<h1>{html.escape(scene.name)}: does the top levitate?</h1>",
             _p(_made(provenance), "note")]
    names = ["equilibria and the band", "spin interval", "a small stability map", "a typical launch"]
    sweep(Path(tempfile.gettempdir()), SCRATCH)     # the scratch folders of killed reports
    with tempfile.TemporaryDirectory(prefix=f"levitron-report-{os.getpid()}-") as tmp, \
            progress.stages(f"report {scene.name}", names + (["launch odds"] if air else []),
                            [1, 1, 3, 2] + ([4] if air else [])) as stage:
        stage(0)
        tmp = Path(tmp)
        rep = Equilibria.of(model)
        eq_json = rep.as_json()
        band = rep.stable_band
        facts["equilibria"], facts["stable_band"] = eq_json["equilibria"], eq_json["stable_band"]
        res = Stability.of(model)          # the answer `levitron stability` prints, its words its own
        iv = res.spin_interval
        facts["spin_interval"] = list(iv) if iv else None
        facts["z_s"] = res.z_s
        hints = rep.reasons
        facts["hints"] = hints
        if iv:
            answer = (f"{u.top(P['m']).capitalize()} hovers at {u.length(facts['z_s'])} and is stable "
                      f"for spin rates {u.rate_span(*iv)}.")
        else:      # what a person can change first (the CLI's `reason`), the technical why below
            why = "; ".join(shown(h, u) for h in hints) or shown(res.reason, u)
            answer = f"No: {u.top(P['m'])} cannot levitate over this plate: {why}."
        parts.append(_p(answer, "answer"))
        if res.equilibrium is not None:             # plate.tilt: say which parts answer for which base
            facts["tilted_base"] = {"equilibrium": res.equilibrium, "level_base": list(LEVEL_SECTIONS)}
            parts.append(_p(tilted_note(res.equilibrium, u), "note"))
        answer_at = len(parts)           # the stated reference values go here, once all are known
        setup = setup_of(model, bands=True)
        parts.append("<h2>The set-up, to scale</h2>")
        parts.append(setup_drawing.drawing(setup, u, f"{scene.name}: a cut through the axis"))
        parts.append(_p(setup_drawing.NOTE, "note"))
        launch_at = len(parts)          # the animation goes here, once the launch has run
        parts.append("<h2>Scene</h2>")
        parts.append(_table(scene_rows(scene, overrides, u, P)))
        if u.note:
            parts.append(_p(u.note, "note"))
        parts.append("<h2>Equilibria and the stable band</h2>")
        roots = ", ".join(f"{u.length(e.z)} ({'vertically stable' if e.vertically_stable else 'unstable'})"
                          for e in rep.equilibria) or "none"
        parts.append(_table([
            (f"equilibria ({THESIS} 3.3.2)", roots),
            ("stable band", f"z {u.length_span(*band.z)}, mass {span(*band.mass, u.mass)}" if band else "none"),
            ("heaviest top that hovers", u.mass(rep.max_mass) if rep.max_mass else "n/a")]))
        parts.append(_png(figure_3_5(model, tmp / "equilibrium.png")))
        stage(1)
        parts.append("<h2>Spin interval (linear stability, thesis 3.3)</h2>")
        parts.append(_p(res.summary(u)))
        full = "full" in model.parts      # the map and the launch run the 12-D model
        if iv and not full:
            facts["map"] = facts["launch"] = None
            facts["not_drawn"] = ('no stability map and no launch: they run the full model, which '
                                  'this scene does not derive; add "full" to model.needs in the scene')
            parts.append(_p(facts["not_drawn"] + ".", "note"))
        if iv and full:
            stage(2)
            spin = math.sqrt(iv[0] * iv[1])
            T = slow_period(model, P["m"], facts["z_s"], spin)
            spins = spins_around(iv, MAP_SPINS)
            tilts = np.linspace(0.005, 0.1, MAP_TILTS)
            m = sc.scan(model, spins, "tilt", tilts, t_end=T, quiet=True)
            facts["map"] = {"spins": spins.tolist(), "tilts": tilts.tolist(), "t_end": T,
                            "fraction_levitating": m.as_json()["fraction_levitating"]}
            parts.append("<h2>A small stability map</h2>")
            parts.append(_p(f"{MAP_SPINS} spins x {MAP_TILTS} tilts, each run one slow period "
                            f"({u.time(T)}); levitating at "
                            f"{sig(100 * facts['map']['fraction_levitating'], 3)}% of the points. "
                            "A sketch: `levitron scan` draws a finer, longer one.", "note"))
            parts.append(_window_figure(model, res, m, u, tmp, facts))
            stage(3)
            # in air the whole flight, to the fall (simulate's default run length); else 3 slow periods
            sim = simulate(model, spin=spin, tilt=LAUNCH_TILT, t_end=None if air else LAUNCH_PERIODS * T,
                           n_out=AIR_SAMPLES if air else 2000)
            run = sim.as_json()
            facts["launch"] = {k: run[k] for k in ("levitating", "t_survived", "max_tilt",
                                                   "max_height_deviation", "energy_drift")}
            facts["launch"]["spin"] = spin
            how = ("the whole flight in air, to the fall" if air else
                   f"{LAUNCH_PERIODS} slow periods")
            parts.append("<h2>A typical launch</h2>")
            parts.append(_p(f"spin {u.rate(spin)} (the geometric mean of the interval), tilt "
                            f"{u.angle(LAUNCH_TILT)}, {how}: "
                            + (f"floats {u.time(run['t_survived'])}, then falls" if air and run["flight"]["fell"]
                               else f"{'levitating' if run['levitating'] else run['status']} for "
                               f"{u.time(run['t_survived'])}")
                            + f"; largest tilt {u.angle(run['max_tilt'])}, "
                            f"energy {'balance residual' if air else 'drift'} {sig(run['energy_drift'], 2)}"))
            sim.plot(tmp / "launch.png")
            parts.append(_png(tmp / "launch.png"))
            data = sim.animation(setup)
            facts["animation"] = {"frames": len(data["t"]), "speed": data["speed"], "precession": data["precession"]}
            parts.insert(launch_at, "<h2>A launch to watch</h2>" + animation.fragment(
                data, f"The typical launch below ({how}), played: spin {u.rate(spin)}, tilt "
                      f"{u.angle(LAUNCH_TILT)}."))
            if air:
                stage(4)
                html_air, facts["air"] = real_launch.section(model, run, u, tmp, _png)
                parts.append(html_air)
        stated = reference.rows(scene, {
            "z_stable": facts["z_s"], "spin_interval": facts["spin_interval"],
            "mass_window": band.mass if band is not None else None,
            "flight_time": (facts.get("air") or {}).get("flight_time")}, u)
        if stated:
            parts.insert(answer_at, "<h3>Beside the stated values</h3>" + _table(stated))
        if facts.get("air"):          # what a maker decides on, right under the answer
            parts.insert(answer_at, _p(facts["air"]["summary"], "answer"))
        block, facts["rebuild"] = rebuild.section(scene, overrides, provenance)
        parts.append(block)
    page = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>levitron report: {html.escape(scene.name)}</title><style>{CSS}</style></head>"
            f"<body>{_cite_first(''.join(parts))}{_provenance(provenance, scene.name)}"
            "</body></html>\n")
    if provenance is not None:
        facts["provenance"] = provenance
    return render(page, "cli", u), facts    # the page tells its reader commands to type, in its units


def _window_figure(model, res, scan, u: Units, tmp: Path, facts: dict) -> str:
    """The map, and below it on the same spins the tilt each spin tolerates with the resonances
    marked (runtime/report/tolerance.py, cached by its inputs; the level, aligned top only): the
    figure and its note; facts["tilt_tolerance"] the curve (SI)."""
    from levitron.runtime.report import tolerance
    if res.equilibrium is not None or res.floquet is not None:        # off the axis: the map alone
        facts["tilt_tolerance"] = None
        scan.plot(tmp / "map.png")
        return _png(tmp / "map.png")
    rs = [r.as_json() for r in res.resonances or ()]      # the answer's (Stability.of)
    curve, cached = tolerance.curve(model, res.spin_interval, res.z_s, rs)
    facts["tilt_tolerance"] = {**curve.as_json(), "cached": cached, "resonances": rs}
    tolerance.figure(scan, curve, tmp / "window.png", u)
    return _png(tmp / "window.png") + _p(
        f"Below the map: the largest launch tilt that floats {u.time(curve.t_end)} (the spin held), "
        f"{curve.spins.size} spins inside the window, a bisection each; the lines mark the resonances among "
        "the linear modes (red: explosive). `«levitron=stability» «tilt_tolerance»` draws the finer curve.",
        "note")


def _cite_first(body: str) -> str:
    """The first citation of the thesis on the page names the work (THESIS_NAME)."""
    return body.replace(f"({THESIS} ", f"({THESIS_NAME}, ", 1) if THESIS_NAME not in body else body


def _made(block: dict | None) -> str:
    """The line under the title: when, by which version, from which scene (its hash)."""
    if block is None:
        return ""
    when = str(block.get("time", "")).replace("T", " ").replace("+00:00", " UTC")
    digest = str(block.get("scene_hash", ""))[:12]
    return (f"levitron {block.get('version')}, {when}; scene hash {digest}"
            + (f"; «set» {' '.join(block['overrides'])}" if block.get("overrides") else ""))


def _shown(v, unit: str, u: Units) -> str:
    """A scene key's value in the scene's units: lengths in cm/mm, masses in g (SI); a bare number
    in a dimensionless scene (no SI unit, not even one the human units do not know)."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return str(v)
    if unit == "m":
        return u.length(v)
    if unit == "kg":
        return u.mass(v)
    if unit == "s":        # as written ("120 s", not "2 min 0 s"): a scene key, not an answer
        return u.value(v, "s", 6)
    if not u.si:
        return u.value(v, unit, 6) if unit in SI_SYMBOLS or not unit else sig(v, 6)
    return f"{sig(v, 6)} {unit}".rstrip()


def _key_units(section: str, table: dict) -> dict[str, str]:
    """key -> SI unit of a scene section (scene/keys.py's key tables, the plate kinds' own)."""
    from levitron.scene.keys import FIELD_KEYS, TOP_KEYS
    if section == "plate":
        kind = plates.KINDS.get(table.get("kind"))
        return {k.name: k.unit for k in kind.keys} if kind is not None else {}
    return {k.name: k.unit for k in {"top": TOP_KEYS, "field": FIELD_KEYS}.get(section, ())}


def scene_rows(scene, overrides, u: Units, P: dict) -> list[tuple[str, str]]:
    """The scene as its author wrote it: one row per key (`plate.radius`, with its unit; the keys
    --set changed marked), the scene file, and the top's magnetic moment (thesis 2.2.11 needs only
    the product mu rho where the scene gives murho)."""
    from levitron.scene.keys import SCENE_KEYS
    changed = {o.split("=", 1)[0].strip() for o in overrides}
    top_units = {k.name: k.unit for k in SCENE_KEYS}
    rows = [("file", f"{scene.path}" + (f" with «set» {', '.join(overrides)}" if overrides else ""))]

    def add(key: str, v, unit: str) -> None:
        rows.append((key + (" («set»)" if key in changed else ""), _shown(v, unit, u)))

    def walk(prefix: str, section: str, table: dict) -> None:
        units = _key_units(section, table)
        for k, v in table.items():
            if isinstance(v, dict):
                walk(f"{prefix}{k}.", section, v)
            elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
                for i, part in enumerate(v):
                    walk(f"{prefix}{k}.{i}.", "plate", part)
            else:
                add(prefix + k, v, units.get(k, ""))

    for k in ("g", "temperature"):
        if k in scene.data:
            add(k, scene.data[k], top_units.get(k, ""))
    for section in ("top", "plate", "field"):
        if isinstance(scene.data.get(section), dict):
            walk(f"{section}.", section, scene.data[section])
    if "moment" not in scene.data.get("top", {}):
        rows.append(("the top's magnetic moment mu", "not given: the plate's murho = mu rho is the only "
                     "product the dynamics sees (thesis 2.2.11)"))
    else:
        rows.append(("the top's magnetic moment mu", _shown(P["mu"], "A m^2", u)))
    return rows


def _provenance(block: dict | None, name: str) -> str:
    """The foot of the page: how it was made (the command that rebuilds it), by which version, from
    which scene file (with its hash), when."""
    if block is None:
        return f'<p class="note">levitron report {html.escape(name)}</p>'
    rows = [(k.replace("_", " "), ", ".join(v) if isinstance(v, list) else v)
            for k, v in block.items() if v not in (None, [], "")]
    return "<h2>Provenance</h2>" + _table(rows)
