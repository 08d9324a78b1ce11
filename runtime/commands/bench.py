"""`levitron bench SCENE`: the speed-versus-error report (issue 3; docs/contract.md `bench`)."""
from __future__ import annotations

from .. import bench as _bench
from .common import model_of

NAME = "bench"
HELP = ("work-precision report: error of the final state against wall time for every backend and "
        "integrator, reduced and full model; CSV/JSON/PNG in reports/<scene>/")


def add_arguments(parser) -> None:
    parser.add_argument("--quick", action="store_true", help="a small version (a few seconds)")
    parser.add_argument("--out", default=None, metavar="DIR",
                        help="output folder (default reports/<scene>/, or out/bench-quick with --quick so that "
                             "a quick run never overwrites the full report)")


def run(args) -> dict:
    model = model_of(args)
    out = args.out or ("out/bench-quick" if args.quick else f"reports/{model.scene.name}")
    return _bench.run(model, out, args.quick)
