"""`levitron stability SCENE`: the spin interval of linear stability at the stable height.

Two routes (thesis 3.3; runtime/stability.py): "discriminant" (exact rational arithmetic on the ray
polynomial L and a Sturm count of N(t)) and "eigenvalues" (the generated full model's Jacobian at the
relative equilibrium). spin_interval is the discriminant route's; both are reported. Rates in rad/s,
with Hz and rpm beside.
"""
from __future__ import annotations

import time

from ..errors import UserError
from ..stability import stability_of
from .common import model_of

NAME = "stability"
HELP = "spin interval of linear stability at the stable height (two routes), thesis approximations"


def add_arguments(parser) -> None:
    parser.add_argument("--height", type=float, default=None, metavar="Z",
                        help="analyse at this height (m) instead of the vertically stable equilibrium")


def run(args) -> dict:
    model = model_of(args)
    if args.height is not None and not args.height > 0:
        raise UserError(f"--height {args.height} must be positive (above the plate, z > 0)")
    t0 = time.perf_counter()
    res = stability_of(model, z_s=args.height)
    wall = time.perf_counter() - t0
    out = {"scene": model.scene.name, "mass": model.param("m")}
    out.update(res.as_dict())
    out["eigen_source"] = ("full_jac (generated)" if model.has_function("full_jac")
                           else "transverse_matrix (8-D)")
    out["wall_s"] = wall
    return out
