"""Replace a folder by another in one step that a kill cannot split, and clear what kills left.

`swap_in(new, target)`: where the kernel has it (Linux renameat2 RENAME_EXCHANGE), `new` and
`target` trade places in one system call, so `target` always exists and holds the old or the new
files; the old files, now under the temporary name, are removed after. Elsewhere two renames
(target -> .<name>.old-<pid>-*, new -> target); a kill between them leaves target missing, and
`recover(target)` (called before every write and read of the folder) renames the newest old copy
back. Temporary names carry the owner's pid: `sweep(parent, name)` removes those whose owner
process is gone and that are older than STALE_AFTER_S (a live writer's are never touched).
"""
from __future__ import annotations

import ctypes
import ctypes.util
import errno
import os
import re
import shutil
import time
from pathlib import Path

from levitron.scene.faults import die_at

STALE_AFTER_S = 60.0
_AT_FDCWD = -100
_RENAME_EXCHANGE = 2
_LIBC = None


def temp_prefix(name: str, kind: str) -> str:
    """`.<name>.<kind>-<pid>-` (kind "new" or "old"): the owner's pid is in the name."""
    return f".{name}.{kind}-{os.getpid()}-"


def _exchange(a: Path, b: Path) -> bool:
    """Swap a and b atomically (renameat2 RENAME_EXCHANGE); False where the system cannot."""
    global _LIBC
    if _LIBC is None:
        _LIBC = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
    fn = getattr(_LIBC, "renameat2", None)
    if fn is None:
        return False
    rc = fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def swap_in(new: Path, target: Path, exchange: bool = True) -> None:
    """Make `new` (a complete folder beside `target`) the folder `target`; remove the old one."""
    if not os.path.lexists(target):
        os.replace(new, target)
        return
    if exchange and _exchange(new, target):
        die_at("write_atomic.swapped")
        shutil.rmtree(new)                   # the old files, under the temporary name now
        return
    old = Path(str(new).replace(f".{target.name}.new-", f".{target.name}.old-", 1))
    os.replace(target, old)
    die_at("write_atomic.between_renames")
    os.replace(new, target)
    shutil.rmtree(old)


_PID = re.compile(r"\.(?:new|old)-(\d+)-")


def owner_alive(pid: int) -> bool:
    """Whether process `pid` still runs (a temporary's owner: sweeps leave a live owner's alone)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def recover(target: Path) -> None:
    """If `target` is missing but a kill left its old copy (.<name>.old-*), put the newest back."""
    if os.path.lexists(target) or not target.parent.is_dir():
        return
    olds = sorted(target.parent.glob(f".{target.name}.old-*"), key=lambda p: p.stat().st_mtime)
    for old in reversed(olds):
        if (old / "manifest.json").is_file():
            try:
                os.replace(old, target)
            except OSError:
                continue
            return


def sweep(parent: Path, name: str, stale_after: float = STALE_AFTER_S) -> list[Path]:
    """Remove .<name>.new-* / .old-* folders of dead owners older than stale_after seconds (after
    recover, so an old copy that is the only one left is put back first); returns them."""
    recover(parent / name)
    gone = []
    now = time.time()
    for p in list(parent.glob(f".{name}.new-*")) + list(parent.glob(f".{name}.old-*")):
        m = _PID.search(p.name)
        try:
            old_enough = now - p.lstat().st_mtime >= stale_after
        except FileNotFoundError:
            continue
        if m and not owner_alive(int(m.group(1))) and old_enough:
            shutil.rmtree(p, ignore_errors=True)
            gone.append(p)
    return gone
