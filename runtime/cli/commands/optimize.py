"""`levitron optimize SCENE`: CasADi-based design and fitting (docs/contract.md `optimize`).

    --maximize spin-range|spin-ratio|mass-window --vary KEY=LO:HI [...] [--constrain EXPR] [--write-scene FILE]
    --fit DATA.csv --vary KEY=LO:HI [...]
    --fit-height Z [--param KEY]   (a scene key, e.g. plate.murho, or a parameter name, e.g. mu)

Design: runtime/design/optimize.py (IPOPT, verified by a grid and the float routes; its answer
runtime/design/design_answer.py's Design, whose as_json() this prints); fitting:
runtime/design/fit.py (Gauss-Newton, exact Jacobians); --fit-height: runtime/design/fit_height.py.
"""
from __future__ import annotations

import argparse

from levitron.runtime.design.constraints import Constraint
from levitron.runtime.errors import UserError
from levitron.runtime.physics.apparatus.level_only import refuse_tilted
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.human import Units, lines, sig
from levitron.runtime.design.fit_height import fit_equilibrium_height
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.design.sharpness import parse_tolerance
from levitron.runtime.cli.commands import launch, production_args
from levitron.runtime.cli.commands.production_args import add_production_arguments
from levitron.runtime.cli.commands.common import model_of, scene_of

NAME = "optimize"
HELP = "design (maximise the launch odds or the spin window over scene keys) or fit scene keys to measurements"
EXAMPLE = ("levitron optimize thesis_stable --maximize spin-range --vary top.mass=0.0505:0.0524 "
           "--constrain 'stiffness>=0.5'")


def add_arguments(parser) -> None:
    parser.add_argument("--maximize", metavar="OBJECTIVE", default=None,
                        help="launch-odds (the probability that a launch by hand floats, as `levitron "
                             "launch` gives it: its flags below), yield (the kits of a production run that "
                             "float after their owners trim them: --kit, --washers, --kits), spin-range "
                             "(sigma_hi - sigma_lo, rad/s), "
                             "spin-ratio (sigma_hi/sigma_lo) or mass-window ((m_hi - m_lo)/m_hi of the "
                             "stable band)")
    parser.add_argument("--minimize", metavar="OBJECTIVE", default=None,
                        help="refused: every objective is a quantity to maximise")
    parser.add_argument("--vary", action="append", default=[], metavar="KEY=LO:HI",
                        help="a scene key and its bounds, e.g. plate.hole=0.01:0.05 (repeatable, 1-3)")
    parser.add_argument("--constrain", action="append", default=[], metavar="EXPR",
                        help="NAME>=NUMBER or NAME<=NUMBER, NAME one of z_s, stiffness, sigma_lo, "
                             "sigma_hi (SI units), e.g. stiffness>=1 (repeatable)")
    parser.add_argument("--tolerance", action="append", default=[], metavar="KEY=VALUE",
                        help="a maker's tolerance of a --vary key in its SI unit, e.g. plate.hole=0.0005 "
                             "(repeatable; default 0.1 mm of a length, 0.1 g of a mass, 1 %% of a magnet's "
                             "strength, 0.2 %% of any other key): the design's sharpness, the objective at "
                             "+- it")
    parser.add_argument("--grid", type=int, default=None, metavar="N",
                        help="points a key of the verification grid (>= 20, default 20; spin-range, "
                             "spin-ratio and mass-window: the launch-odds design has its own grid and zoom)")
    parser.add_argument("--write-scene", metavar="FILE", default=None,
                        help="write the optimised scene to FILE (.toml)")
    parser.add_argument("--fit", metavar="DATA.csv", default=None,
                        help="fit the --vary keys to measurements (CSV: quantity,value,sigma[,overrides])")
    parser.add_argument("--fit-height", type=float, default=None, metavar="Z",
                        help="the equilibrium height to fit (m)")
    parser.add_argument("--param", default=None, metavar="KEY",
                        help="with --fit-height: the scene key to solve for, as --vary takes it "
                             "(e.g. plate.murho, top.moment, plate.remanence, top.mass; default: "
                             "the top's moment mu, which fits the product mu x strength)")
    add_production_arguments(parser.add_argument_group("a production run (--maximize yield)"))
    launch.add_launch_arguments(parser.add_argument_group(
        "launch odds (--maximize launch-odds, and the odds the other objectives report in air)"))


def run(args) -> dict:
    if args.minimize is not None:
        why = ("odds of falling are not a design goal" if args.minimize == "launch-odds"
               else "the design objectives are quantities to maximise")
        raise UserError(f"--minimize {args.minimize}: {why}; use --maximize {args.minimize}")
    modes = [m for m, v in (("--maximize", args.maximize), ("--fit", args.fit),
                            ("--fit-height", args.fit_height)) if v is not None]
    if len(modes) != 1:
        raise UserError("optimize needs exactly one of --maximize OBJECTIVE, --fit DATA.csv or "
                        f"--fit-height Z (given: {', '.join(modes) or 'none'})")
    if args.write_scene is not None:
        if args.maximize is None:
            raise UserError("--write-scene goes with --maximize")
        from levitron.runtime.design.scene_write import check_target
        check_target(args.write_scene)
    refuse_ignored(args)
    varies = [Vary.parse(v) for v in args.vary]
    tolerance = parse_tolerance(args.tolerance)
    if tolerance and args.maximize is None:
        raise UserError("--tolerance goes with --maximize (a design's sharpness)")
    constraints = [Constraint.parse(c) for c in args.constrain]
    if args.fit_height is not None:
        if varies or constraints:
            raise UserError("--fit-height takes --param, not --vary or --constrain")
        model = model_of(args)
        refuse_tilted(model, "optimize fits and designs")
        out = fit_equilibrium_height(model, args.fit_height, args.param or "mu").as_json()     # its HeightFit
    elif args.fit is not None:
        from levitron.runtime.design.fit import fit
        from levitron.runtime.design.measurements import read_rows
        rows = read_rows(args.fit)
        model = model_of(args)
        refuse_tilted(model, "optimize fits and designs")
        out = fit(model, rows, varies).as_json()     # the answer: runtime/design/fit_answer.py's Fit
    elif args.maximize == "yield":
        res = _yield(args, varies, constraints)
        model = res.model
        out = res.answer.as_json()      # the answer (runtime/design/yield_answer.py)
        if args.write_scene:
            out["written"] = res.answer.write_scene(args.write_scene)
    elif args.maximize == "launch-odds":
        from levitron.runtime.design.design_notes import with_launch_notes
        from levitron.runtime.design.launch_design import maximize_launch_odds
        if constraints:
            raise UserError("--maximize launch-odds takes no --constrain: the odds already count a top "
                            "that cannot hover or falls as a failure")
        scene = scene_of(args)
        request = launch.launch_request(args, scene)
        model = model_of(args)
        res = maximize_launch_odds(model, varies, request, tolerance=tolerance)
        res = with_launch_notes(model, res)      # a resonance's side, keys below noise (design_notes.py)
        out = res.as_json()      # the answer (runtime/design/launch_design_answer.py)
        if args.write_scene:
            out["written"] = res.write_scene(args.write_scene)
    else:
        from levitron.runtime.design import launch_design
        from levitron.runtime.design.optimize import GRID_MIN, optimize
        model = model_of(args)
        refuse_tilted(model, "optimize fits and designs")
        if (given := launch_flags_given(args)) and not launch_design.worth_the_launches(model):
            raise UserError(f"{', '.join(given)}: a design counts its launches only in air or with a [launch] "
                            f"table, and this scene has neither: drop {'it' if len(given) == 1 else 'them'}, "
                            "or use --maximize launch-odds")
        res = optimize(model, varies, args.maximize, constraints, args.grid or GRID_MIN, tolerance)
        out = res.as_json()      # the answer (runtime/design/design_answer.py), then what the face adds
        if launch_design.worth_the_launches(model):
            scene = scene_of(args)
            u = Units.of_scene(scene)
            try:
                cost = launch_design.what_it_costs(
                    model, varies, launch.launch_request(args, scene),
                    res.optimum, args.maximize, lambda k, v: u.mass(v) if k == "top.mass" else sig(v, 6))
            except UserError as exc:        # the design stands; only its cost in launches is unknown
                cost = {"warning": f"the launch odds are not computed: {exc}"}
            out.update({k: v for k, v in cost.items() if k != "warning"})
            if "warning" in cost:
                out["warnings"] = [*out["warnings"], cost["warning"]]
        if args.write_scene:
            out["written"] = res.write_scene(args.write_scene)
    out["scene"] = model.scene.name
    return out


def launch_flags_given(args) -> list[str]:
    """The launch flags (launch.add_launch_arguments) given a value other than their default."""
    flags = argparse.ArgumentParser(add_help=False)
    launch.add_launch_arguments(flags)
    return [a.option_strings[0] for a in flags._actions
            if getattr(args, a.dest, a.default) != a.default]


def refuse_ignored(args) -> None:
    """A flag the chosen mode would ignore is refused in one line, not dropped silently."""
    mode = ("--fit-height" if args.fit_height is not None else "--fit" if args.fit is not None
            else f"--maximize {args.maximize}")
    if args.grid is not None and args.maximize in ("launch-odds", "yield"):
        raise UserError(f"--grid {args.grid}: --maximize {args.maximize} searches its own grid and zooms in "
                        "around the best point (docs/contract.md optimize): drop --grid")
    run = production_args.given(args)
    if run and args.maximize != "yield":
        raise UserError(f"{', '.join(run)}: a production run goes with --maximize yield; {mode} has none: "
                        f"drop {'it' if len(run) == 1 else 'them'}")
    if args.grid is not None and args.maximize is None:
        raise UserError(f"--grid {args.grid} goes with --maximize spin-range, spin-ratio or mass-window "
                        f"(their verification grid); {mode} has none: drop --grid")
    if args.param is not None and args.fit_height is None:
        raise UserError(f"--param {args.param} goes with --fit-height Z (the key it solves for); {mode} "
                        "takes --vary KEY=LO:HI: drop --param")
    if args.constrain and args.fit is not None:
        raise UserError("--fit takes no --constrain (the fit is least squares over the --vary box): drop it")
    given = launch_flags_given(args)
    if given and args.maximize is None:
        raise UserError(f"{', '.join(given)}: launch flags go with --maximize (the launch odds); "
                        f"{mode} runs no launch: drop {'it' if len(given) == 1 else 'them'}")


def human(r: dict, scene=None) -> str:
    """Answer first: the optimum (design), the fitted keys with their standard errors (fit), or
    the fitted parameter (--fit-height); then how it was verified. Each in its answer's own words
    (the `*_lines` beside each answer type: runtime/design/)."""
    from levitron.runtime.design.design_answer import design_lines
    from levitron.runtime.design.fit_answer import fit_lines
    from levitron.runtime.design.fit_height import height_fit_lines
    from levitron.runtime.design.launch_design_answer import launch_design_lines
    from levitron.runtime.design.yield_answer import yield_lines
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    if "z_star" in r:
        view = height_fit_lines(r, u)
    elif r.get("objective_name") == "yield":
        view = yield_lines(r, u, scene)
    elif r.get("objective_name") == "launch-odds":
        view = launch_design_lines(r, u, scene)
    elif "parameters" in r:
        view = fit_lines(r, u)
    else:
        view = design_lines(r, u, scene)
    return lines(*worded(view, u, None))


class _Yield:
    def __init__(self, model, answer):
        self.model, self.answer = model, answer


def _yield(args, varies, constraints) -> _Yield:
    """--maximize yield: the production run from the flags, the hand from the launch flags."""
    from levitron.runtime.design.yield_design import maximize_yield
    if constraints:
        raise UserError("--maximize yield takes no --constrain: a kit that cannot hover already counts as a "
                        "failure")
    scene = scene_of(args)
    request = launch.launch_request(args, scene)
    prod = production_args.production_of(args, request.seed, scene.data.get("production"))
    model = model_of(args)
    refuse_tilted(model, "optimize fits and designs")
    return _Yield(model, maximize_yield(model, varies, request, prod, tolerance=parse_tolerance(args.tolerance)))
