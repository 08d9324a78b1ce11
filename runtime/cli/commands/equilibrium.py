"""`levitron equilibrium SCENE`: vertical equilibria, z_c, the largest mass, the stable band.

Thesis 3.3.1-3.3.3 and the stable band of docs/contract.md: the answer is runtime/physics/equilibrium/answer.py's
Equilibria (its as_json(), and `plot` with --plot); beside the band the adiabatic (Berry-Simon) one, never instead.
"""
from __future__ import annotations

from levitron.runtime.physics.equilibrium.answer import Equilibria
from levitron.runtime.ui.human import Units, lines
from levitron.runtime.ui.plotting import check_plot_path
from levitron.runtime.cli.commands.common import model_of

NAME = "equilibrium"
HELP = "vertical equilibria, z_c, the largest mass, and the band where a spin can stabilise the top"
EXAMPLE = 'levitron equilibrium thesis --plot out/thesis_equilibrium.png'


def add_arguments(parser) -> None:
    parser.add_argument("--plot", metavar="FILE", default=None,
                        help="also draw the equilibrium condition (thesis fig. 3.5) into FILE (.png)")


def run(args) -> dict:
    if args.plot is not None:
        check_plot_path(args.plot)
    model = model_of(args)
    out = Equilibria.of(model).as_json()
    if args.plot:
        from pathlib import Path

        from levitron.runtime.report.figures import figure_3_5
        out["plot"] = str(figure_3_5(model, Path(args.plot)))
    return out


def human(r: dict, scene=None) -> str:
    """The answer's own plain view (Equilibria.lines: the equilibria with the scene's stated value
    beside, the band, the reason), with the plot's file."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    return lines(*Equilibria.from_json(r, u).lines(u), f"plot: {r['plot']}" if r.get("plot") else "")
