"""`levitron equilibrium SCENE`: vertical equilibria, z_c, the largest mass, the stable band.

Thesis 3.3.1-3.3.3 and the stable band of docs/contract.md: the answer is runtime/physics/equilibria.py's
Equilibria (its as_json(), and `plot` with --plot); beside the band the adiabatic (Berry-Simon) one, never instead.
"""
from __future__ import annotations

from levitron.runtime.physics.bands import edge_note
from levitron.runtime.physics.equilibria import Equilibria
from levitron.runtime.ui.human import Units, lines, restate, span
from levitron.runtime.ui.reference import MODIFIED
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.cli.commands.common import model_of

NAME = "equilibrium"
HELP = "vertical equilibria, z_c, the largest mass, and the band where a spin can stabilise the top"
EXAMPLE = 'levitron equilibrium thesis --plot out/thesis_equilibrium.png'


def add_arguments(parser) -> None:
    parser.add_argument("--plot", metavar="FILE", default=None,
                        help="also draw the equilibrium condition (thesis fig. 3.5) into FILE (.png)")


def run(args) -> dict:
    if args.plot is not None:
        check_plot_path(args.plot)
    model = model_of(args)
    out = Equilibria.of(model).as_json()
    if args.plot:
        from pathlib import Path

        from levitron.runtime.report.figures import figure_3_5
        out["plot"] = str(figure_3_5(model, Path(args.plot)))
    return out


def _stiffness(equilibria, u: Units) -> str:
    """The vertical stiffness U'' = mu Phi_3 (thesis 3.3.3) at each vertically stable equilibrium:
    what `optimize --constrain stiffness>=K` speaks of."""
    stable = [e for e in equilibria if e["vertically_stable"]]
    if not stable:
        return ""
    return ("vertical stiffness U'' = mu Phi_3 (thesis 3.3.3): " +
            ", ".join(f"{u.value(e['stiffness'], 'N/m')} at {u.length(e['z'])}" for e in stable))


def _z_c_role(r: dict) -> str:
    """What z_c is to this plate: where the stable band starts (the thesis's plate), or only the
    height of the heaviest top that hovers, where the band starts higher up."""
    band = r.get("stable_band")
    if band and abs(band["z"][0] - r["z_c"]) <= 1e-6 * r["z_c"]:
        return "where the band starts"
    return "the heaviest top's height" + (", below the band" if band else "")


def human(r: dict, scene=None) -> str:
    """Answer first: the equilibria (with the scene's stated value beside), then the band, the reason."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    ref = (r.get("reference") or {}).get("z_stable")     # only for the scene it describes
    roots = []
    for e in r["equilibria"]:
        kind = "vertically stable" if e["vertically_stable"] else "vertically unstable"
        if e.get("marginal"):
            kind = "marginal"
        if ref and e["vertically_stable"]:
            kind += f"; {ref['source']}: {u.length(ref['value'])}"
            if not ref.get("describes", True):
                kind += f" ({MODIFIED})"
        roots.append(f"{u.length(e['z'])} ({kind})")
    band, adia = r["stable_band"], r["adiabatic_band"]
    band_line = "stable_band: none (no height where a spin can stabilise the top)"
    if band:
        band_line = (f"stable_band: z {u.length_span(*band['z'])}, mass {span(*band['mass'], u.mass)}")
        note = edge_note(band, r.get("z_range") is not None)
        band_line += f" ({note})" if note else ""
        if adia:
            band_line += f"   (Berry-Simon's adiabatic band: {u.length_span(*adia['z'])})"
    poles = [f"{s['kind']} at {u.length(s['z'])}" + (f"-{u.length(s['z_end'])}" if s.get("z_end") not in
                                                        (None, s["z"]) else "")
             for s in r.get("singularities") or []]
    return lines(
        f"equilibria: {', '.join(roots) if roots else 'none'}",
        band_line,
        f"singular (not equilibria): {', '.join(poles)}" if poles else "",
        f"reason: {restate(r['reason'], u)}" if r.get("reason") else "",
        _stiffness(r["equilibria"], u),
        f"top {u.mass(r['mass'])}; z_c {u.length(r['z_c'])} ({_z_c_role(r)}); the heaviest top "
        f"that hovers: {u.mass(r['max_mass'])}" if r.get("z_c") is not None else "",
        r.get("note", ""),
        u.note,
        f"plot: {r['plot']}" if r.get("plot") else "")
