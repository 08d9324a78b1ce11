"""`levitron bench SCENE`: the speed-versus-error report (docs/contract.md `bench`)."""
from __future__ import annotations


from levitron.runtime.bench import kinds as bench_kinds
from levitron.runtime.ui.human import duration, lines, sig
from levitron.runtime.cli.commands.common import model_of

NAME = "bench"
HELP = ("work-precision report: error of the final state against wall time for every backend and "
        "integrator, reduced and full model; CSV/JSON/PNG in reports/<scene>/")
EXAMPLE = 'levitron bench thesis_stable --quick'


def add_arguments(parser) -> None:
    kinds = ", ".join(f"{k.name} ({k.doc})" for k in bench_kinds.KINDS.values())
    parser.add_argument("--kind", default=bench_kinds.DEFAULT, choices=list(bench_kinds.KINDS),
                        metavar="KIND", help=f"which benchmark: {kinds}; default {bench_kinds.DEFAULT}")
    parser.add_argument("--quick", action="store_true", help="a small version (a few seconds)")
    parser.add_argument("--out", default=None, metavar="DIR",
                        help="output folder (default the kind's report folder, reports/<scene>/ for "
                             "work-precision, or out/bench-quick/<kind> with --quick so that a quick run "
                             "never overwrites the full report)")


def run(args) -> dict:
    model = model_of(args)
    out = args.out or bench_kinds.out_dir(args.kind, model.scene.name, args.quick)
    return bench_kinds.run(args.kind, model, out, args.quick)


def human(r: dict, scene=None) -> str:
    """Answer first: the fastest run within the error goal (work-precision) or the kind's headline;
    then the table's size and files."""
    if r.get("kind", bench_kinds.DEFAULT) != "work-precision":
        return lines(f"bench {r['kind']}: {r.get('headline', '')}", "files: " + ", ".join(r.get("files", [])))
    g = r.get("goals") or {}
    best = g.get("c_dop853")
    head = ("bench: no run met the error goal" if g.get("error_bound") is not None else
            "bench: the reduced model only (the scene has no full model, which the goals are about)")
    if best:
        head = (f"bench: C dop853 reaches error {sig(best['error'], 2)} in {duration(best['wall_s'])} "
                f"({best['model']} model; goal: error below {sig(g.get('error_bound'), 2)})")
    speed = [f"{k.replace('_', ' ')} {sig(g[k], 3)}x" for k in ("speedup_vs_scipy", "speedup_vs_cvodes")
             if g.get(k) is not None]
    rhs = (f"full_rhs: {sig(g['full_rhs_ns'], 3)} ns per call ({g.get('full_rhs_ops')} operations)"
           if g.get("full_rhs_ns") is not None else "")
    files = r.get("files")
    return lines(head, ", ".join(speed), rhs,
                 f"{len(r['rows'])} runs in {duration(r.get('wall_s'))}",
                 f"files: {files}" if isinstance(files, int) else
                 ("files: " + ", ".join(map(str, files)) if files else ""))
