"""python -m derive [SCENE ...] [--out DIR] [--force] [--json]: regenerate models (make derive)."""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from .build import GENERATED, derive_scene
from .scene import SCENES_DIR, SceneError, load_scene


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m derive", description=__doc__)
    ap.add_argument("scenes", nargs="*", help="scene names or .toml paths (default: all in scenes/)")
    ap.add_argument("--set", action="append", default=[], metavar="K=V", help="override a scene key")
    ap.add_argument("--out", type=Path, default=GENERATED, help="output root (default generated/)")
    ap.add_argument("--force", action="store_true", help="derive even when the input hash matches")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    args = ap.parse_args(argv)
    names = args.scenes or sorted(p.stem for p in SCENES_DIR.glob("*.toml"))
    results = []
    try:
        scenes = [load_scene(n, args.set) for n in names]   # validate all before writing any
        for scene in scenes:
            res = derive_scene(scene, args.out, force=args.force)
            results.append(res)
            if not args.json:
                state = "unchanged" if res["skipped"] else f"derived in {res['seconds']:.2f} s"
                print(f"{scene.name}: {state} -> {args.out / scene.name}", file=sys.stderr)
    except SceneError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.json:
        print(json.dumps({"scenes": results}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
