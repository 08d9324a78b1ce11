"""`levitron figures SCENE [--out DIR]`: the thesis's figures of chapter 3, redrawn.

Figures 3.4-3.8 depend on the scene (phase portrait, equilibrium condition, forces at larger z,
critical spins against g21, the stability map over spin and tilt) and come from
runtime/report/figures.py, one file each named after the scene. Figures 3.2-3.3 (Euler against RK4
on a point held on a circle, thesis 3.1.3) do not depend on the scene: runtime/bench/solver_compare.py
writes them once per folder, without a scene's name, and a later run into the same folder keeps
them (--solvers draws them again).
"""
from __future__ import annotations

import json
from pathlib import Path

from levitron.runtime.report import figures as figures_stability

from levitron.runtime.bench import solver_compare
from levitron.runtime.ui import progress
from levitron.runtime.ui.human import lines
from levitron.runtime.cli.commands.common import model_of

NAME = "figures"
HELP = ("redraw the thesis's chapter 3 figures as PNG files: 3.4-3.8 for the scene, 3.2-3.3 "
        "(scene-independent) once per folder")
EXAMPLE = 'levitron figures thesis --out out/figures'


def add_arguments(parser) -> None:
    parser.add_argument("--out", default="out/figures", help="folder for the PNG files")
    parser.add_argument("--quick", action="store_true",
                        help="fewer turns and steps in 3.2/3.3, a coarser map in 3.8")
    parser.add_argument("--setup", action="store_true",
                        help="also draw the set-up to scale (base, top, hover height, stable band, z_c) "
                        "as <scene>_setup.html")
    parser.add_argument("--solvers", action="store_true",
                        help="draw the scene-independent 3.2/3.3 again even if the folder has them")


def _solver_figures_current(outdir: Path, quick: bool) -> list[str] | None:
    """The folder's 3.2/3.3 files when present and drawn with the same --quick; else None."""
    try:
        data = json.loads((outdir / "solver_compare.json").read_text())
    except (OSError, ValueError):
        return None
    files = [outdir / "solver_compare_fig3_2.png", outdir / "solver_compare_fig3_3.png",
             outdir / "solver_compare.json"]
    if data.get("quick") is not quick or not all(f.is_file() for f in files):
        return None
    return [str(f) for f in files]


def run(args) -> dict:
    from levitron.runtime.physics.level_only import refuse_tilted
    model = model_of(args)
    refuse_tilted(model, "figures redraws the thesis's figures")      # before the folder is made
    outdir = Path(args.out)
    outdir.mkdir(parents=True, exist_ok=True)
    kept = None if args.solvers else _solver_figures_current(outdir, args.quick)
    written = []
    if kept is None:      # the longest part in a new folder: its own progress line, not silence
        with progress.stages("figures 3.2-3.3 (Euler against RK4, once for this folder)",
                             ["solver comparison"]) as stage:
            stage(0)
            written += solver_compare.run(outdir, quick=args.quick)["files"]
    drawn, not_drawn = figures_stability.make_figures(outdir, model, args.quick)
    scene_files = [str(p) for p in drawn]
    if args.setup:        # the set-up to scale, as the report draws it (runtime/report/setup_drawing.py)
        from levitron.runtime.report import setup_drawing
        from levitron.runtime.simulate.setup_shape import setup_of
        from levitron.runtime.ui.human import Units
        name = model.scene.name
        svg = setup_drawing.drawing(setup_of(model, bands=True), Units.of_scene(model.scene),
                                    f"{name}: a cut through the axis")
        path = outdir / f"{name}_setup.html"
        from levitron.runtime.ui.atomic import write_text
        write_text(path, setup_drawing.page(svg, f"{name}: the set-up to scale", setup_drawing.NOTE),
                   "--out")
        scene_files.append(str(path))
    return {"scene": model.scene.name, "files": written + scene_files, "scene_files": scene_files,
            "solver_files": written or kept, "solver_files_kept": kept is not None,
            "not_drawn": not_drawn}


def human(r: dict, scene=None) -> str:
    solver = r["solver_files"]
    solver_line = ("figs. 3.2, 3.3 (Euler against RK4 on a circle, thesis 3.1.3) do not depend on the "
                   + ("scene: kept from this folder (--solvers draws them again): " if r["solver_files_kept"]
                      else "scene: written once for this folder: ") + ", ".join(solver))
    return lines(f"figures of {r['scene']}: {len(r['files'])} files written",
                 *r["scene_files"],
                 *[f"fig. {n} not drawn: {why}" for n, why in r["not_drawn"].items()],
                 solver_line)
