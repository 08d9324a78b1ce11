"""`levitron stability SCENE`: the spin interval of linear stability at the stable height.

Two routes (thesis 3.3; runtime/physics/stability/analysis.py): "discriminant" (exact rational arithmetic on the ray
polynomial L and a Sturm count of N(t)) and "eigenvalues" (the generated full model's Jacobian at the
relative equilibrium). spin_interval is the discriminant route's; both are reported. Rates in rad/s,
with Hz and rpm beside. Inside the interval, the low-order resonances among the linear modes
(runtime/physics/stability/resonances.py, docs/resonances.md); with --spin W the linear modes at W
(runtime/physics/stability/modes.py: frequency, sense, energy sign).
"""
from __future__ import annotations

from levitron.runtime.ui.human import Units, lines
from levitron.runtime.ui.plain_text import shown
from levitron.runtime.physics.stability.answer import Stability
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
    """runtime/physics/stability/answer.py's Stability, its as_json() (and the plot's path)."""
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
    moving, with its `truncation` in `equilibrium` (runtime/physics/stability/off_axis_truncation.py)."""
    from levitron.runtime.physics.stability.off_axis_truncation import checked
    return answer.with_record(checked(model, answer.record()))


def _modes(model, answer, spin: float) -> dict:
    """runtime/physics/stability/modes.py's Modes at `spin` for the top analysed (its mass), as JSON; with the
    magnet tilted over a level axisymmetric base the turning frame's (runtime/physics/stability/rotating_modes.py),
    elsewhere off the axis {"spin", "given": False, "reason"}: the one line why none are given."""
    from levitron.runtime.physics.stability.modes import Modes
    from levitron.runtime.physics.stability import rotating_modes as rm
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
        return [shown(md["reason"], u)]
    if md.get("frame") == "turning":
        from levitron.runtime.physics.stability.rotating_modes import lines as turning_lines
        return turning_lines(md, u)
    out = [f"modes at {u.rate(md['spin'])}" + ("" if md["stable"] else " (not all stable)") + ":"]
    for m in md["modes"]:
        energy = {1: "energy +", -1: "energy - (Krein)"}.get(m["krein"]) or \
            f"unstable (grows at {u.value(m['growth_rate'], '1/s', 3)})"
        out.append(f"  {m['name']}: {u.rate(m['frequency'])}, {_SENSE[m['sense']]}, {energy}")
    return out


def human(r: dict, scene=None) -> str:
    """The answer's own plain view (Stability.lines: the interval first, then where, the thesis's
    approximations, the resonances), with the command's additions: the modes, the launch tilt
    tolerated, the plot's file."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    more = [*(_mode_lines(r["modes"], u) if r.get("modes") else []),
            *(plain_lines(r["tilt_tolerance"], u) if r.get("tilt_tolerance") else [])]
    return lines(*Stability.from_json(r, u).lines(u, more), f"plot: {r['plot']}" if r.get("plot") else "")
