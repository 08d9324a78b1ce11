"""`levitron simulate SCENE`: one trajectory from the stable hover height (docs/contract.md)."""
from __future__ import annotations

from ..errors import UserError
from ..integrators_table import DEFAULT, METHODS, lookup
from ..plotting import check_plot_path
from ..simulate import simulate
from .common import model_of

NAME = "simulate"
HELP = ("one trajectory from the stable hover height: does the top stay levitating, for how long, "
        "energy drift, work and wall time")


def add_arguments(parser) -> None:
    parser.add_argument("--spin", type=float, default=None, metavar="W",
                        help="spin rate about the symmetry axis, rad/s (see `levitron stability`)")
    parser.add_argument("--tilt", type=float, default=0.0, metavar="TH", help="initial tilt of the axis, rad")
    parser.add_argument("--offset", type=float, default=0.0, metavar="DX", help="initial offset in x, m")
    parser.add_argument("--t-end", type=float, default=1.0, metavar="T", help="run length, s (default 1)")
    parser.add_argument("--integrator", default=DEFAULT, metavar="NAME",
                        help=f"one of: {', '.join(METHODS)} (default {DEFAULT})")
    parser.add_argument("--tol", type=float, default=1e-9, help="tolerance of adaptive integrators (default 1e-9)")
    parser.add_argument("--step", type=float, default=None, metavar="H",
                        help="step of fixed-step integrators, s (default: 1/100 of the fastest period)")
    parser.add_argument("--box", type=float, default=None, metavar="B",
                        help="half-width of the box the top must stay in, m (default: z_s / 2)")
    parser.add_argument("--part", default="full", choices=("full", "reduced"), help="model part (default full)")
    parser.add_argument("--n-out", type=int, default=2000, help="number of output samples (default 2000)")
    parser.add_argument("--plot", default=None, metavar="FILE", help="draw height, radial offset and tilt to FILE.png")


def run(args) -> dict:
    if args.spin is None:
        raise UserError("pass --spin W (rad/s); `levitron stability SCENE` gives the stable spin interval")
    if args.t_end is None or not args.t_end > 0:
        raise UserError(f"--t-end {args.t_end} must be a positive run length in s, e.g. --t-end 1")
    lookup(args.integrator)   # an unknown name is a one-line UserError
    if args.plot is not None:
        check_plot_path(args.plot)
    model = model_of(args)
    return simulate(model, spin=args.spin, tilt=args.tilt, offset=args.offset, t_end=args.t_end,
                    integrator=args.integrator, tol=args.tol, box=args.box, plot=args.plot,
                    part=args.part, h=args.step, n_out=args.n_out)
