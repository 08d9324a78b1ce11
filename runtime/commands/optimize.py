"""`levitron optimize SCENE --fit-height Z [--param NAME]`: CasADi-based fitting."""
from __future__ import annotations

from ..optimize import fit_equilibrium_height
from .common import model_of

NAME = "optimize"
HELP = "fit a parameter (default: the moment mu) so that the top hovers at a given height"


def add_arguments(parser) -> None:
    parser.add_argument("--fit-height", type=float, required=True, metavar="Z",
                        help="the equilibrium height to fit (m)")
    parser.add_argument("--param", default="mu", help="the parameter to solve for (default mu)")


def run(args) -> dict:
    model = model_of(args)
    out = fit_equilibrium_height(model, args.fit_height, args.param)
    out["scene"] = model.scene.name
    return out
