"""`levitron simulate SCENE`: one trajectory from the stable hover height (docs/contract.md): the
answer is runtime/simulate/simulation.py's Simulation (its as_json()); --plot, --save and --animate
are its actions, and a full-model run without air friction adds `linear`."""
from __future__ import annotations

from levitron.runtime.errors import UserError
from levitron.runtime.words import si_unit
from levitron.runtime.simulate import animation, trajectory_file
from levitron.runtime.simulate.start import linear_context
from levitron.runtime.ui.human import Units, lines
from levitron.runtime.integrate.methods import DEFAULT, FULL_MODEL_METHODS, lookup
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.simulate.run import simulate
from levitron.runtime.simulate.simulation import Simulation
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
                        "energy, L_z, L_n, tilt and the spin omega_3; each file names its columns' units "
                        "(CSV: a first line '# units: t=s, ...'; .npz and Parquet: a 'units' entry)")
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


def human(r: dict, scene=None) -> str:
    """The answer's own plain view (Simulation.lines: does it stay up, for how long; then the
    launch, the excursions, the invariants), with what the command added (linear, files)."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    return lines(*Simulation.from_json(r, u).lines(u, scene))
