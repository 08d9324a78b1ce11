"""`levitron figures SCENE [--out DIR]`: the thesis's figures, redrawn.

Figures 3.5-3.7 (equilibrium condition, forces at larger z, critical spins against g21) come from
runtime/report/figures.py; figures 3.2-3.3 (Euler against RK4 on the circle, thesis 3.1.3) from
runtime/bench/solver_compare.py.
"""
from __future__ import annotations

from pathlib import Path

from runtime.report import figures as figures_stability

from runtime.bench import solver_compare
from runtime.ui.human import lines
from runtime.cli.commands.common import model_of

NAME = "figures"
HELP = "redraw the thesis's figures (3.2, 3.3, 3.5, 3.6, 3.7) as PNG files"
EXAMPLE = 'levitron figures thesis --out out/figures'


def add_arguments(parser) -> None:
    parser.add_argument("--out", default="out/figures", help="folder for the PNG files")
    parser.add_argument("--quick", action="store_true", help="fewer turns and steps in 3.2/3.3")


def run(args) -> dict:
    outdir = Path(args.out)
    outdir.mkdir(parents=True, exist_ok=True)
    model = model_of(args)
    files = [f for f in solver_compare.run(outdir, quick=args.quick)["files"] if f.endswith(".png")]
    files += [str(p) for p in figures_stability.make_figures(outdir, model)]
    return {"scene": model.scene.name, "files": files}


def human(r: dict, scene=None) -> str:
    return lines(f"figures of {r['scene']}: {len(r['files'])} files", *r["files"])
