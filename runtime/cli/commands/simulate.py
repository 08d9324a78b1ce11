"""`levitron simulate SCENE`: one trajectory from the stable hover height (docs/contract.md): the
answer is runtime/simulate/simulation.py's Simulation (its as_json()); --plot, --save and --animate
are its actions, and a full-model run without air friction adds `linear`."""
from __future__ import annotations

from levitron.runtime.errors import UserError
from levitron.runtime.words import si_unit
from levitron.runtime.simulate import animation, trajectory_file
from levitron.scene.plates.symmetry import symmetry
from levitron.runtime.simulate.start import linear_context
from levitron.runtime.ui.human import Units, duration, lines, restate, sig
from levitron.runtime.integrate.methods import DEFAULT, FULL_MODEL_METHODS, lookup
from levitron.runtime.integrate.verdict import UP, stopped_early
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.simulate.run import simulate
from levitron.runtime.simulate.rotations import DEFAULT_AZIMUTH
from levitron.runtime.simulate.start import DEFAULT_TILT
from levitron.runtime.cli.commands.common import model_of

NAME = "simulate"
HELP = ("one trajectory from the stable hover height: does the top stay levitating, for how long, "
        "energy drift, work and wall time")
EXAMPLE = 'levitron simulate thesis_stable --spin 1000 --tilt 0.01 --offset 0.001 --t-end 5 --plot out/run.png'


def add_arguments(parser) -> None:
    parser.add_argument("--spin", type=float, default=None, metavar="W",
                        help="spin rate about the symmetry axis, rad/s (see `levitron stability`)")
    parser.add_argument("--tilt", type=float, default=None, metavar="TH",
                        help=f"initial tilt of the axis, rad (default {DEFAULT_TILT}: a launch with tilt "
                        "0 and offset 0 lies on the invariant set and tests no stability)")
    parser.add_argument("--tilt-azimuth", type=float, default=DEFAULT_AZIMUTH, metavar="AZ",
                        help="direction of the tilt, rad from +x towards +y (default pi/2: towards +y)")
    parser.add_argument("--offset", type=float, default=0.0, metavar="DX", help="initial offset in x, m")
    parser.add_argument("--t-end", type=float, default=None, metavar="T",
                        help="run length, s (default: 3 periods of the slowest motion at the hover "
                        "height, as `levitron scan`'s; in air 5 spin decay times: the run ends when "
                        "the top falls)")
    parser.add_argument("--integrator", default=DEFAULT, metavar="NAME",
                        help=f"one of: {', '.join(FULL_MODEL_METHODS)} (default {DEFAULT})")
    parser.add_argument("--tol", type=float, default=1e-9, help="tolerance of adaptive integrators (default 1e-9)")
    parser.add_argument("--step", type=float, default=None, metavar="H",
                        help="step of fixed-step integrators, s (default: 1/100 of the fastest period)")
    parser.add_argument("--box", type=float, default=None, metavar="B",
                        help="half-width of the box the top must stay in, m (default: z_s / 2)")
    parser.add_argument("--part", default="full", choices=("full", "reduced"), help="model part (default full)")
    parser.add_argument("--n-out", type=int, default=2000, help="number of output samples (default 2000)")
    parser.add_argument("--plot", default=None, metavar="FILE", help="draw height, radial offset and tilt to FILE.png")
    parser.add_argument("--save", default=None, metavar="FILE",
                        help="write the samples (--n-out of them) to FILE.csv, .npz or .parquet: t, every state, "
                        "energy, L_z, L_n, tilt and the spin omega_3")
    parser.add_argument("--animate", default=None, metavar="FILE",
                        help="an animation of the run: FILE.html (a page that plays offline), .gif or .mp4")


def run(args) -> dict:
    if args.spin is None:
        raise UserError(f"pass --spin W ({si_unit('rad/s')}); "
                        "`levitron stability SCENE` gives the stable spin interval")
    lookup(args.integrator)   # an unknown name is a one-line UserError
    if args.plot is not None:
        check_plot_path(args.plot)
    animate = getattr(args, "animate", None)
    if animate is not None:
        animation.check_path(animate)
        if args.part != "full":
            raise UserError("--animate draws the whole top: drop --part reduced (the reduced model has no tilt)")
    model = model_of(args)
    if args.save is not None:
        trajectory_file.check_path(args.save)
    sim = simulate(model, spin=args.spin, tilt=args.tilt, offset=args.offset, t_end=args.t_end,
                   integrator=args.integrator, tol=args.tol, box=args.box, part=args.part, h=args.step,
                   n_out=args.n_out, azimuth=args.tilt_azimuth)
    r = sim.as_json()
    r["plot"] = None
    if args.plot:
        sim.plot(args.plot)                     # the Figure; the answer names the file written
        r["plot"] = str(check_plot_path(args.plot))
    if args.save is not None:
        r["saved"] = sim.save(args.save, flag="--save")
    if animate is not None:
        r["animation"] = sim.animate(animate, f"{model.scene.name}: a launch at "
                                     f"{Units.of_scene(model.scene).rate(args.spin)}")
    if args.part == "full" and "flight" not in r:      # in air the flight line gives the limits
        r["linear"] = linear_context(model, model.p, r["z_s"], args.spin)
    return r


def flight_line(r: dict, u: Units) -> str:
    """A flight in air as a person says it: "floats 1 min 57 s; falls at 457 rad/s, 0.8 s after the
    spin crosses the linear limit" (runtime/physics/friction.py)."""
    fl = r["flight"]
    iv = fl["spin_interval"]
    if iv is None:
        limits = "no spin interval of linear stability at this height: no spin holds the top"
    else:
        limits = f"linear limits {u.rate_span(iv[0], iv[1])}"
    pred = (f"adiabatic prediction {u.time(fl['t_cross'])} (tau ln(omega_0 / sigma_lo))"
            if fl["t_cross"] else "")
    above = ""
    if fl["launched_above"]:
        above = (f"launched above the upper limit: the spin decays into the interval after "
                 f"{u.time(fl['t_enter'])}; "
                 + ("the top fell before that" if fl["fell_before_interval"] else "the top survived that"))
    if fl["fell"]:
        after = fl["after_cross"]
        when = "" if after is None or fl["fell_before_interval"] else (
            f", {u.time(abs(after))} {'after' if after >= 0 else 'before'} the spin crosses the lower limit")
        head = f"floats {u.time(fl['flight_time'])}; falls at {u.rate(fl['fall_spin'])}{when}"
    elif stopped_early(r["status"]):     # no verdict: neither "still floating" nor a fall
        head = (f"no verdict: the run stopped early ({r['status']}) after {u.time(r['t_survived'])} "
                f"of {u.time(r['t_end'])}, spin then {u.rate(fl['spin_final'])}")
    elif past_its_window(r):             # up at the end, but its spin left the window (verdict.py past_window)
        head = (f"no verdict: up after {u.time(r['t_survived'])} (the whole run), but its spin "
                f"{u.rate(fl['spin_final'])} is past the stable window")
    else:
        head = (f"still floating after {u.time(r['t_survived'])} (the whole run), spin now "
                f"{u.rate(fl['spin_final'])}")
    taus = ", ".join(f"{name} {u.time(v)}" for name, v in fl["decay_times"].items() if v)
    return lines(head, f"{limits}; {pred}" if pred else limits, above, f"air friction: decay times {taus}")


def linear_line(r: dict, u: Units) -> str:
    """What linear theory says of this spin (runtime/simulate/start.py linear_context): inside the
    stable interval, or outside it with the e-folding time of a tilt, so that a run shorter than a
    few of them is not read as a verdict."""
    lin = r.get("linear")
    if not lin:
        return ""
    spin, iv = u.value(r["spin"]["rad_s"], "rad/s"), lin["spin_interval"]
    if lin.get("refused"):
        return f"linear theory: none ({lin['refused'].split(': ')[0]})"
    if iv is None:
        return "linear theory: no spin holds this top at its hover height (`levitron stability` says why)"
    span = u.rate_span(*iv).split(" (")[0]
    if lin["inside"]:
        return f"linear theory: {spin} lies inside the stable interval {span} (thesis 3.3.9-3.3.16)"
    side = "below" if r["spin"]["rad_s"] < iv[0] else "above"
    te = lin["e_folding_time"]
    grow = ("" if te is None else f": a tilt grows by e every {u.time(te)} "
            f"({sig(r['t_end'] / te, 2)} e-foldings in this run)")
    return f"linear theory: {spin} lies {side} the stable interval {span}{grow}"


def _not_conserved(name: str, scene) -> str:
    """" (not conserved: ...)" for L_z over a plate without axial symmetry (scene/plates/symmetry.py)."""
    if name != "L_z" or scene is None:
        return ""
    sym = symmetry(scene.data["plate"], scene.params)
    return "" if "L_z" in sym.conserved else f" (not conserved by a plate of {sym.name} symmetry)"


def past_its_window(r: dict) -> bool:
    """A run that reached t_end with its spin below the window (runtime/integrate/verdict.py
    past_window): no verdict, not "untested" (a launch on the invariant set, which tests nothing)."""
    on_invariant_set = r.get("part") == "reduced" or (r["tilt"] == 0 and r["offset"] == 0)
    return r["levitating"] is None and r["status"] == UP and not on_invariant_set


def human(r: dict, scene=None) -> str:
    """Answer first: does it stay up, for how long; then the launch, the excursions, the invariants."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    if r["levitating"] is None:
        word = ("no verdict" if stopped_early(r["status"]) else "no verdict (past its stable window)"
                if past_its_window(r) else "untested")
        up = f"{word}: {r['untested']}"
    else:
        up = "yes" if r["levitating"] else f"no ({r['status']}: {r['message']})"
    dev = r.get("conserved_max_deviation") or {}
    if "flight" in r:
        inv = [f"energy balance {sig(dev.get('energy_balance'), 2)}",
               f"L_n against exp(-t/tau) {sig(dev.get('L_n_decay'), 2)}"]
    else:
        inv = [f"energy {sig(r['energy_drift'], 2)}"]
        inv += [f"{k} {sig(dev[k], 2)}{_not_conserved(k, scene)}" for k in ("L_z", "L_n")
                if dev.get(k) is not None]
    azi = r.get("tilt_azimuth")
    toward = f" toward azimuth {u.angle(azi)}" if azi is not None else ""
    return lines(
        flight_line(r, u) if "flight" in r else "",
        f"levitating: {up}, {u.time(r['t_survived'])} of flight (of {u.time(r['t_end'])}), "
        f"{duration(r['wall_s'])} of wall time",
        linear_line(r, u),
        f"launch: spin {u.rate(r['spin']['rad_s'])}, tilt {u.angle(r['tilt'])}"
        f"{' (the default perturbation)' if r.get('tilt_default') else ''}{toward}, offset "
        f"{u.length(r['offset'])}, from z_s = {u.length(r['z_s'])}",
        f"largest excursion: height {u.length(r['max_height_deviation'])}, radial "
        f"{u.length(r['max_radial_offset'])}, tilt {u.angle(r['max_tilt'])}",
        f"invariants, largest relative deviation over the run: {', '.join(inv)}",
        restate(r["note"], u) if r.get("note") else "",
        f"integrator: {r['integrator']} ({r['backend']}"
        f"{', chosen by auto' if r.get('integrator_requested') == 'auto' else ''}), "
        f"{sig(r['rhs_evals'], 6)} rhs evaluations",
        u.note,
        f"plot: {r['plot']}" if r.get("plot") else "",
        f"samples: {r['saved']}" if r.get("saved") else "",
        f"animation: {r['animation']}" if r.get("animation") else "")
