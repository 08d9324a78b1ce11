"""`levitron compare SCENE SCENE ...`: bases compared under one launch spread (docs/contract.md
`compare`; runtime/design/compare.py, whose Comparison.as_json() this prints)."""
from __future__ import annotations

from levitron.runtime.cli.commands import launch
from levitron.runtime.cli.commands.common import load
from levitron.runtime.cli.commands.production_args import add_production_arguments, production_of
from levitron.runtime.scan.launch_inputs import ALL_INPUTS

NAME = "compare"
HELP = ("bases compared under one hand: hover height, stable band, spin and weight windows, the launch "
        "odds (at each scene's mass and at its best mass) and the yield of a production run, every scene "
        "launched by the same spread")
MULTI_SCENE = True
EXAMPLE = "levitron compare thesis_air levitron_toy --n 100 --t-end 10"


def add_arguments(parser) -> None:
    launch.add_launch_arguments(parser.add_argument_group(
        "the one launch spread (default: the first scene's, as `levitron launch` resolves it)"))
    add_production_arguments(parser.add_argument_group("the production run of every scene's yield"))


def run(args) -> dict:
    from levitron.runtime.design.compare import compare
    from levitron.runtime.errors import UserError
    from levitron.runtime.model.load import load_model
    if len(args.scenes) < 2:
        raise UserError("compare needs two scenes or more, e.g. levitron compare thesis_air levitron_toy")
    scenes = [load(n, args.set) for n in args.scenes]       # validate all before running any
    request = launch.launch_request(args, scenes[0])
    flags = [k for k in ALL_INPUTS if getattr(args, f"dist_{k}") is not None]
    prod = production_of(args, request.seed, scenes[0].data.get("production"))    # the first scene's, as the hand
    return compare([load_model(s) for s in scenes], request, flags, prod).as_json()


def human(r: dict, scene=None) -> str:
    """The hand first, then one row a scene (runtime/design/compare.py comparison_view, the answer's
    own words)."""
    from levitron.runtime.design.compare import comparison_view
    from levitron.runtime.ui.answer_lines import worded
    from levitron.runtime.ui.human import Units, lines
    return lines(*worded(comparison_view(r), Units(si=r.get("units", "SI") == "SI"), None))
