"""The words of a Stability (runtime/physics/stability/answer.py): its plain view, line by line,
from its fields, in the scene's display units. What `levitron stability` prints, what the answer's
`message`, repr and notebook table say, and what the report places all come from `lines` here.
"""
from __future__ import annotations

import math

from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plain_text import kept, shown
from levitron.runtime.words import render

SHOWN = 5      # resonances listed in the plain view, the strongest first (all in the JSON)


def _pair(iv):
    """An interval as (lo, hi), an open upper end (inf, or JSON null) as None."""
    if iv is None:
        return None
    hi = iv[1]
    return float(iv[0]), None if hi is None or math.isinf(hi) else float(hi)


def agreement(disc, eig) -> str:
    """", both routes agree to 4e-12" where both routes give an interval."""
    a, b = (_pair(ivs[0]) if ivs else None for ivs in (disc, eig))
    if not a or not b or None in a or None in b:
        return ""
    rel = max(abs(x - y) / max(abs(x), 1e-300) for x, y in zip(a, b))
    return f", both routes agree to {sig(max(rel, 1e-16), 1)}"


def head(st, u: Units) -> str:
    """"spin_interval: 459.6-2740 rad/s (...)", the answer first."""
    iv = st.spin_interval
    fq = st.floquet
    if fq is not None:
        return (f"spin_interval: {u.rate_span(*iv)}" if iv else "spin_interval: none") + (
            f" (route Floquet: the moment {u.angle(fq['moment_tilt'])} off the axis; the aligned top's, "
            f"by the eigenvalues: {u.rate_span(*fq['aligned_interval'])})")
    return (f"spin_interval: {u.rate_span(*iv)}{agreement(st.discriminant, st.eigenvalues)}" if iv
            else "spin_interval: none: no spin rate stabilises this top")


def where(st, u: Units) -> str:
    """Which top the interval is for: the scene's, or with a height the top that hovers there."""
    if not st.z_s:
        return ""
    if not st.height_given:
        return f"at z_s = {u.length(st.z_s)} for {u.top(st.mass)}"
    return (f"at z = {u.length(st.z_s)} («height») for the top that hovers there, "
            f"of mass {u.mass(st.mass)} (the scene's top is {u.mass(st.scene_mass)})")


def summary(st, u: Units) -> str:
    """One sentence: "stable for spin 459.6-2740 rad/s (...) at z_s = 10.65 cm for the 51.5 g top",
    or "no stable spin interval: " and why."""
    reason = shown(kept(st.reason, st.said.get("reason"), st.units), u)
    if st.spin_interval is None:
        return f"no stable spin interval: {reason or 'no stable hover height'}"
    text = f"stable for spin {u.rate_span(*st.spin_interval)} {where(st, u)}".rstrip()
    return text + (f" ({reason})" if reason else "")


def _periodic(e: dict, u: Units) -> str:
    """The periodic orbit's start: how far off the axis, its period, the axis' angle there."""
    return (f"the steady motion is periodic (the moment turns with the spin): period "
            f"{u.time(e['period'])} at the window's middle, the top {u.length(e['offset'], 2)} off "
            f"the centre and {u.length(abs(e['rise']), 2)} {'higher' if e['rise'] >= 0 else 'lower'} "
            f"than the aligned top, its axis {u.angle(math.acos(min(1.0, e['axis'][2])))} from the "
            "plate's")


def equilibrium(e: dict, u: Units) -> str:
    """Where the top hovers over a tilted base: off the centre (downhill or uphill), higher or
    lower than over the level base (along the plate's axis)."""
    if e.get("periodic"):
        return _periodic(e, u)
    rounding = 64 * 2.0 ** -52 * e["z_level"]      # what Newton's last step leaves
    if e["offset"] <= rounding and abs(e["rise"]) <= rounding:
        return "the top hovers on the axis, as over the level base"
    side = "downhill" if e["downhill"] >= 0 else "uphill"
    updown = "higher" if e["rise"] >= 0 else "lower"
    return (f"the top hovers {u.length(e['offset'], 2)} off the centre, {side}, "
            f"{u.length(abs(e['rise']), 2)} {updown} (base tilted {u.angle(e['tilt'])}; its axis "
            f"{u.angle(math.acos(min(1.0, e['axis'][2])))} from the plate's)")


def moment_line(t: dict, u: Units) -> str:
    """"the magnet aligned with the axis to 2.9 deg (0.05 rad)", or why not given."""
    b = t.get("max_moment_tilt")
    if b is None:
        return "" if t.get("max_base_tilt") is None else f"magnet: {shown(t['moment_tolerance']['note'], u)}"
    return (f"the magnet aligned with the axis to {sig(math.degrees(b), 3)} deg ({sig(b, 3)} rad; "
            "beyond it no spin stabilises the top's periodic motion, route Floquet)")


def level_line(t: dict, u: Units) -> str:
    """"level to 0.0822 deg: 0.14 mm across 10 cm (the plate's largest length)"."""
    if t["max_base_tilt"] is None:
        return "level_tolerance: none: the top has no stable spin interval even on a level base"
    why = {"fold": "beyond it the equilibrium itself is gone",
           "instability": "beyond it no spin stabilises the top"}.get(t["limited_by"], "")
    return (f"level to {sig(math.degrees(t['max_base_tilt']), 3)} deg ({sig(t['max_base_tilt'], 4)} rad): "
            f"{u.length(t['height_difference'], 2)} across {u.length(t['length'], 3)} (the plate's "
            f"largest length){'; ' + why if why else ''}")


def interval(ivl, u: Units) -> str:
    """A spin interval; one without an upper end as "above LO"."""
    lo, hi = _pair(ivl)
    return f"above {u.rate(lo)}" if hi is None else u.rate_span(lo, hi)


def approximations(ap: dict, u: Units) -> str:
    """Thesis 3.3.22/3.3.23, labelled as what they are: an estimate for another top (the one of
    mass m(z_c) at z_c), for comparison; shown only beside an interval."""
    if ap.get("sigma1") is None:
        return ""
    if ap["sigma1"] >= ap["sigma2"]:    # small-g21 estimates beyond their range: no interval at all
        return (f"for comparison: the thesis's approximations (eqs. 3.3.22/3.3.23) do not apply to "
                f"{u.top(ap['mass_at_z_c'])} at z_c = {u.length(ap['z_c'])}: they give sigma_1 = "
                f"{u.rate(ap['sigma1'])} above sigma_2 = {u.rate(ap['sigma2'])}")
    return (f"for comparison, not this top's interval: the thesis's approximations (eqs. 3.3.22/3.3.23) "
            f"for {u.top(ap['mass_at_z_c'])} at z_c = {u.length(ap['z_c'])}: "
            f"{u.rate_span(ap['sigma1'], ap['sigma2'])}")


def resonance_lines(rs, u: Units) -> list[str]:
    """"resonances: strongest: 3-wave, explosive, at 213.1 rad/s (...)" and one line each (rs: the
    Resonances or their JSON)."""
    if rs is None:
        return []
    if not rs:
        return ["resonances: none of order 3 or 4 inside the spin interval"]
    rs = [r if isinstance(r, dict) else r.as_json() for r in rs]
    r = rs[0]
    out = [f"resonances: {len(rs)} inside the spin interval; strongest: {r['order']}-wave, "
           f"{'explosive' if r['explosive'] else 'bounded'}, at {u.rate(r['spin'])} ({r['relation']})"]
    for r in rs[:SHOWN]:
        out.append(f"  {u.value(r['spin'], 'rad/s')}: {r['order']}-wave, {r['relation']}, m-balance "
                   f"{r['m_balance']}, {'explosive' if r['explosive'] else 'bounded'}")
    if len(rs) > SHOWN:
        out.append(f"  ... {len(rs) - SHOWN} more (weaker) in «json»")
    return out


def note_lines(st, notes, u: Units) -> list[str]:
    """The answer's notes, the truncation warnings (runtime/physics/field/truncation.py: the level
    tolerance's, the base's and the magnet's, and the equilibrium's off the axis) as "warning: " lines."""
    t = st.level_tolerance or {}
    blocks = (t.get("truncation"), (t.get("moment_tolerance") or {}).get("truncation"),
              (st.equilibrium or {}).get("truncation"))
    warn = {b["warning"] for b in blocks if b and b.get("warning")}
    return [f"warning: {shown(n, u)}" if n in warn or render(n, "api", st.units) in warn else shown(n, u)
            for n in notes or ()]


def lines(st, u: Units, more=()) -> list[str]:
    """The plain view of the Stability `st`: the interval first, then where, the tolerances, the
    reason, the thesis's approximations, the resonances, `more` (what a command adds: the modes,
    the launch tilt tolerated), the notes; in the display units `u`."""
    iv = st.spin_interval
    reason = kept(st.reason, st.said.get("reason"), st.units)
    t = st.level_tolerance
    further = [_pair(v) for v in (st.discriminant or [])[1:]] if iv else []
    return [line for line in (
        head(st, u),
        equilibrium(st.equilibrium, u) if st.equilibrium else "",
        level_line(t, u) if t else "",
        moment_line(t, u) if t else "",
        where(st, u),
        f"vertical stiffness there: U'' = mu Phi_3 = {u.value(st.stiffness, 'N/m')} (thesis 3.3.3)"
        if st.stiffness is not None else "",
        "further intervals: " + ", ".join(interval(v, u) for v in further) if further else "",
        f"reason: {shown(reason, u)}" if reason else "",
        approximations(st.approximations or {}, u) if iv else "",
        *resonance_lines(st.resonances, u), *more,
        *note_lines(st, kept(st.notes, st.said.get("notes"), st.units), u), u.note) if line]
