"""`levitron optimize SCENE --fit-height Z [--param NAME]`: CasADi-based fitting."""
from __future__ import annotations

from ..human import Units, lines, sig
from ..optimize import fit_equilibrium_height
from .common import model_of

NAME = "optimize"
HELP = "fit a parameter (default: the moment mu) so that the top hovers at a given height"
EXAMPLE = 'levitron optimize thesis --fit-height 0.0762'


def add_arguments(parser) -> None:
    parser.add_argument("--fit-height", type=float, required=True, metavar="Z",
                        help="the equilibrium height to fit (m)")
    parser.add_argument("--param", default="mu", help="the parameter to solve for (default mu)")


def run(args) -> dict:
    model = model_of(args)
    out = fit_equilibrium_height(model, args.fit_height, args.param)
    out["scene"] = model.scene.name
    return out


def human(r: dict, scene=None) -> str:
    """Answer first: the fitted parameter; then the equilibria it gives."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    fit = ", ".join(f"{k} = {sig(v, 6)}" for k, v in r["optimum"].items())
    roots = ", ".join(f"{u.length(e['z'])} ({'vertically stable' if e['vertically_stable'] else 'unstable'})"
                      for e in r.get("equilibria") or [])
    stable = "vertically stable" if r.get("z_star_vertically_stable") else "vertically unstable"
    return lines(
        f"fit: {fit} puts an equilibrium at {u.length(r['z_star'])} ({stable})",
        f"equilibria then: {roots}" if roots else "",
        f"solver: {r['solver_status']}, residual {sig(r['residual_N'], 2)}{' N' if u.si else ''} "
        f"({r['objective']})",
        u.note)
