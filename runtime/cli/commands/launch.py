"""`levitron launch SCENE`: launch odds by Monte Carlo over launch conditions and manufacturing spread
(docs/contract.md `launch`; runtime/scan/launch_odds.py)."""
from __future__ import annotations


from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.scan import launch_inputs as li
from levitron.runtime.scan import launch_summary as ls
from levitron.runtime.scan.launch_answer import (  # noqa: F401  (launch_input, launches_line: the other commands')
    launch_input, launch_lines, launches_line, temperature_matters as _temperature_matters)
from levitron.runtime.simulate import trajectory_file
from levitron.runtime.errors import UserError
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.human import Units, lines
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.cli.commands.common import model_of, scene_of

NAME = "launch"
HELP = ("launch odds by Monte Carlo: the probability (a 95 percent Wilson interval) that a launch floats at "
        "least --success-time, the flight times, and which input matters most")
EXAMPLE = "levitron launch thesis_air --n 200 --t-end 60 --workers 2 --out out/launch.png"


# what --help says of each input's default (launch_odds.defaults: scaled to the scene)
DEFAULT_TEXT = {"spin": "normal about the geometric mean of the stable interval, sd 10 %%",
                "tilt": "uniform:0,0.02 rad", "tilt_azimuth": "uniform:0,2pi rad",
                "offset": "normal:0,(1 %% of z_s) m", "velocity": "normal:0,(1 %% of sqrt(g z_s)) m/s",
                "mass": "a relative sd of 0.2 %%", "strength": "a relative sd of 0.5 %%",
                "temperature": "the scene's temperature, degC",
                **{a.name: a.default_text.replace("%", "%%") for a in li.APPARATUS}}


def add_launch_arguments(parser) -> None:
    """Every flag of a launch Monte Carlo (launch, optimize --maximize launch-odds, trim): the
    inputs' distributions, n, seed, the success criterion, the integrator and the workers."""
    for name in li.ALL_INPUTS:
        flag = "--" + name.replace("_", "-")
        if flag == "--temperature":          # the common --temperature sets the scene's own
            flag = "--temperature-spread"
        unit = {"mass": "the mass in kg, or rel:... a relative spread, e.g. rel:normal:0,0.002 or rel:0.2%%",
                "strength": "a factor on the magnets, e.g. normal:1,0.005, or rel:... relative, e.g. rel:0.5%%",
                **{a.name: f"{a.unit}; needs {a.scene_key} in the scene, e.g. --set {a.scene_key}=0"
                   for a in li.APPARATUS}}.get(name, li.INPUT_UNITS[name])
        parser.add_argument(flag, dest=f"dist_{name}", default=None, metavar="DIST",
                            help=f"{name} ({unit}): normal:MEAN,SD, uniform:LO,HI or a number (default: "
                                 f"the scene's [launch] table, else {DEFAULT_TEXT[name]})")
    parser.add_argument("--n", type=int, default=None,
                        help=f"number of launches (default: [launch] n, else {mc.DEFAULT_N})")
    parser.add_argument("--seed", type=int, default=None,
                        help=f"seed of the sampler (default: [launch] seed, else {mc.DEFAULT_SEED})")
    parser.add_argument("--success-time", type=float, default=None, metavar="T",
                        help="success: floating at least T s (default: --t-end; in air half the spin "
                             "decay time; else 3 slow periods)")
    parser.add_argument("--t-end", type=float, default=None, metavar="T",
                        help="run length of each launch, s (default: the success time)")
    parser.add_argument("--integrator", default="auto", metavar="NAME", help="dop853, vern9 or auto")
    parser.add_argument("--tol", type=float, default=mc.LAUNCH_TOL,
                        help=f"tolerance (default {mc.LAUNCH_TOL:g}: the loosest whose odds stay well inside their "
                             "interval; the contract in the documentation)")
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help="local worker processes (default: every usable core, serial below 64 launches; "
                             "1: serial; at most the usable cores)")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS", help="a dask scheduler")


def launch_request(args, scene) -> mc.Request:
    """The launch Monte Carlo the flags ask for, over the scene's [launch] table."""
    if args.scheduler is not None and args.workers not in (None, 1):
        raise UserError("pass either --workers N (local processes) or --scheduler ADDRESS (dask), not both")
    given = {k: getattr(args, f"dist_{k}") for k in li.ALL_INPUTS if getattr(args, f"dist_{k}") is not None}
    return mc.Request.of(scene.data.get("launch", {}), given, n=args.n, seed=args.seed,
                         success_time=args.success_time, t_end=args.t_end, integrator=args.integrator,
                         tol=args.tol, workers=args.workers, scheduler=args.scheduler)


def add_arguments(parser) -> None:
    add_launch_arguments(parser)
    parser.add_argument("--out", default=None, metavar="FILE.png", help="draw the flight-time histogram")
    parser.add_argument("--save", default=None, metavar="FILE",
                        help="write every launch to FILE.csv, .npz or .parquet: its sampled inputs (mass "
                             "in kg and mu as run, strength as the factor 1 + d), hover height, verdict, "
                             "floats (0/1) and flight time, one row per launch; each file names its columns' "
                             "units (CSV: a first line '# units: ...'; .npz and Parquet: a 'units' entry)")


def saved_block(path, rows: int, u: Units, columns) -> dict:
    """The JSON's `saved`: the file and each column's unit in the scene's units (its meaning:
    docs/contract.md `launch --save`)."""
    return {"path": str(path), "rows": rows,
            "columns": {k: u.named(ls.LAUNCH_UNITS[k]) for k in columns}}


def run(args) -> dict:
    if args.out is not None:
        check_plot_path(args.out, "--out")
    if args.save is not None:
        trajectory_file.check_path(args.save)
    scene = scene_of(args)
    request = launch_request(args, scene)
    model = model_of(args)
    odds = request.run(model, quiet=args.quiet)
    out = odds.as_json()        # the JSON stays its size: the launches' table goes to --save
    out["saved"] = None
    if odds.reason:                 # the top cannot hover: no launch ran, nothing to save or draw
        out["out"] = None
        return out
    if args.save is not None:
        out["saved"] = saved_block(odds.save(args.save, flag="--save"), len(odds.launches["launch"]),
                                   odds.units, tuple(odds.launches))
    out["out"] = None
    if args.out:
        odds.plot(args.out)                     # the Figure; the answer names the file written
        out["out"] = str(check_plot_path(args.out, "--out"))
    return out


def human(r: dict, scene=None) -> str:
    """Answer first: the odds with their interval; the flight times; what matters most
    (runtime/scan/launch_answer.py launch_lines, the answer's own words)."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    return lines(*worded(launch_lines(r, u, scene), u, None))
