"""`levitron figures SCENE [--out DIR]`: the thesis's figures, redrawn.

Figures 3.5-3.7 (equilibrium condition, forces at larger z, critical spins against g21) come from
runtime/figures_stability.py; figures 3.2-3.3 (Euler against RK4 on the circle, thesis 3.1.3) from
runtime/solver_compare.py.
"""
from __future__ import annotations

import importlib
from pathlib import Path

from .common import model_of

NAME = "figures"
HELP = "redraw the thesis's figures (3.2, 3.3, 3.5, 3.6, 3.7) as PNG files"

# (module, function taking (outdir, model) or (outdir,)) in thesis order
SOURCES = (("runtime.solver_compare", "make_figures", False),
           ("runtime.figures_stability", "make_figures", True))


def add_arguments(parser) -> None:
    parser.add_argument("--out", default="out/figures", help="folder for the PNG files")


def run(args) -> dict:
    outdir = Path(args.out)
    outdir.mkdir(parents=True, exist_ok=True)
    model = model_of(args)
    files = []
    for module, func, needs_model in SOURCES:
        fn = getattr(importlib.import_module(module), func)
        made = fn(outdir, model) if needs_model else fn(outdir)
        files += [str(p) for p in made]
    return {"scene": model.scene.name, "files": files}
