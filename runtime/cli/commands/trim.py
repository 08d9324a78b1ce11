"""`levitron trim SCENE`: the mass to add or take off so that most launches by hand float, the odds
before and after, and a plot of the spin limits and the odds against mass (docs/contract.md `trim`;
runtime/design/trim.py)."""
from __future__ import annotations

from levitron.runtime.cli.commands import launch
from levitron.runtime.cli.commands.common import model_of, scene_of
from levitron.runtime.design.trim_answer import trim_lines
from levitron.runtime.ui.answer_lines import worded
from levitron.runtime.ui.human import Units, lines
from levitron.runtime.ui.plotting import check_plot_path

NAME = "trim"
HELP = ("the mass to add or take off (washers, putty) so that most launches by hand float: the launch "
        "odds before and after, and the spin window of every mass that hovers")
EXAMPLE = "levitron trim thesis_air --temperature 28 --n 200 --out out/trim.png"


def add_arguments(parser) -> None:
    launch.add_launch_arguments(parser.add_argument_group("the launches (as `levitron launch` takes them)"))
    parser.add_argument("--out", default=None, metavar="FILE.png",
                        help="draw the spin limits and the launch odds against the top's mass")


def run(args) -> dict:
    from levitron.runtime.design.trim import trim
    if args.out is not None:
        check_plot_path(args.out, "--out")
    scene = scene_of(args)
    request = launch.launch_request(args, scene)
    model = model_of(args)
    out = trim(model, request).as_json()
    out["scene"] = scene.name
    out["out"] = None
    if args.out is not None:
        from levitron.runtime.design.trim_plot import draw
        out["out"] = str(draw(out, args.out, Units.of_scene(scene), scene.name))
    return out


def human(r: dict, scene=None) -> str:
    """Answer first: the change and what it does to the odds; then the band and the widest window
    (runtime/design/trim_answer.py trim_lines, the answer's own words)."""
    u = Units.of_scene(scene) if scene is not None else Units(si=True)
    return lines(*worded(trim_lines(r, u, scene), u, None))
