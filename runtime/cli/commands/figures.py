"""`levitron figures SCENE [--out DIR]`: the thesis's figures of chapter 3, redrawn.

Figures 3.4-3.8 depend on the scene (phase portrait, equilibrium condition, forces at larger z,
critical spins against g21, the stability map over spin and tilt) and come from
runtime/report/figures.py, one file each named after the scene. Figures 3.2-3.3 (Euler against RK4
on a point held on a circle, thesis 3.1.3) do not depend on the scene: runtime/bench/solver_compare.py
computes them once (14 s) into the cache, `$LEVITRON_CACHE/figures/<hash of their inputs>` (the
code that computes and draws them, the C integrators, the versions, --quick), and a new folder gets a
copy (each file written atomically; an entry whose files do not match its sha256.json is computed
again). They are written once per folder, without a scene's name, and a later run into the same
folder keeps them (--solvers computes them again).
"""
from __future__ import annotations

import hashlib
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
                        help="compute the scene-independent 3.2/3.3 again even if the folder or the "
                        "cache has them")


SOLVER_PNGS = ("solver_compare_fig3_2.png", "solver_compare_fig3_3.png")
SOLVER_JSON = "solver_compare.json"
SUMS = "sha256.json"          # a cache entry's manifest, written last: {file: sha256}


def solver_key(quick: bool) -> str:
    """The hash of what figures 3.2-3.3 come from: the source that computes and draws them
    (runtime/bench/solver_compare.py, the plotting style, the C integrators and the circle in
    runtime/csrc/), the package's and matplotlib's versions, and --quick."""
    import matplotlib
    from levitron.runtime.ui import plotting
    from levitron.runtime.ui.provenance import version
    h = hashlib.sha256(f"levitron {version()} matplotlib {matplotlib.__version__} quick {quick}".encode())
    csrc = Path(solver_compare.__file__).resolve().parents[1] / "csrc"
    sources = sorted(p for p in csrc.iterdir() if p.suffix in (".c", ".h"))
    for path in (Path(solver_compare.__file__), Path(plotting.__file__), *sources):
        h.update(f"\0{path.name}\0".encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _entry(quick: bool) -> Path:
    """The cache entry of figures 3.2-3.3 (runtime/model/cbuild.py cache_dir: $LEVITRON_CACHE)."""
    from levitron.runtime.model.cbuild import cache_dir
    return cache_dir() / "figures" / f"solver_compare-{solver_key(quick)[:32]}"


def _cached(entry: Path) -> tuple[dict[str, bytes], dict] | None:
    """The entry's PNGs and numbers when whole (every file matching its manifest), else None."""
    try:
        sums = json.loads((entry / SUMS).read_text())
        data = {name: (entry / name).read_bytes() for name in (*SOLVER_PNGS, SOLVER_JSON)}
        if sums != {name: hashlib.sha256(b).hexdigest() for name, b in data.items()}:
            return None
        return data, json.loads(data[SOLVER_JSON])
    except (OSError, ValueError, TypeError):
        return None


def solver_figures(outdir: Path, quick: bool, fresh: bool = False) -> tuple[list[str], bool]:
    """Figures 3.2-3.3 and their numbers in `outdir`: copied from the cache, or (a miss, a damaged
    entry, `fresh`) computed there and stored in the cache. (files, whether from the cache); the
    files' bytes are those a computation into `outdir` writes (solver_compare.json lists its PNGs
    under `outdir`)."""
    from levitron.runtime.ui.atomic import write_bytes, write_text
    entry = _entry(quick)
    hit = None if fresh else _cached(entry)
    files = [str(outdir / name) for name in SOLVER_PNGS]
    if hit is not None:
        data, result = hit
        for name, path in zip(SOLVER_PNGS, files):
            write_bytes(path, data[name], "--out")
        write_text(outdir / SOLVER_JSON, json.dumps({**result, "files": files}, indent=1), "--out")
        return [*files, str(outdir / SOLVER_JSON)], True
    with progress.stages("figures 3.2-3.3 (Euler against RK4, once into the cache)",
                         ["solver comparison"]) as stage:
        stage(0)
        result = solver_compare.run(outdir, quick=quick)
    numbers = {k: v for k, v in result.items() if k != "files"}
    data = {name: Path(outdir, name).read_bytes() for name in SOLVER_PNGS}
    data[SOLVER_JSON] = json.dumps(numbers, indent=1).encode()
    for name, b in data.items():
        write_bytes(entry / name, b, "LEVITRON_CACHE", mkdir=True)
    write_text(entry / SUMS, json.dumps({n: hashlib.sha256(b).hexdigest() for n, b in data.items()}),
               "LEVITRON_CACHE")
    return result["files"], False


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
    from levitron.runtime.physics.apparatus.level_only import refuse_tilted
    model = model_of(args)
    refuse_tilted(model, "figures redraws the thesis's figures")      # before the folder is made
    outdir = Path(args.out)
    outdir.mkdir(parents=True, exist_ok=True)
    kept = None if args.solvers else _solver_figures_current(outdir, args.quick)
    written, cached = [], False
    if kept is None:      # a copy from the cache, or the computation (14 s) with its progress line
        written, cached = solver_figures(outdir, args.quick, fresh=args.solvers)
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
            "solver_files_cached": cached,
            "not_drawn": not_drawn}


def human(r: dict, scene=None) -> str:
    solver = r["solver_files"]
    solver_line = ("figs. 3.2, 3.3 (Euler against RK4 on a circle, thesis 3.1.3) do not depend on the "
                   + ("scene: kept from this folder (--solvers computes them again): " if r["solver_files_kept"]
                      else "scene: copied from the cache (computed once): " if r.get("solver_files_cached")
                      else "scene: computed once into the cache and written for this folder: ")
                   + ", ".join(solver))
    return lines(f"figures of {r['scene']}: {len(r['files'])} files written",
                 *r["scene_files"],
                 *[f"fig. {n} not drawn: {why}" for n, why in r["not_drawn"].items()],
                 solver_line)
