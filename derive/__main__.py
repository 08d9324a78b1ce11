"""python -m levitron.derive [SCENE ...] [--out DIR] [--force] [--json]: regenerate models (make derive).

Without --out (or with --out generated) it writes the committed models, generated/<name>/, and
only for scenes of scenes/ without --set: a variant or an out-of-tree scene is refused there (give
--out, or use `levitron derive`, which derives it into the cache), so a committed model is never
overwritten.

--stages writes one line per stage of a derivation on stderr, "stage 3/7 Hamilton's equations", for
the runtime's progress display (runtime/model/load.py reads them while the child runs). The stages
are marked by wrapping the functions that begin them, here: derive's modules are not changed (this
file is outside the input hash, scene/inputs.py).
"""
from __future__ import annotations

import argparse
import contextlib
import json
import sys
from pathlib import Path

from levitron.scene.faults import die_at
from levitron.scene.load import SceneError, load_scene
from levitron.scene.paths import GENERATED, SCENES_DIR, is_committed_scene


def refuse_uncommitted(scenes, overrides) -> None:
    """generated/ holds the models of scenes/ as they are: raise SceneError for anything else."""
    if overrides:
        raise SceneError(f"--set {overrides[0]} would overwrite a committed model in generated/: give "
                         "--out OTHER_DIR, or use `levitron derive` (derives variants into the cache)")
    for scene in scenes:
        if not is_committed_scene(scene.name, scene.path):
            raise SceneError(f"scene '{scene.name}' ({scene.path}) is not scenes/{scene.name}.toml, "
                             "so it has no committed model in generated/: give --out OTHER_DIR, or use "
                             "`levitron derive` (derives it into the cache)")


# (module, function name, which call, stage name) in the order a derivation meets them
# (derive/build.py's _render, derive/spec.py's build_spec): a stage begins at that call of its
# function (_part_functions' second call is the full part's; a scene without it skips stages).
STAGES = (
    ("build", "build_plate", 1, "the plate's on-axis potential"),
    ("build", "field_order", 1, "the field's order"),
    ("spec", "reduced_system", 1, "the reduced model"),
    ("spec", "hamiltonian_system", 1, "Hamilton's equations"),
    ("spec", "_part_functions", 2, "the full model's Jacobian and energy"),
    ("build", "lower", 1, "common subexpressions"),
    ("casadi_builder", "build_function", 1, "C and CasADi files"),
)


@contextlib.contextmanager
def stage_lines(enabled: bool):
    """While enabled, the first call of each STAGES function prints its stage line on stderr."""
    if not enabled:
        yield
        return
    from . import build, spec
    from .emit.casadi import builder as casadi_builder
    modules = {"build": build, "spec": spec, "casadi_builder": casadi_builder}
    calls = [0] * len(STAGES)
    saved = []

    def wrap(k: int, fn):
        def marked(*a, **kw):
            calls[k] += 1
            if calls[k] == STAGES[k][2]:
                print(f"stage {k + 1}/{len(STAGES)} {STAGES[k][3]}", file=sys.stderr, flush=True)
            return fn(*a, **kw)
        return marked

    for k, (mod, name, _, _) in enumerate(STAGES):
        module = modules[mod]
        saved.append((module, name, getattr(module, name)))
        setattr(module, name, wrap(k, getattr(module, name)))
    try:
        yield
    finally:
        for module, name, fn in saved:
            setattr(module, name, fn)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m levitron.derive", description=__doc__.splitlines()[0])
    ap.add_argument("scenes", nargs="*", help="scene names or .toml paths (default: all in scenes/)")
    ap.add_argument("--set", action="append", default=[], metavar="K=V", help="override a scene key")
    ap.add_argument("--out", type=Path, default=None,
                    help="output root (default generated/, for the scenes of scenes/ only)")
    ap.add_argument("--force", action="store_true", help="derive even when the input hash matches")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--stages", action="store_true",
                    help="a line per stage of each derivation on stderr (for a progress display)")
    args = ap.parse_args(argv)
    die_at("derive.child")
    names = args.scenes or sorted(p.stem for p in SCENES_DIR.glob("*.toml"))
    out = GENERATED if args.out is None else args.out
    results = []
    try:
        scenes = [load_scene(n, args.set) for n in names]   # validate all before writing any
        if out.resolve() == GENERATED.resolve():
            refuse_uncommitted(scenes, args.set)
        from .build import derive_scene      # sympy and the emitters: after the scenes are valid
        for scene in scenes:
            with stage_lines(args.stages):
                res = derive_scene(scene, out, force=args.force)
            results.append(res)
            if not args.json:
                state = "unchanged" if res["skipped"] else f"derived in {res['seconds']:.2f} s"
                print(f"{scene.name}: {state} -> {out / scene.name}", file=sys.stderr)
    except SceneError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps({"scenes": results}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
