"""Every output file the tool writes: a temporary beside it, then one rename.

`output(path, option)` is a context manager that yields a temporary path in the target's folder
(`.<name>.<pid>-<hex>.tmp<suffix>`: the owner's pid in the name, the target's suffix kept for
writers that choose a format by it), created empty with mode 0666 less the umask (what `open`
gives, so a written file has the usual 0644, never mkstemp's 0600). When the block ends normally
the file is flushed to disk and renamed over the target in one step; on any error the temporary
is removed and the target is untouched. So a kill, a full disk or a file-size limit never leaves
a half file under the target's name, and two concurrent writers leave one whole file (the last
rename). An OSError becomes one UserError line naming the option and what to do.

`sweep(folder)` removes the temporaries of this pattern whose owner process is gone and that are
older than STALE_AFTER_S (a kill -9 leaves them); every `output` into a folder sweeps it first.
`sweep(folder, pattern)` does the same for another pid-named pattern (the report's scratch
folders, runtime/report/page.py).
"""
from __future__ import annotations

import errno
import os
import re
import secrets
import shutil
import time
from contextlib import contextmanager
from pathlib import Path

from levitron.derive.atomic_dir import owner_alive
from levitron.scene.faults import die_at
from levitron.runtime.errors import UserError

STALE_AFTER_S = 60.0
_FULL = (errno.EFBIG, errno.ENOSPC, errno.EDQUOT)
_TMP = re.compile(r"\..+\.(\d+)-[0-9a-f]{8}\.tmp(\.[A-Za-z0-9]+)?\Z", re.S)


def temp_beside(path: Path) -> Path:
    """The temporary name for `path` (module docstring)."""
    return path.with_name(f".{path.name}.{os.getpid()}-{secrets.token_hex(4)}.tmp{path.suffix}")


def stale(path: Path, pid: int, now: float, stale_after: float = STALE_AFTER_S) -> bool:
    """Whether a temporary of owner `pid` may go: the owner is dead (not this process) and the
    file is older than `stale_after` seconds."""
    try:
        age = now - path.lstat().st_mtime
    except FileNotFoundError:
        return False
    return age >= stale_after and pid != os.getpid() and not owner_alive(pid)


def sweep(folder: Path, pattern: re.Pattern = _TMP, stale_after: float = STALE_AFTER_S) -> list[Path]:
    """Remove the stale temporaries in `folder` whose names match `pattern` (group 1: the owner's
    pid; default: the output temporaries of the module docstring), files or folders; returns them."""
    now, gone = time.time(), []
    try:
        names = [n for n in os.listdir(folder) if pattern.match(n)]
    except OSError:
        return gone
    for name in names:
        path = Path(folder) / name
        if not stale(path, int(pattern.match(name).group(1)), now, stale_after):
            continue
        try:
            if path.is_dir() and not path.is_symlink():
                shutil.rmtree(path)
            else:
                path.unlink()
        except OSError:
            continue                        # taken meanwhile, or read-only: the next run tries again
        gone.append(path)
    return gone


def _problem(option: str, path: Path, exc: OSError) -> UserError:
    why = exc.strerror or str(exc)
    from levitron.runtime.ui.validate import shown
    return UserError(f"{option} {shown(path)}: cannot write it ({why}); choose another path"
                     + (" or free some space" if exc.errno in _FULL else ""))


@contextmanager
def output(path, option: str, mkdir: bool = False):
    """Yield a temporary beside `path`; rename it over `path` when the block succeeds (module
    docstring). `option` names the flag or argument in the error line; `mkdir`: make the folder."""
    path = Path(path)
    tmp = None
    try:
        if mkdir:
            path.parent.mkdir(parents=True, exist_ok=True)
        sweep(path.parent)
        tmp = temp_beside(path)
        os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
        yield tmp
        die_at("output.written")            # the kill tests' point (scene/faults.py)
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
        tmp = None
    except OSError as exc:
        raise _problem(option, path, exc) from None
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def write_text(path, text: str, option: str, mkdir: bool = False) -> Path:
    """`text` (UTF-8) to `path` through `output`."""
    with output(path, option, mkdir) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_bytes(path, data: bytes, option: str, mkdir: bool = False) -> Path:
    """`data` to `path` through `output`."""
    with output(path, option, mkdir) as tmp:
        tmp.write_bytes(data)
    return Path(path)


@contextmanager
def open_text(path, option: str, newline: str | None = None):
    """A text file handle (UTF-8) on a temporary beside `path`, renamed over it when the block
    succeeds (`output`): for writers that take a file, e.g. csv.writer."""
    with output(path, option) as tmp, open(tmp, "w", encoding="utf-8", newline=newline) as fh:
        yield fh
