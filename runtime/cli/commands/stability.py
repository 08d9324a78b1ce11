"""`levitron stability SCENE`: the spin interval of linear stability at the stable height.

Two routes (thesis 3.3; runtime/physics/stability.py): "discriminant" (exact rational arithmetic on the ray
polynomial L and a Sturm count of N(t)) and "eigenvalues" (the generated full model's Jacobian at the
relative equilibrium). spin_interval is the discriminant route's; both are reported. Rates in rad/s,
with Hz and rpm beside. Inside the interval, the low-order resonances among the linear modes
(runtime/physics/resonances.py, docs/resonances.md); with --spin W the linear modes at W
(runtime/physics/modes.py: frequency, sense, energy sign).
"""
from __future__ import annotations

import math

from levitron.runtime.ui.human import Units, lines, restate, sig
from levitron.runtime.physics.stability_answer import Stability
from levitron.runtime.scan.tilt_tolerance import plain_lines
from levitron.runtime.errors import UserError
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.ui.validate import spin_rate
from levitron.runtime.cli.commands.common import model_of

NAME = "stability"
HELP = "spin interval of linear stability at the stable height (two routes), thesis approximations"
EXAMPLE = 'levitron stability thesis_stable --spin 1000'


def add_arguments(parser) -> None:
    parser.add_argument("--height", type=float, default=None, metavar="Z",
                        help="analyse the top that hovers at this height (m): its mass is m(Z) = "
                             "-mu Phi_2(Z)/g, not the scene's (default: the scene's top at its "
                             "vertically stable equilibrium)")
    parser.add_argument("--level-tolerance", action="store_true",
                        help="also how level the base must be: the largest base tilt at which a "
                             "stable spin interval still exists (rad; needs the tilted model: "
                             "plate.tilt in the scene or --set plate.tilt=0)")
    parser.add_argument("--spin", type=float, default=None, metavar="W",
                        help="also the linear modes at this spin (rad/s): each mode's frequency, its "
                             "sense of rotation relative to the spin and its energy (Krein) sign")
    parser.add_argument("--tilt-tolerance", action="store_true",
                        help="also the largest launch tilt each spin tolerates, by simulation (40 spins "
                             "inside the window, the spin held, a bisection each: seconds), with the "
                             "resonances marked")
    parser.add_argument("--plot", default=None, metavar="FILE",
                        help="with --level-tolerance: draw the spin interval against the base's "
                             "tilt up to the tolerance; with --tilt-tolerance: the tolerated tilt "
                             "against the spin (.png, .pdf, .svg)")


def run(args) -> dict:
    """runtime/physics/stability_answer.py's Stability, its as_json() (and the plot's path)."""
    plot = getattr(args, "plot", None)
    level = getattr(args, "level_tolerance", False)     # (a Namespace built by hand may lack it)
    tilts = getattr(args, "tilt_tolerance", False)
    if plot is not None:
        check_plot_path(plot)
        if level == tilts:
            raise UserError("--plot draws the spin interval against the base's tilt (add "
                            "--level-tolerance) or the tolerated launch tilt against the spin (add "
                            "--tilt-tolerance): give one of them")
    model = model_of(args)
    spin = getattr(args, "spin", None)
    if spin is not None:            # the modes' own check, before the analysis (--height: stability_of's)
        spin_rate(spin)
    answer = Stability.of(model, height=args.height, level_tolerance=level)
    answer = _checked(model, answer)
    out = answer.as_json()
    if spin is not None:
        out["modes"] = _modes(model, answer, spin)
    if tilts:
        from levitron.runtime.scan.tilt_tolerance import tilt_tolerance
        if args.height is not None:
            raise UserError("--tilt-tolerance launches the scene's own top: leave out --height")
        curve = tilt_tolerance(model, answer.spin_interval, answer.z_s, out.get("resonances") or [])
        out["tilt_tolerance"] = curve.as_json()
        if plot is not None:
            curve.plot(plot)                    # the Figure; the answer names the file written
            out["plot"] = str(check_plot_path(plot))
            plot = None
    if plot is not None:
        if answer.plot(plot) is not None:       # the Figure; the answer names the file written
            out["plot"] = str(check_plot_path(plot))
    return out


def _checked(model, answer: Stability) -> Stability:
    """Over a tilted base or with the magnet tilted: the answer at the field order where it stops
    moving, with its `truncation` in `equilibrium` (runtime/physics/off_axis_truncation.py)."""
    from dataclasses import replace

    from levitron.runtime.physics.off_axis_truncation import checked
    return replace(answer, result=checked(model, answer.result))


def _modes(model, answer, spin: float) -> dict:
    """runtime/physics/modes.py's Modes at `spin` for the top analysed (its mass), as JSON; with the
    magnet tilted over a level axisymmetric base the turning frame's (runtime/physics/rotating_modes.py),
    elsewhere off the axis {"spin", "given": False, "reason"}: the one line why none are given."""
    from levitron.runtime.physics.modes import Modes
    from levitron.runtime.physics import rotating_modes as rm
    if not answer.z_s:
        raise UserError("--spin: the top has no stable hover height, so no linear modes")
    p = model.with_params({"m": answer.mass}) if answer.mass else model.p
    if rm.off_axis(model, p):
        why = rm.refusal(model, p)
        if why is not None:
            return {"spin": spin, "given": False, "reason": why}
        return rm.turning_modes(model, spin, p).as_json()
    return Modes.of(model, spin, answer.z_s, answer.spin_interval, p).as_json()


_SENSE = {1: "with the spin", -1: "against the spin", 0: "vertical"}


def _mode_lines(md: dict, u: Units) -> list[str]:
    """"modes at 1000 rad/s (...):" then one line a mode (the turning frame's, or why none)."""
    if md.get("given") is False:
        return [restate(md["reason"], u)]
    if md.get("frame") == "turning":
        from levitron.runtime.physics.rotating_modes import lines as turning_lines
        return turning_lines(md, u)
    out = [f"modes at {u.rate(md['spin'])}" + ("" if md["stable"] else " (not all stable)") + ":"]
    for m in md["modes"]:
        energy = {1: "energy +", -1: "energy - (Krein)"}.get(m["krein"]) or \
            f"unstable (grows at {u.value(m['growth_rate'], '1/s', 3)})"
        out.append(f"  {m['name']}: {u.rate(m['frequency'])}, {_SENSE[m['sense']]}, {energy}")
    return out


SHOWN = 5      # resonances listed in the plain view, the strongest first (all in the JSON)


def _resonance_lines(rs, u: Units) -> list[str]:
    """"resonances: strongest: 3-wave, explosive, at 213.1 rad/s (...)" and one line each."""
    if rs is None:
        return []
    if not rs:
        return ["resonances: none of order 3 or 4 inside the spin interval"]
    r = rs[0]
    out = [f"resonances: {len(rs)} inside the spin interval; strongest: {r['order']}-wave, "
           f"{'explosive' if r['explosive'] else 'bounded'}, at {u.rate(r['spin'])} ({r['relation']})"]
    for r in rs[:SHOWN]:
        out.append(f"  {u.value(r['spin'], 'rad/s')}: {r['order']}-wave, {r['relation']}, m-balance "
                   f"{r['m_balance']}, {'explosive' if r['explosive'] else 'bounded'}")
    if len(rs) > SHOWN:
        out.append(f"  ... {len(rs) - SHOWN} more (weaker) in --json")
    return out


def _agreement(routes) -> str:
    a, b = routes.get("discriminant"), routes.get("eigenvalues")
    if not a or not b:
        return ""
    rel = max(abs(x - y) / max(abs(x), 1e-300) for x, y in zip(a, b))
    return f", both routes agree to {sig(max(rel, 1e-16), 1)}"


def _where(r: dict, u: Units) -> str:
    """Which top the interval is for: the scene's, or with --height the top that hovers there."""
    if not r.get("z_s"):
        return ""
    if not r.get("height_given"):
        return f"at z_s = {u.length(r['z_s'])} for {u.top(r['mass'])}"
    return (f"at z = {u.length(r['z_s'])} (--height) for the top that hovers there, "
            f"of mass {u.mass(r['mass'])} (the scene's top is {u.mass(r['scene_mass'])})")


def _periodic(e: dict, u: Units) -> str:
    """The periodic orbit's start: how far off the axis, its period, the axis' angle there."""
    return (f"the steady motion is periodic (the moment turns with the spin): period "
            f"{u.time(e['period'])} at the window's middle, the top {u.length(e['offset'], 2)} off "
            f"the centre and {u.length(abs(e['rise']), 2)} {'higher' if e['rise'] >= 0 else 'lower'} "
            f"than the aligned top, its axis {u.angle(math.acos(min(1.0, e['axis'][2])))} from the "
            "plate's")


def _equilibrium(e: dict, u: Units) -> str:
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


def _moment_line(t: dict) -> str:
    """"the magnet aligned with the axis to 2.9 deg (0.05 rad)", or why not given."""
    b = t.get("max_moment_tilt")
    if b is None:
        return "" if t.get("max_base_tilt") is None else f"magnet: {t['moment_tolerance']['note']}"
    return (f"the magnet aligned with the axis to {sig(math.degrees(b), 3)} deg ({sig(b, 3)} rad; "
            "beyond it no spin stabilises the top's periodic motion, route Floquet)")


def _level_tolerance(t: dict, u: Units) -> str:
    """"level to 0.0822 deg: 0.14 mm across 10 cm (the plate's largest length)"."""
    if t["max_base_tilt"] is None:
        return "level_tolerance: none: the top has no stable spin interval even on a level base"
    why = {"fold": "beyond it the equilibrium itself is gone",
           "instability": "beyond it no spin stabilises the top"}.get(t["limited_by"], "")
    return (f"level to {sig(math.degrees(t['max_base_tilt']), 3)} deg ({sig(t['max_base_tilt'], 4)} rad): "
            f"{u.length(t['height_difference'], 2)} across {u.length(t['length'], 3)} (the plate's "
            f"largest length){'; ' + why if why else ''}")


def _interval(ivl, u: Units) -> str:
    """A spin interval; one without an upper end (JSON null: inf) as "above LO"."""
    lo, hi = ivl
    return f"above {u.rate(lo)}" if hi is None else u.rate_span(lo, hi)


def _approximations(ap: dict, u: Units) -> str:
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


def _notes(r: dict) -> list[str]:
    """The answer's notes, the truncation warnings (runtime/physics/truncation.py: the level
    tolerance's, the base's and the magnet's, and the equilibrium's off the axis) as "warning: " lines."""
    t = r.get("level_tolerance") or {}
    blocks = (t.get("truncation"), (t.get("moment_tolerance") or {}).get("truncation"),
              (r.get("equilibrium") or {}).get("truncation"))
    warn = {b["warning"] for b in blocks if b and b.get("warning")}
    return [f"warning: {n}" if n in warn else n for n in r.get("notes") or []]


def human(r: dict, scene=None) -> str:
    """Answer first: the spin interval (rad/s, Hz, rpm), then where, the thesis's approximations."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    iv = r.get("spin_interval")
    head = (f"spin_interval: {u.rate_span(*iv)}{_agreement(r['routes'])}" if iv
            else "spin_interval: none: no spin rate stabilises this top")
    fq = r.get("floquet")
    if fq is not None:
        head = (f"spin_interval: {u.rate_span(*iv)}" if iv else "spin_interval: none") + (
            f" (route Floquet: the moment {u.angle(fq['moment_tilt'])} off the axis; the aligned top's, "
            f"by the eigenvalues: {u.rate_span(*fq['aligned_interval'])})")
    approx = _approximations(r.get("approximations") or {}, u) if iv else ""
    more = r["all_intervals"].get("discriminant", [])[1:] if iv else []
    return lines(
        head,
        _equilibrium(r["equilibrium"], u) if r.get("equilibrium") else "",
        _level_tolerance(r["level_tolerance"], u) if r.get("level_tolerance") else "",
        _moment_line(r["level_tolerance"]) if r.get("level_tolerance") else "",
        _where(r, u),
        f"vertical stiffness there: U'' = mu Phi_3 = {u.value(r['stiffness'], 'N/m')} (thesis 3.3.3)"
        if r.get("stiffness") is not None else "",
        "further intervals: " + ", ".join(_interval(ivl, u) for ivl in more) if more else "",
        f"reason: {restate(r['reason'], u)}" if r.get("reason") else "",
        approx, *_resonance_lines(r.get("resonances"), u),
        *(_mode_lines(r["modes"], u) if r.get("modes") else []),
        *(plain_lines(r["tilt_tolerance"], u) if r.get("tilt_tolerance") else []), *_notes(r), u.note,
        f"plot: {r['plot']}" if r.get("plot") else "")
