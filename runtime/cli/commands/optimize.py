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
from levitron.runtime.physics.level_only import refuse_tilted
from levitron.runtime.ui.human import Units, lines, restate, sig
from levitron.runtime.design.fit_height import fit_equilibrium_height
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.design.sharpness import parse_tolerance, sharpness_lines
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
        from levitron.runtime.design.design_notes import with_resonance_advice
        from levitron.runtime.design.launch_design import maximize_launch_odds
        if constraints:
            raise UserError("--maximize launch-odds takes no --constrain: the odds already count a top "
                            "that cannot hover or falls as a failure")
        scene = scene_of(args)
        request = launch.launch_request(args, scene)
        model = model_of(args)
        res = maximize_launch_odds(model, varies, request, tolerance=tolerance)
        res = with_resonance_advice(model, res)      # which side of a resonance crossed (design_notes.py)
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
    the fitted parameter (--fit-height); then how it was verified."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    if "z_star" in r:
        fit = ", ".join(f"{k} = {sig(v, 6)}" for k, v in r["optimum"].items())
        roots = ", ".join(f"{u.length(e['z'])} ({'vertically stable' if e['vertically_stable'] else 'unstable'})"
                          for e in r.get("equilibria") or [])
        stable = "vertically stable" if r.get("z_star_vertically_stable") else "vertically unstable"
        return lines(
            f"fit: {fit} puts an equilibrium at {u.length(r['z_star'])} ({stable})",
            f"equilibria then: {roots}" if roots else "",
            f"solver: {r['solver_status']}, residual {u.value(r['residual_N'], 'N', 2)} "
            f"({r['objective']})",
            u.note)
    if r.get("objective_name") == "yield":
        from levitron.runtime.design.yield_answer import yield_lines
        return lines(*yield_lines(r, u, scene))
    if r.get("objective_name") == "launch-odds":
        return lines(*launch_odds_lines(r, u, scene), *sharpness_lines(r.get("sharpness"), u, scene),
                     *warning_lines(r, scene), u.note)
    status = f"solver: {r['solver_status']}, {r['iterations']} iterations"
    if "parameters" in r:
        fitted = ", ".join(f"{k} = {sig(v['value'], 6)} +- {sig(v['stderr'], 2)}"
                           for k, v in r["parameters"].items())
        worst = max((abs(x.get("normalized", 0.0)) for x in r.get("residuals") or []), default=None)
        return lines(f"fit: {fitted}",
                     f"chi2 {sig(r['objective'], 4)} with {r['dof']} degrees of freedom"
                     + (f"; largest residual {sig(worst, 3)} sigma" if worst is not None else ""),
                     status, *warning_lines(r, scene), u.note)
    best = ", ".join(f"{k} = {sig(v, 6)}" for k, v in r["optimum"].items())
    iv, band = r.get("spin_interval"), r.get("band")
    ver = r["verification"]
    unit = u.unit(r.get("objective_unit") or "1")      # a ratio: no unit to show
    return lines(
        f"optimum: {best}: {r['objective_name']} {sig(r['objective'], 6)} {unit}".rstrip(),
        f"stable band {u.length(band['z'][0])} to {u.length(band['z'][1])}, tops of "
        f"{u.mass(band['mass'][0])} to {u.mass(band['mass'][1])}" if band else "",
        (f"{'the scene top' + chr(39) + 's ' if band else ''}spin interval {u.rate_span(*iv)} "
         f"at z_s = {u.length(r['z_s'])}") if iv
        else "the scene's top has no stable spin interval there" if band else "",
        f"the scene itself: {r['objective_name']} {sig(r['scene_objective'], 6)} {unit}".rstrip()
        if r.get("scene_objective") is not None else "",
        f"verified: float route at the optimum, best of {ver['grid_points']} grid points "
        f"{sig(ver['grid_best'], 6) if ver.get('grid_best') is not None else 'none feasible'} {unit}".rstrip(),
        status, *sharpness_lines(r.get("sharpness"), u, scene, r["objective_name"], r.get("objective_unit") or "1"),
        *cost_lines(r, u), *warning_lines(r, scene),
        f"scene written: {r['written']} (check it: levitron stability {r['written']})"
        if r.get("written") else "", u.note)


def warning_lines(r: dict, scene=None) -> list[str]:
    """Every warning of the result in plain view, one a line."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    return [f"warning: {restate(w, u)}" for w in r.get("warnings") or []]


def odds_text(block: dict) -> str:
    lo, hi = block["probability_ci95"]
    if hi == 0:                         # odds_at: a design whose top cannot hover floats never
        return "0 % (it cannot hover)"
    return f"{sig(100 * block['probability'], 3)} % ({sig(100 * lo, 3)}-{sig(100 * hi, 3)} %)"


def change_text(key: str, start: float, to: float, u: Units) -> str:
    """"take 1.2 g off" / "add 0.3 g" for the top's mass; "set KEY from A to B" for any key."""
    if key == "top.mass":
        d = to - start
        return f"take {u.mass(-d)} off" if d < 0 else f"add {u.mass(d)}"
    return f"set {key} from {sig(start, 6)} to {sig(to, 6)}"


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
    prod = production_args.production_of(args, request.seed)
    model = model_of(args)
    refuse_tilted(model, "optimize fits and designs")
    return _Yield(model, maximize_yield(model, varies, request, prod, tolerance=parse_tolerance(args.tolerance)))


def launch_odds_lines(r: dict, u: Units, scene=None) -> list[str]:
    """The launch-odds design in plain view: the advice and what it does to the odds."""
    a, b = r["start_launch_odds"], r["launch_odds"]
    advice = "; ".join(change_text(k, r["start"][k], v, u) for k, v in r["optimum"].items())
    search = r["search"]
    return [f"{advice}: odds {sig(100 * a['probability'], 3)} % -> {sig(100 * b['probability'], 3)} %",
            "optimum: " + ", ".join(f"{k} = {u.mass(v) if k == 'top.mass' else sig(v, 6)}"
                                    for k, v in r["optimum"].items())
            + f": {odds_text(b)} of {b['n']} launches float at least {u.time(r['success_time'])} (seed {b['seed']})",
            f"as written: {odds_text(a)} (the same seed)",
            launch.launches_line(r, u, scene),
            f"searched: {search['evaluations']} designs of {search['n']} launches each on common random "
            f"numbers (seed {search['seed']}), the best at {sig(100 * search['best_search_odds'], 3)} % (biased "
            f"upwards: the best of {search['evaluations']}); decided on the fresh seed {b['seed']}"]


def cost_lines(r: dict, u: Units) -> list[str]:
    """What another objective's optimum costs in launches (scenes in air or with a [launch] table)."""
    if "launch_odds" not in r:
        return []
    best = r["launch_odds_optimum"]
    where = ", ".join(f"{k} = {u.mass(v) if k == 'top.mass' else sig(v, 6)}" for k, v in best["optimum"].items())
    return [f"launch odds at this optimum: {odds_text(r['launch_odds'])}; "
            f"as written {odds_text(r['start_launch_odds'])}; "
            f"the launch-odds optimum ({where}) {odds_text(best['launch_odds'])}"]
