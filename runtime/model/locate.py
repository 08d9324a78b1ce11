"""Where a scene's model lives, and making it exist there: generated/<name>/ for a scene of scenes/
(committed by `make derive`), else a folder of the cache keyed by the input hash (scene/inputs.py),
derived into it in a subprocess (`python -m levitron.derive`, the only route to sympy) when missing,
stale or damaged, and installed by one rename (a killed run leaves no half-written folder). What is
found is verified before use (runtime/model/manifest.py); runtime/model/load.py loads it. No sympy here.

A model is found by its content: the input hash covers the scene's physics, not its name or its
description, so a renamed copy of a scene (or another scene of the same structure) uses the model
already derived for it, in generated/<other>/ or in the cache's derived/<other>-<hash>/.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import NamedTuple

import tomli_w

from levitron.scene.faults import die_at
from levitron.scene.inputs import input_hash
from levitron.scene.paths import GENERATED, ROOT, is_committed_scene
from levitron.scene.load import Scene

from levitron.runtime.model.cbuild import cache_dir, cache_problem, locked
from levitron.runtime.errors import UserError
from levitron.runtime.model.manifest import ArtefactError, Manifest, read_manifest
from levitron.runtime.model.processes import die_with_parent
from levitron.runtime.ui import progress


def committed_folder(scene: Scene) -> Path | None:
    """generated/<name>/ for a scene of scenes/ (its committed model), else None."""
    return GENERATED / scene.name if is_committed_scene(scene.name, scene.path) else None


def cache_folder(scene: Scene) -> Path:
    """The cache folder of the scene's model: keyed by the input hash (scene/inputs.py)."""
    return cache_dir() / "derived" / f"{scene.name}-{input_hash(scene.data)[:16]}"


def _manifest_hash(folder: Path) -> str | None:
    try:
        data = json.loads((folder / "manifest.json").read_text())
    except (OSError, UnicodeDecodeError, json.JSONDecodeError):
        return None
    return data.get("input_hash") if isinstance(data, dict) else None


class Located(NamedTuple):
    """A verified model folder: where, its manifest, what to do when it is damaged, and whether
    this call derived it."""

    folder: Path
    manifest: Manifest
    fix: str
    derived: bool


def make_derive_fix(name: str) -> str:
    return f"run `make derive` to regenerate generated/{name}"


def locate(scene: Scene, force: bool = False) -> Located:
    """The scene's verified model folder: generated/<name>/ when it is current for the scene (a scene
    of scenes/, also with --set overrides of numbers, which are runtime parameters), else a folder
    in the cache keyed by the input hash, derived first (python -m levitron.derive, in a subprocess: the
    runtime does not import sympy) when missing, damaged (derived again, once) or `force`d. Before
    deriving, a model of the same input hash under another name is used (`_same_content`): the hash
    covers the physics, not the scene's name.

    The runtime never writes into generated/ (only `make derive` does): a damaged current
    generated/<name> is an ArtefactError naming the file."""
    ihash = input_hash(scene.data)
    committed = committed_folder(scene)
    if committed is not None and _manifest_hash(committed) == ihash and not force:
        fix = make_derive_fix(scene.name)
        return Located(committed, read_manifest(committed, fix, ihash), fix, False)
    out = cache_folder(scene)
    fix = f"delete {out} (or run `make clean-cache`) and try again"
    note = None
    if committed is not None and committed.exists() and not scene.overrides:
        note = (f"generated/{scene.name} is stale (the scene or derive/ changed): using a fresh "
                "derivation in the cache; run `make derive` to update generated/")
    if not force:
        try:
            return Located(out, read_manifest(out, fix, ihash), fix, False)
        except ArtefactError as exc:
            if os.path.lexists(out):
                note = f"the cached model is damaged ({str(exc).split('; ')[0]}): deriving it again"
        same = _same_content(ihash, out)     # the same physics derived under another name
        if same is not None:
            return same
    _derive_into(scene, out, ihash, note)
    return Located(out, read_manifest(out, fix, ihash), fix, True)


def _same_content(ihash: str, own: Path) -> Located | None:
    """An intact model of the same input hash derived under another name: a folder of generated/
    (in name order), else one of the cache's derived/ (<name>-<hash>); None when there is none. A
    damaged one is passed over (the scene's own cache folder is derived instead)."""
    def intact(folder: Path, fix: str) -> Located | None:
        if folder == own or _manifest_hash(folder) != ihash:
            return None
        try:
            return Located(folder, read_manifest(folder, fix, ihash), fix, False)
        except ArtefactError:
            return None
    try:
        shipped = sorted(p for p in GENERATED.iterdir() if not p.name.startswith("."))
    except OSError:
        shipped = []
    for folder in shipped:
        if (found := intact(folder, make_derive_fix(folder.name))) is not None:
            return found
    try:
        cached = sorted(own.parent.glob(f"*-{ihash[:16]}"))
    except OSError:
        cached = []
    for folder in cached:
        if not folder.name.startswith(".") and (found := intact(
                folder, f"delete {folder} (or run `make clean-cache`) and try again")) is not None:
            return found
    return None


def _derive_into(scene: Scene, out: Path, ihash: str, note: str | None = None) -> None:
    """Derive the scene into `out` (a cache folder): into a temporary folder beside it, then one
    rename, so concurrent processes (scan workers) never see a half-written model. The temporary
    folder is removed on every path. `note`: why, said once the cache is known to be writable."""
    if scene.path is None:
        raise UserError(f"scene '{scene.name}' was not read from a file: nothing to derive from")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{scene.name}-{os.getpid()}-", dir=out.parent))
    except OSError as exc:
        raise cache_problem(out.parent, exc) from None
    if note:
        print(f"levitron: {note}", file=sys.stderr)
    print(f"levitron: deriving the model of scene '{scene.name}' ...", file=sys.stderr)
    try:
        # the scene as this process read it (overrides applied), written by a TOML writer: the
        # child derives exactly what is hashed here, even if the file is edited meanwhile
        snapshot = tmp / f"{scene.name}.toml"
        snapshot.write_text(tomli_w.dumps(scene.data), encoding="utf-8")
        cmd = [sys.executable, "-m", "levitron.derive", str(snapshot), "--out", str(tmp), "--force", "--stages"]
        child = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                                 cwd=ROOT, preexec_fn=die_with_parent)
        try:
            die_at("runtime.deriving")
            err = _follow_stages(child)
        finally:
            if child.poll() is None:         # interrupted (SIGTERM, Ctrl-C): the child goes too
                child.kill()
                child.wait()
        if child.returncode < 0:
            raise UserError(f"derive for scene '{scene.name}' was killed (signal {-child.returncode}) "
                            "before it finished: run the command again (out of memory? see `dmesg`)")
        if child.returncode != 0:
            last = (err.strip().splitlines() or ["no message"])[-1].removeprefix("error: ")
            raise UserError(f"derive failed for scene '{scene.name}': {last}")
        _install(tmp / scene.name, out, tmp, ihash)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


# the stages of python -m levitron.derive --stages (derive/__main__.py's STAGES) and their shares of a
# derivation's time (measured: thesis and ring_magnet at field orders 4 and 6), for the ETA
DERIVE_STAGES = ("the plate's on-axis potential", "the field's order", "the reduced model",
                 "Hamilton's equations", "the full model's Jacobian and energy",
                 "common subexpressions", "C and CasADi files")
DERIVE_WEIGHTS = (0.3, 0.1, 1.2, 0.9, 1.7, 1.25, 0.15)


def _follow_stages(child) -> str:
    """Read the derive child's stderr to its end, showing each "stage k/n NAME" line as a progress
    stage ("deriving: Hamilton's equations 4/7", runtime/ui/progress.py); returns the other lines."""
    import re
    rest = []
    with progress.stages("deriving", DERIVE_STAGES, DERIVE_WEIGHTS) as stage:
        for line in child.stderr:
            m = re.match(r"stage (\d+)/(\d+) ", line)
            if m and int(m.group(2)) == len(DERIVE_STAGES):
                stage(int(m.group(1)) - 1)
            else:
                rest.append(line)
    child.wait()
    return "".join(rest)


def _intact(folder: Path, ihash: str) -> bool:
    try:
        read_manifest(folder, "", ihash)
    except ArtefactError:
        return False
    return True


def _install(new: Path, out: Path, trash: Path, ihash: str) -> None:
    """Rename `new` to `out`; a damaged `out` is first moved into `trash` (removed by the caller),
    an intact one (another process's identical result, installed meanwhile) is kept. Under a lock
    on the cache's derived/ folder, so that two processes that derived the same model at once
    never take each other's installed result for a damaged one."""
    with locked(out.parent):
        _install_unlocked(new, out, trash, ihash)


def _install_unlocked(new: Path, out: Path, trash: Path, ihash: str) -> None:
    if _intact(out, ihash):
        return
    try:
        if os.path.lexists(out):
            try:
                os.replace(out, trash / "damaged")
            except FileNotFoundError:
                pass                          # another process moved it at the same moment
        os.replace(new, out)
    except OSError as exc:
        if _manifest_hash(out) != ihash:      # not another process's identical result: a real error
            raise cache_problem(out.parent, exc) from None
