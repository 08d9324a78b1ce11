"""`levitron derive [SCENE ...]`: regenerate models.

The scenes of scenes/, as they are, are derived into generated/ (the same as `make derive`, which
alone writes committed models). A variant (--set) or an out-of-tree scene is derived into the
cache, where the other commands find it: generated/ is never overwritten by one.
"""
from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

from levitron.scene.paths import ROOT, SCENES_DIR

from levitron.runtime.ui import progress
from levitron.runtime.errors import UserError
from levitron.runtime.ui.human import duration, lines
from levitron.runtime.model.locate import committed_folder, locate
from levitron.runtime.cli.commands.common import load

NAME = "derive"
HELP = ("regenerate the models of the given scenes (default: every shipped scene, `levitron scenes`); "
        "variants (--set) and out-of-tree scenes go to the cache, never to generated/")
MULTI_SCENE = True
EXAMPLE = 'levitron derive thesis ring_magnet'


def add_arguments(parser) -> None:
    parser.add_argument("--force", action="store_true", help="derive even when nothing changed")


def run(args) -> dict:
    names = args.scenes or sorted(p.stem for p in SCENES_DIR.glob("*.toml"))
    scenes = [load(n, args.set) for n in names]        # validate all before deriving any
    committed = [not args.set and committed_folder(s) is not None for s in scenes]
    done = {}
    if any(committed):
        done = {r["name"]: r for r in _derive_committed(
            [s for s, c in zip(scenes, committed) if c], args.force)}
    results = []
    for scene, is_committed in progress.track(list(zip(scenes, committed)), "derive"):
        if is_committed:
            results.append(done[scene.name])
            continue
        t0 = time.perf_counter()
        found = locate(scene, force=args.force)
        results.append({"name": scene.name, "files": sorted(p.name for p in found.folder.iterdir()),
                        "seconds": round(time.perf_counter() - t0, 3), "skipped": not found.derived,
                        "folder": str(found.folder)})
    return {"scenes": results}


def _derive_committed(scenes, force: bool) -> list[dict]:
    """python -m levitron.derive (the runtime never imports sympy) on the scenes' absolute paths: the
    subprocess runs in the repository, not in the user's folder."""
    cmd = [sys.executable, "-m", "levitron.derive", *(str(Path(s.path).resolve()) for s in scenes), "--json"]
    if force:
        cmd.append("--force")
    from levitron.scene.paths import GENERATED
    from levitron.runtime.model.cache_sweep import sweep_generated
    from levitron.runtime.model.processes import die_with_parent
    res = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT, check=False, preexec_fn=die_with_parent)
    sweep_generated(GENERATED)            # what a killed earlier derive left (its folder stays whole)
    names = ", ".join(s.name for s in scenes)
    if res.returncode < 0:
        raise UserError(f"derive of {names} was killed (signal {-res.returncode}) before it finished: "
                        "generated/ holds the models as they were; run the command again (out of memory? "
                        "see `dmesg`)")
    if res.returncode != 0:
        last = (res.stderr.strip().splitlines() or [f"derive of {names} failed (exit {res.returncode}) "
                                                    "without a message"])[-1]
        raise UserError(last.removeprefix("error: "))
    return json.loads(res.stdout)["scenes"]


def human(r: dict, scene=None) -> str:
    """One line per scene: derived or unchanged, how long, where."""
    rows = []
    for s in r["scenes"]:
        what = "unchanged (skipped by hash)" if s.get("skipped") else "derived"
        where = f" -> {s['folder']}" if s.get("folder") else ""
        rows.append(f"{s['name']}: {what} in {duration(s.get('seconds'))}{where}")
    done = sum(1 for s in r["scenes"] if not s.get("skipped"))
    return lines(f"derive: {done} of {len(r['scenes'])} scenes derived", *rows)
