"""Sweep what killed runs left in the cache: temporaries whose owner process is gone.

The runtime names every temporary of the cache after its owner's pid: derived/.<scene>-<pid>-*
(a derivation in progress, runtime/model/load.py), .lev_<key>_<pid>_*.so / .sha256 (a compilation,
runtime/model/cbuild.py) and heyoka/.<key>-<pid>-*.tmp (a compiled heyoka integrator being written,
runtime/bench/heyoka.py). A kill -9 or a SIGTERM during `timeout` leaves them behind; the first use of
the cache in a later process removes those whose owner is dead and that are older than
STALE_AFTER_S (so a live writer's, or one of another machine sharing the folder, are left alone
for a minute at least).
"""
from __future__ import annotations

import os
import re
import shutil
import time
from pathlib import Path

from levitron.derive.atomic_dir import owner_alive

STALE_AFTER_S = 60.0
_DERIVED_TMP = re.compile(r"\.[A-Za-z0-9_-]+?-(\d+)-[A-Za-z0-9_]+\Z")
_LIB_TMP = re.compile(r"\.lev_[0-9a-f]+_(\d+)_[A-Za-z0-9_]+\.(so|sha256)\Z")
_HEYOKA_TMP = re.compile(r"\.[0-9a-f]+-(\d+)-[0-9a-f]+\.tmp\Z")




def _stale(path: Path, pid: int, now: float, stale_after: float) -> bool:
    try:
        age = now - path.lstat().st_mtime
    except FileNotFoundError:
        return False
    return age >= stale_after and pid != os.getpid() and not owner_alive(pid)


def sweep_cache(root: Path, stale_after: float = STALE_AFTER_S) -> list[Path]:
    """Remove the stale temporaries of `root`, `root`/derived and `root`/heyoka (module docstring);
    returns them."""
    now, gone = time.time(), []
    candidates = []
    try:
        candidates += [(p, _LIB_TMP.match(p.name)) for p in root.iterdir() if p.name.startswith(".")]
        derived = root / "derived"
        if derived.is_dir():
            candidates += [(p, _DERIVED_TMP.match(p.name)) for p in derived.iterdir()
                           if p.name.startswith(".")]
        heyoka = root / "heyoka"
        if heyoka.is_dir():
            candidates += [(p, _HEYOKA_TMP.match(p.name)) for p in heyoka.iterdir()
                           if p.name.startswith(".")]
    except OSError:
        return gone                          # an unreadable cache: cache_dir's users say so
    for path, m in candidates:
        if m is None or not _stale(path, int(m.group(1)), now, stale_after):
            continue
        try:
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path)
            else:
                path.unlink()
        except OSError:
            continue                         # read-only or taken meanwhile: the next run tries again
        gone.append(path)
    return gone
