"""`levitron optimize SCENE`: CasADi-based design and fitting (docs/contract.md `optimize`).

    --maximize spin-range|spin-ratio --vary KEY=LO:HI [...] [--constrain EXPR] [--write-scene FILE]
    --fit DATA.csv --vary KEY=LO:HI [...]
    --fit-height Z [--param NAME]

Design: runtime/design.py (IPOPT, verified by a grid and the float routes); fitting:
runtime/fit.py (Gauss-Newton, exact Jacobians); --fit-height: runtime/optimize.py.
"""
from __future__ import annotations

from ..constraints import Constraint
from ..errors import UserError
from ..optimize import fit_equilibrium_height
from ..scene_keys import Vary
from .common import model_of

NAME = "optimize"
HELP = "design (maximise the spin range over scene keys) or fit scene keys to measurements"


def add_arguments(parser) -> None:
    parser.add_argument("--maximize", metavar="OBJECTIVE", default=None,
                        help="spin-range (sigma_hi - sigma_lo, rad/s) or spin-ratio (sigma_hi/sigma_lo)")
    parser.add_argument("--vary", action="append", default=[], metavar="KEY=LO:HI",
                        help="a scene key and its bounds, e.g. plate.hole=0.01:0.05 (repeatable, 1-3)")
    parser.add_argument("--constrain", action="append", default=[], metavar="EXPR",
                        help="NAME>=NUMBER or NAME<=NUMBER, NAME one of z_s, stiffness, sigma_lo, "
                             "sigma_hi (SI units), e.g. stiffness>=1 (repeatable)")
    parser.add_argument("--grid", type=int, default=20, metavar="N",
                        help="points a key of the verification grid (>= 20)")
    parser.add_argument("--write-scene", metavar="FILE", default=None,
                        help="write the optimised scene to FILE (.toml)")
    parser.add_argument("--fit", metavar="DATA.csv", default=None,
                        help="fit the --vary keys to measurements (CSV: quantity,value,sigma[,overrides])")
    parser.add_argument("--fit-height", type=float, default=None, metavar="Z",
                        help="the equilibrium height to fit (m)")
    parser.add_argument("--param", default="mu", help="with --fit-height: the parameter to solve for")


def run(args) -> dict:
    modes = [m for m, v in (("--maximize", args.maximize), ("--fit", args.fit),
                            ("--fit-height", args.fit_height)) if v is not None]
    if len(modes) != 1:
        raise UserError("optimize needs exactly one of --maximize OBJECTIVE, --fit DATA.csv or "
                        f"--fit-height Z (given: {', '.join(modes) or 'none'})")
    if args.write_scene is not None:
        if args.maximize is None:
            raise UserError("--write-scene goes with --maximize")
        from ..scene_write import check_target
        check_target(args.write_scene)
    varies = [Vary.parse(v) for v in args.vary]
    constraints = [Constraint.parse(c) for c in args.constrain]
    if args.fit_height is not None:
        if varies or constraints:
            raise UserError("--fit-height takes --param, not --vary or --constrain")
        model = model_of(args)
        out = fit_equilibrium_height(model, args.fit_height, args.param)
    elif args.fit is not None:
        from ..fit import fit, read_rows
        rows = read_rows(args.fit)
        model = model_of(args)
        out = fit(model, rows, varies).as_dict()
    else:
        from ..design import optimize
        model = model_of(args)
        res = optimize(model, varies, args.maximize, constraints, args.grid)
        out = res.as_dict()
        if args.write_scene:
            from ..scene_write import write_scene
            note = (f"levitron optimize {model.scene.name} --maximize {args.maximize}: "
                    + ", ".join(f"{k} = {v:.6g}" for k, v in res.optimum.items()))
            out["written"] = str(write_scene(res.scene, args.write_scene, note))
    out["scene"] = model.scene.name
    return out
