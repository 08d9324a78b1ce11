"""`levitron scan SCENE`: a stability map over spin and tilt, mass or height (docs/contract.md `scan`;
thesis fig. 3.8 after Gans et al.). The map is runtime/scan/stability_map.py's (grid: grid.py), the
answer runtime/scan/scan_answer.py's Scan (its as_json()); --out and --save are its actions."""
from __future__ import annotations

import re

from levitron.runtime.scan import stability_map as sc
from levitron.runtime.errors import UserError
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.human import Units, lines
from levitron.runtime.integrate.budget import check_tolerance
from levitron.runtime.integrate.methods import DEFAULT, FULL_MODEL_METHODS, lookup
from levitron.runtime.simulate import trajectory_file
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.scan.grid import check_axis, check_grid_size, parse_range, pick_axis
from levitron.runtime.scan.runners import CONNECT_TIMEOUT_S
from levitron.runtime.scan.scan_answer import runs, scan_lines, stopped_early  # noqa: F401  (runs, stopped_early: scripts')
from levitron.runtime.cli.commands.common import model_of

NAME = "scan"
HELP = ("stability map: does the top stay up, over --spin LO:HI:N and one of --tilt, --mass, --height "
        "(one nonlinear run per point, chunks of points per C call; local processes or a dask cluster)")


# "LO:HI:N" with a negative LO ("-0.3:0.3:5") must not be taken for an option: argparse's own
# negative-number test (a private attribute, present in 3.8-3.13) is widened to ranges; where it is
# missing, `--height=-0.3:0.3:5` still works.
_NEGATIVE_RANGE = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?(:.*)?$")
EXAMPLE = 'levitron scan thesis_stable --spin 200:3500:20 --tilt 0.005:0.1:10 --out out/map.png'


def add_arguments(parser) -> None:
    if hasattr(parser, "_negative_number_matcher"):
        parser._negative_number_matcher = _NEGATIVE_RANGE
    parser.add_argument("--spin", default=None, metavar="LO:HI:N",
                        help="spin rates, rad/s: N evenly spaced values from LO to HI")
    parser.add_argument("--tilt", default=None, metavar="LO:HI:N", help="second axis: initial tilt, rad")
    parser.add_argument("--mass", default=None, metavar="LO:HI:N",
                        help="second axis: top mass, kg (each starts at its own hover height; no re-derivation)")
    parser.add_argument("--height", default=None, metavar="LO:HI:N",
                        help="second axis: initial vertical displacement as a FRACTION of the hover "
                             "height, z0 = z_s (1 + h), |h| < 0.5 (scenes may be dimensionless); "
                             "e.g. --height -0.3:0.3:7")
    parser.add_argument("--base-tilt", type=float, default=sc.BASE_TILT, metavar="TH",
                        help=f"initial tilt (rad) of --mass and --height scans (default {sc.BASE_TILT}: "
                             "an upright top on the axis stays there by symmetry)")
    parser.add_argument("--t-end", type=float, default=None, metavar="T",
                        help=f"run length per point, s (default: {sc.PERIODS} periods of the slowest "
                             "motion at the relative equilibrium, the transverse precession/wobble mode "
                             "of the linearisation or the vertical bounce; ~10.5 s for the thesis plate "
                             "with a 51.5 g top)")
    parser.add_argument("--integrator", default=DEFAULT, metavar="NAME",
                        help=f"one of: {', '.join(FULL_MODEL_METHODS)} (default {DEFAULT})")
    parser.add_argument("--tol", type=float, default=1e-9, help="tolerance of adaptive integrators (default 1e-9)")
    parser.add_argument("--step", type=float, default=None, metavar="H",
                        help="step of fixed-step integrators, s (default: 1/100 of the fastest period)")
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help="local worker processes (default: every usable core; 1: serial); the grid "
                             "is dealt into chunks, each run by one C call")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="run on a dask.distributed cluster (e.g. tcp://host:8786; start it with "
                             "`dask scheduler` and `dask worker ADDRESS` on each machine, which needs "
                             "this package and the scene at the same path); needs the `cluster` "
                             "extra: pip install 'levitron[cluster]'")
    parser.add_argument("--scheduler-timeout", type=float, default=None, metavar="S",
                        help="with --scheduler: how long to wait for the scheduler's answer and for a "
                             f"worker, s (default {CONNECT_TIMEOUT_S:g})")
    parser.add_argument("--out", default=None, metavar="FILE.png", help="draw the map to FILE.png")
    parser.add_argument("--save", default=None, metavar="FILE",
                        help="write the map's points to FILE.csv, .npz or .parquet, one row a point: spin, "
                             "the other axis, levitating, t_survived, status; each file names its columns' "
                             "units (CSV: a first line '# units: ...'; .npz and Parquet: a 'units' entry)")


def run(args) -> dict:
    if args.spin is None:
        raise UserError("pass --spin LO:HI:N (rad/s, or rad per time unit in a dimensionless scene); "
                        "`levitron stability SCENE` gives the linear interval")
    axis, spec = pick_axis({"tilt": args.tilt, "mass": args.mass, "height": args.height})
    check_grid_size(args.spin, spec, axis)
    spins = parse_range(args.spin, "spin")
    others = parse_range(spec, axis)
    check_axis(axis, others)
    lookup(args.integrator)   # an unknown name is a one-line UserError
    check_tolerance(args.integrator, args.tol)      # before the model: no compile to wait for first
    if args.out is not None:
        check_plot_path(args.out, "--out")
    if args.save is not None:
        trajectory_file.check_path(args.save)
    model = model_of(args)
    res = sc.scan(model, spins, axis, others, t_end=args.t_end,
                  integrator=args.integrator, tol=args.tol, workers=args.workers,
                  scheduler=args.scheduler, base_tilt=args.base_tilt, h=args.step,
                  quiet=args.quiet, scheduler_timeout=args.scheduler_timeout)
    out = res.as_json()
    out["out"] = None
    if args.out:
        res.plot(args.out)                      # the Figure; the answer names the file written
        out["out"] = str(check_plot_path(args.out, "--out"))
    if args.save is not None:
        out["saved"] = res.save(args.save, flag="--save")
    return out


def human(r: dict, scene=None) -> str:
    """Answer first: where it levitates (the runs of spins per row, "cannot hover" apart from
    "falls"), then the linear interval beside (runtime/scan/scan_answer.py scan_lines, the answer's
    own words)."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    return lines(*worded(scan_lines(r, u), u, None))
