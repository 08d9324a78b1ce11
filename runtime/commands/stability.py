"""`levitron stability SCENE`: the spin interval of linear stability at the stable height.

Two routes (thesis 3.3; runtime/stability.py): "discriminant" (exact rational arithmetic on the ray
polynomial L and a Sturm count of N(t)) and "eigenvalues" (the generated full model's Jacobian at the
relative equilibrium). spin_interval is the discriminant route's; both are reported. Rates in rad/s,
with Hz and rpm beside.
"""
from __future__ import annotations

import time

from ..human import Units, lines, restate, sig
from ..stability import stability_of
from ..validate import real
from .common import model_of

NAME = "stability"
HELP = "spin interval of linear stability at the stable height (two routes), thesis approximations"
EXAMPLE = 'levitron stability thesis_stable'


def add_arguments(parser) -> None:
    parser.add_argument("--height", type=float, default=None, metavar="Z",
                        help="analyse at this height (m) instead of the vertically stable equilibrium")


def run(args) -> dict:
    model = model_of(args)
    if args.height is not None:
        real(args.height, "--height", positive=True, unit="m (above the plate, z > 0)")
    t0 = time.perf_counter()
    res = stability_of(model, z_s=args.height)
    wall = time.perf_counter() - t0
    out = {"scene": model.scene.name, "mass": model.param("m")}
    out.update(res.as_dict())
    out["eigen_source"] = ("full_jac (generated)" if model.has_function("full_jac")
                           else "transverse_matrix (8-D)")
    out["wall_s"] = wall
    return out


def _agreement(routes) -> str:
    a, b = routes.get("discriminant"), routes.get("eigenvalues")
    if not a or not b:
        return ""
    rel = max(abs(x - y) / max(abs(x), 1e-300) for x, y in zip(a, b))
    return f", both routes agree to {sig(max(rel, 1e-16), 1)}"


def human(r: dict, scene=None) -> str:
    """Answer first: the spin interval (rad/s, Hz, rpm), then where, the thesis's approximations."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    iv = r.get("spin_interval")
    head = (f"spin_interval: {u.rate_span(*iv)}{_agreement(r['routes'])}" if iv
            else "spin_interval: none: no spin rate stabilises this top")
    ap = r.get("approximations") or {}
    approx = ""
    if ap.get("sigma1") is not None:
        approx = (f"thesis approximations (eqs. 3.3.22/3.3.23 at z_c = {u.length(ap['z_c'])}): "
                  f"{u.rate(ap['sigma1'])} to {u.rate(ap['sigma2'])}")
    more = [ivl for ivl in r["all_intervals"].get("discriminant", [])[1:]]
    return lines(
        head,
        f"at z_s = {u.length(r['z_s'])} for the {u.mass(r['mass'])} top" if r.get("z_s") else "",
        "further intervals: " + ", ".join(u.rate_span(*ivl) for ivl in more) if more else "",
        f"reason: {restate(r['reason'], u)}" if r.get("reason") else "",
        approx, u.note)
