"""Sweep what killed runs left in the cache and in generated/: temporaries whose owner is gone.

The runtime names every temporary of the cache after its owner's pid: derived/.<scene>-<pid>-*
(a derivation in progress, runtime/model/load.py), .lev_<key>_<pid>_*.so / .sha256 (a compilation,
runtime/model/cbuild.py), obj/.<key>_<pid>_*.o / .sha256 (a compiled object, the same) and
heyoka/.<key>-<pid>-*.tmp (a compiled heyoka integrator being written, runtime/bench/heyoka.py).
A kill -9 or a SIGTERM during `timeout` leaves them behind; the first use of the cache in a later
process removes those whose owner is dead and that are older than STALE_AFTER_S (so a live
writer's, or one of another machine sharing the folder, are left alone for a minute at least).
`sweep_generated` does the same for generated/.<scene>.new-* / .old-* (a killed `make derive`;
derive/atomic_dir.py's own sweep runs only when that scene is written again).
"""
from __future__ import annotations

import re
from pathlib import Path

from levitron.runtime.ui.atomic import sweep

STALE_AFTER_S = 60.0
_DERIVED_TMP = re.compile(r"\.[A-Za-z0-9_-]+?-(\d+)-[A-Za-z0-9_]+\Z")
_LIB_TMP = re.compile(r"\.lev_[0-9a-f]+_(\d+)_[A-Za-z0-9_]+\.(so|sha256)\Z")
_OBJ_TMP = re.compile(r"\.[0-9a-f]+_(\d+)_[A-Za-z0-9_]+\.(o|sha256)\Z")
_GENERATED_TMP = re.compile(r"\.([A-Za-z0-9_-]+)\.(?:new|old)-\d+-")
_HEYOKA_TMP = re.compile(r"\.[0-9a-f]+-(\d+)-[0-9a-f]+\.tmp\Z")


def sweep_cache(root: Path, stale_after: float = STALE_AFTER_S) -> list[Path]:
    """Remove the stale temporaries of `root`, `root`/derived, `root`/obj and `root`/heyoka (module
    docstring; runtime/ui/atomic.py sweep, files or folders); returns them."""
    places = ((root, _LIB_TMP), (root / "derived", _DERIVED_TMP), (root / "obj", _OBJ_TMP),
              (root / "heyoka", _HEYOKA_TMP))
    return [p for folder, pattern in places for p in sweep(folder, pattern, stale_after)]


def sweep_generated(generated: Path, stale_after: float = STALE_AFTER_S) -> list[Path]:
    """Remove the stale .<scene>.new-* / .old-* folders of `generated` (derive/atomic_dir.py sweep:
    a scene whose folder a kill left missing gets its old copy back first); returns them."""
    from levitron.derive.atomic_dir import sweep as sweep_scene
    try:
        names = {m.group(1) for p in generated.iterdir() if (m := _GENERATED_TMP.match(p.name))}
    except OSError:
        return []
    return [p for name in sorted(names) for p in sweep_scene(generated, name, stale_after)]
