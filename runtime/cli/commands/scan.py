"""`levitron scan SCENE`: a stability map over spin and tilt, mass or height (docs/contract.md `scan`;
thesis fig. 3.8 after Gans et al.). The map is runtime/scan/stability_map.py's (grid: grid.py), the
answer runtime/scan/scan_answer.py's Scan (its as_json()); --out and --save are its actions."""
from __future__ import annotations

import re

from levitron.runtime.scan import stability_map as sc
from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import Units, duration, lines, sig
from levitron.runtime.integrate import verdict
from levitron.runtime.integrate.methods import DEFAULT, FULL_MODEL_METHODS, lookup
from levitron.runtime.integrate.verdict import NO_HOVER
from levitron.runtime.simulate import trajectory_file
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.scan.grid import check_axis, check_grid_size, parse_range, pick_axis
from levitron.runtime.scan.runners import CONNECT_TIMEOUT_S
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
                             "the other axis, levitating, t_survived, status")


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


def _axis_value(axis: str, v: float, u: Units) -> str:
    if axis == "tilt":
        return u.angle(v)
    if axis == "mass":
        return u.mass(v)
    return f"{sig(v, 3)} z_s"


def runs(flags) -> list[tuple[int, int]]:
    """The maximal runs of consecutive True entries, as (first, last) index pairs."""
    out, start = [], None
    for i, f in enumerate(list(flags) + [False]):
        if f and start is None:
            start = i
        elif not f and start is not None:
            out.append((start, i - 1))
            start = None
    return out


def _stays_up(spins, up, u: Units) -> str:
    """"stays up for spin 671.4-2557 rad/s (...)": every run of levitating spins as it is, several
    where the map has gaps ("200-400 rad/s (...) and 900 rad/s (...)")."""
    parts = [u.rate(spins[a]) if a == b else u.rate_span(spins[a], spins[b]) for a, b in runs(up)]
    return "stays up for spin " + " and ".join(parts)


def stopped_early(status) -> list[str]:
    """The statuses of the runs that stopped early: no verdict (runtime/integrate/verdict.py)."""
    return [s for s in status if verdict.stopped_early(s)]


def _row(axis: str, v, spins, up, status, u: Units) -> str:
    """One row of the summary: where it stays up, "cannot hover" where no run was made (no
    equilibrium at that mass or height), "falls at every spin" where every run fell, and the runs
    that stopped early (step budget, ...) apart: no verdict, never "falls"."""
    skipped = sum(s == NO_HOVER for s in status)
    if skipped == len(spins):
        return f"  {axis} {_axis_value(axis, v, u)}: cannot hover (no equilibrium: not simulated)"
    stopped = stopped_early(status)
    ran = len(spins) - skipped
    why = ", ".join(sorted(set(stopped)))
    head = f"  {axis} {_axis_value(axis, v, u)}: "
    if len(stopped) == ran:
        return head + f"no verdict at any spin: {ran} of {ran} runs stopped early ({why})"
    where = (_stays_up(spins, up, u) if any(up) else
             "falls at every spin" + (" that gave a verdict" if stopped else ""))
    tail = f"; no verdict: {len(stopped)} of {ran} runs stopped early ({why})" if stopped else ""
    return head + f"{where} ({sum(up)} of {ran - len(stopped)}){tail}"


def _tilted_line(eq: dict | None, u: Units) -> str:
    """Over a tilted base: where the runs start (runtime/scan/stability_map.py tilted_sites)."""
    if not eq:
        return ""
    where = (f"the top's equilibrium there, {u.length(eq['offset'])} off the axis" if eq.get("position")
             else "each top's equilibrium there")
    return f"base tilted by {u.angle(eq['tilt'])}: every run starts at {where}"


def human(r: dict, scene=None) -> str:
    """Answer first: where it levitates (the runs of spins per row, "cannot hover" apart from
    "falls"), then the linear interval beside."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    axis = r["axes"][1]
    spins = r["grid"]["spin"]
    status = r.get("status") or [["" for _ in r["grid"][axis]] for _ in spins]
    rows = [_row(axis, v, spins, [bool(r["levitating"][i][j]) for i in range(len(spins))],
                 [status[i][j] for i in range(len(spins))], u)
            for j, v in enumerate(r["grid"][axis])]
    iv = r.get("spin_interval")
    n_stopped = len(stopped_early([s for row in status for s in row]))
    return lines(
        f"levitating at {sig(100 * r['fraction_levitating'], 3)}% of {r['points']} points "
        f"(spin x {axis}, {u.time(r['t_end'])} each)"
        + (f"; {n_stopped} runs stopped early without a verdict (JSON status)" if n_stopped else ""),
        *rows,
        f"linear spin interval: {u.rate_span(*iv)}" if iv else "linear spin interval: none",
        _tilted_line(r.get("equilibrium"), u),
        f"{duration(r['wall_s'])} of wall time, {r['runner']['kind']} runner",
        u.note,
        f"map: {r['out']}" if r.get("out") else "",
        f"points: {r['saved']}" if r.get("saved") else "")
