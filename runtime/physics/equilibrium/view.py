"""The words of an Equilibria (runtime/physics/equilibrium/answer.py): its plain view, line by line, from
its fields, in the scene's display units: what `levitron equilibrium` prints, and what the answer's
message, repr and notebook table say.
"""
from __future__ import annotations

from levitron.runtime.physics.equilibrium.bands import edge_note
from levitron.runtime.ui.human import Units, span
from levitron.runtime.ui.plain_text import kept, shown
from levitron.runtime.ui.reference import MODIFIED


def _kind(e) -> str:
    return "marginal" if e.marginal else "vertically stable" if e.vertically_stable else "vertically unstable"


def roots(eq, u: Units) -> str:
    """"equilibria: 10.65 cm (vertically stable; ...), 4.1 cm (vertically unstable)"."""
    ref = (eq.reference or {}).get("z_stable")     # only for the scene it describes
    out = []
    for e in eq.equilibria:
        kind = _kind(e)
        if ref and e.vertically_stable:
            kind += f"; {ref['source']}: {u.length(ref['value'])}"
            if not ref.get("describes", True):
                kind += f" ({MODIFIED})"
        out.append(f"{u.length(e.z)} ({kind})")
    return f"equilibria: {', '.join(out) if out else 'none'}"


def band_line(eq, u: Units) -> str:
    """"stable_band: z 9.948-11.02 cm, mass 49.4-52.49 g", with the adiabatic band beside."""
    band, adia = eq.stable_band, eq.adiabatic_band
    if band is None:
        return "stable_band: none (no height where a spin can stabilise the top)"
    line = f"stable_band: z {u.length_span(*band.z)}, mass {span(*band.mass, u.mass)}"
    note = edge_note(band, eq.z_range is not None)
    line += f" ({note})" if note else ""
    if adia is not None:
        line += f"   (Berry-Simon's adiabatic band: {u.length_span(*adia.z)})"
    return line


def _singular(eq, u: Units) -> str:
    poles = [f"{s.kind} at {u.length(s.z)}" + (f"-{u.length(s.z_end)}" if s.z_end not in (None, s.z)
                                                 and s.z_end != float("inf") else "")
             for s in eq.singularities or ()]
    return f"singular (not equilibria): {', '.join(poles)}" if poles else ""


def _stiffness(eq, u: Units) -> str:
    """The vertical stiffness U'' = mu Phi_3 (thesis 3.3.3) at each vertically stable equilibrium:
    what `optimize «constrain» stiffness>=K` speaks of."""
    stable = [e for e in eq.equilibria if e.vertically_stable]
    if not stable:
        return ""
    return ("vertical stiffness U'' = mu Phi_3 (thesis 3.3.3): " +
            ", ".join(f"{u.value(e.stiffness, 'N/m')} at {u.length(e.z)}" for e in stable))


def _z_c_role(eq) -> str:
    """What z_c is to this plate: where the stable band starts (the thesis's plate), or only the
    height of the heaviest top that hovers, where the band starts higher up."""
    band = eq.stable_band
    if band is not None and abs(band.z[0] - eq.z_c) <= 1e-6 * eq.z_c:
        return "where the band starts"
    return "the heaviest top's height" + (", below the band" if band is not None else "")


def reason(eq) -> str | None:
    """The reasons in one sentence, as written (markers), None where the top can levitate."""
    reasons = kept(eq.reasons, eq.said.get("reasons"), eq.units)
    return "; ".join(reasons) if reasons else None


def lines(eq, u: Units) -> list[str]:
    """The plain view: the equilibria (the scene's stated value beside), the band, the reason, the
    stiffness, z_c and the heaviest top, the note."""
    why = reason(eq)
    return [line for line in (
        roots(eq, u),
        band_line(eq, u),
        _singular(eq, u),
        f"reason: {shown(why, u)}" if why else "",
        _stiffness(eq, u),
        f"top {u.mass(eq.mass)}; z_c {u.length(eq.z_c)} ({_z_c_role(eq)}); the heaviest top "
        f"that hovers: {u.mass(eq.max_mass)}" if eq.z_c is not None else "",
        shown(eq.note, u) if eq.note else "",
        u.note) if line]
