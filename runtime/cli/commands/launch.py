"""`levitron launch SCENE`: launch odds by Monte Carlo over launch conditions and manufacturing spread
(docs/contract.md `launch`; runtime/scan/launch_odds.py)."""
from __future__ import annotations

from pathlib import Path

from levitron.runtime.scan import launch_odds as mc
from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import Units, lines, sig
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.cli.commands.common import model_of, scene_of

NAME = "launch"
HELP = ("launch odds by Monte Carlo: the probability (a 95 percent Wilson interval) that a launch floats at "
        "least --success-time, the flight times, and which input matters most")
EXAMPLE = "levitron launch thesis_air --n 200 --t-end 60 --workers 2 --out out/launch.png"


def add_arguments(parser) -> None:
    for name in mc.INPUTS:
        flag = "--" + name.replace("_", "-")
        if flag == "--temperature":          # the common --temperature sets the scene's own
            flag = "--temperature-spread"
        parser.add_argument(flag, dest=f"dist_{name}", default=None, metavar="DIST",
                            help=f"{name}: normal:MEAN,SD, uniform:LO,HI or a number "
                                 "(default: the scene's [launch] table, else runtime/scan/launch_odds.py's)")
    parser.add_argument("--n", type=int, default=None, help="number of launches (default 1000)")
    parser.add_argument("--seed", type=int, default=None, help="seed of the sampler (default 0)")
    parser.add_argument("--success-time", type=float, default=None, metavar="T",
                        help="success: floating at least T s (default: the run length; in air tau/2)")
    parser.add_argument("--t-end", type=float, default=None, metavar="T",
                        help="run length of each launch, s (default: the success time)")
    parser.add_argument("--integrator", default="auto", metavar="NAME", help="dop853, vern9 or auto")
    parser.add_argument("--tol", type=float, default=1e-8, help="tolerance (default 1e-8)")
    parser.add_argument("--workers", type=int, default=1, metavar="N", help="local worker processes")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS", help="a dask scheduler")
    parser.add_argument("--out", default=None, metavar="FILE.png", help="draw the flight-time histogram")


def run(args) -> dict:
    if args.workers is None or args.workers < 1:
        raise UserError(f"--workers {args.workers} must be at least 1 (1 = serial)")
    if args.scheduler is not None and args.workers != 1:
        raise UserError("pass either --workers N (local processes) or --scheduler ADDRESS (dask), not both")
    if args.out is not None:
        check_plot_path(args.out, "--out")
    scene = scene_of(args)
    given, table = mc.table_settings(scene.data.get("launch", {}))
    given.update({k: getattr(args, f"dist_{k}") for k in mc.INPUTS if getattr(args, f"dist_{k}") is not None})
    pick = lambda flag, key, default: flag if flag is not None else table.get(key, default)  # noqa: E731
    model = model_of(args)
    ref = str(Path(scene.path).resolve()) if scene.path is not None else args.scene
    out = mc.monte_carlo(model, ref, args.set, given, n=pick(args.n, "n", 1000),
                         seed=pick(args.seed, "seed", 0),
                         success_time=pick(args.success_time, "success_time", None),
                         t_end=pick(args.t_end, "t_end", None), integrator=args.integrator,
                         tol=args.tol, workers=args.workers, scheduler=args.scheduler, quiet=args.quiet)
    out["scene"] = scene.name
    if args.out:         # the report's histogram: the censored runs' bar labelled (runtime/report/real_launch.py)
        from levitron.runtime.report.real_launch import histogram
        out["out"] = str(histogram(out, Path(args.out), Units.of_scene(scene), scene.name))
    else:
        out["out"] = None
    return out


def launch_input(name: str, spec: str, u: Units) -> str:
    """One input's distribution (the JSON's spec, SI) in the scene's units: "spin 1122 rad/s, sd
    112.2 rad/s (normal)", "tilt 0-0.02 rad (uniform)", "mass +0 %, sd 0.2 % (normal)", "temperature
    20 degC"; a dimensionless scene's lengths and speeds bare."""
    si_unit = mc.INPUT_UNITS[name]
    show = {"m": u.length, "1": lambda v: f"{sig(100 * v, 3)} %",
            "degC": lambda v: f"{sig(v)} degC"}.get(si_unit, lambda v: u.value(v, si_unit))
    d = mc.parse_dist(name, spec)
    if d.kind == "normal":
        mean = show(d.a) if si_unit != "1" else ("+" if d.a >= 0 else "") + show(d.a)
        return f"{name} {mean}, sd {show(d.b)} (normal)"
    if d.kind == "uniform":
        return f"{name} {show(d.a)} to {show(d.b)} (uniform)"
    return f"{name} {show(d.a)}"


def _temperature_matters(spec: str, scene) -> bool:
    """Whether the launches' temperature says anything: it is spread, or the scene's magnets have a
    temperature coefficient (without one, and fixed, it changes nothing: not shown, which also
    keeps degC out of a dimensionless scene that does not model temperature)."""
    if mc.parse_dist("temperature", spec).spread or scene is None:
        return True
    data = scene.data
    return any(float(data.get(t, {}).get("temperature_coefficient", 0.0)) != 0.0 for t in ("plate", "top"))


def human(r: dict, scene=None) -> str:
    """Answer first: the odds with their interval; the flight times; what matters most."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    lo, hi = r["probability_ci95"]
    ft = r["flight_time"]
    rank = [f"{e['input']} ({sig(100 * e['effect'], 3)} points of success rate across its quintiles"
            f"{'' if e['effect'] > e['noise'] else ', within the noise of this sample'})"
            for e in r["ranking"][:3]]
    outcomes = ", ".join(f"{k} {v}" for k, v in r["outcomes"].items())
    cens = f"; {ft['censored']} still up at the end of the run" if ft["censored"] else ""
    at = lambda t: (">= " if t >= r["t_end"] * (1 - 1e-12) else "") + u.time(t)  # noqa: E731 (censored)
    return lines(
        f"launch odds: {sig(100 * r['probability'], 3)}% of {r['n']} launches float at least "
        f"{u.time(r['success_time'])} (95% Wilson interval {sig(100 * lo, 3)}-{sig(100 * hi, 3)}%)",
        f"flight time: median {at(ft['median'])}, quartiles {at(ft['q1'])} - {at(ft['q3'])}"
        f" (runs of {u.time(r['t_end'])}{cens})",
        f"matters most: {'; '.join(rank)}" if rank else "no input has a spread",
        f"outcomes: {outcomes}",
        "launches: " + ", ".join(launch_input(k, v, u) for k, v in r["inputs"].items()
                                 if k != "temperature" or _temperature_matters(v, scene)),
        f"seed {r['seed']}, {r['integrator']} at tol {sig(r['tol'], 2)}",
        u.note,
        f"histogram: {r['out']}" if r.get("out") else "")
