"""Every output file the tool writes: a temporary beside it, then one rename.

`output(path, option)` is a context manager that yields a temporary path in the target's folder
(`.<name>.<pid>-<hex>.tmp<suffix>`: the owner's pid in the name, the target's suffix kept for
writers that choose a format by it; `.t.<pid>-<hex>.tmp<suffix>` where the long name would not fit
the folder's NAME_MAX), created empty with mode 0666 less the umask (what `open`
gives, so a written file has the usual 0644, never mkstemp's 0600). When the block ends normally
the file is flushed to disk and renamed over the target in one step; on any error the temporary
is removed and the target is untouched. So a kill, a full disk or a file-size limit never leaves
a half file under the target's name, and two concurrent writers leave one whole file (the last
rename). An OSError becomes one UserError line naming the option and what to do.

Paths are taken as the user gave them: a path through a symbolic link writes the link's target
(`os.path.realpath`: the temporary in the target's folder, the link kept), and a missing folder is
made, for every writer alike (plots, pages, animations and tables: `check_target` checks a path
before the work, the same way for each).

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


NAME_MAX = 255          # bytes of one file name where the folder does not say (Linux, macOS)


def name_max(folder: Path) -> int:
    """The longest file name (bytes) the file system of `folder` (or of its nearest existing
    ancestor) takes: PC_NAME_MAX, else NAME_MAX."""
    for f in (Path(folder), *Path(folder).parents):
        try:
            return int(os.pathconf(f, "PC_NAME_MAX"))
        except (OSError, ValueError):
            continue
    return NAME_MAX


def temp_beside(path: Path) -> Path:
    """The temporary name for `path` (module docstring): the long form where it fits the folder's
    NAME_MAX, else a short one (the suffix kept where it is a plain one)."""
    tag = f"{os.getpid()}-{secrets.token_hex(4)}.tmp"
    long = f".{path.name}.{tag}{path.suffix}"
    if len(os.fsencode(long)) <= name_max(path.parent):
        return path.with_name(long)
    suffix = path.suffix if re.fullmatch(r"\.[A-Za-z0-9]{1,16}", path.suffix) else ""
    return path.with_name(f".t.{tag}{suffix}")


def target(path) -> Path:
    """Where a write of `path` lands: the path itself, or through symbolic links the file they
    point to (os.path.realpath), so that a link is written through, never replaced. Links that
    loop point to no file: an OSError (ELOOP), never the link itself to replace."""
    real = Path(os.path.realpath(path))
    if real.is_symlink():           # realpath stops where the links loop
        raise OSError(errno.ELOOP, os.strerror(errno.ELOOP), str(path))
    return real


def check_target(path, option: str, example: str) -> Path:
    """`path` as an output file, checked before any work is done (nothing is created here), the one
    check of every writer: not a folder, a name the file system takes, below a folder that exists
    and is writable or can be made there (`output` makes it). `example`: a file name to suggest.
    One-line UserError otherwise; returns the path as given."""
    from levitron.runtime.ui.validate import shown
    p = Path(path)
    try:
        _fits(p, option, shown(path))           # the name as given (a longer one cannot be looked up)
        real = target(path)
        _fits(real, option, shown(path))        # and the link's target's
        if p.is_dir() or not p.name:
            raise UserError(f"{option} {shown(path)} is a folder: give a file name in it, e.g. {option} "
                            f"{shown(p / example)}")
        folder = next((f for f in real.parents if f.exists()), Path("."))
        if not folder.is_dir():
            raise UserError(f"{option} {shown(path)}: {shown(folder)} is a file, not a folder: choose "
                            "another path")
        if not os.access(folder, os.W_OK | os.X_OK):
            raise UserError(f"{option} {shown(path)}: the folder {shown(folder)} is not writable: choose "
                            "another path")
    except OSError as exc:                      # a path too long as a whole, a loop of links, ...
        raise _problem(option, p, exc) from None
    return p


def _fits(p: Path, option: str, shown_path: str) -> None:
    size, limit = len(os.fsencode(p.name)), name_max(p.parent)
    if size > limit:
        raise UserError(f"{option} {shown_path}: the file name is {size} bytes long, more than the "
                        f"{limit} the file system takes: give a shorter name")


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
def output(path, option: str, mkdir: bool = True):
    """Yield a temporary beside `path` (through links: beside their target); rename it over that
    target when the block succeeds (module docstring). `option` names the flag or argument in the
    error line. A missing folder is made (every writer alike; `mkdir` is kept for old callers)."""
    given = Path(path)
    check_target(given, option, f"file{given.suffix}")   # a writer that checked nothing before its work
    path = target(given)
    tmp = None
    try:
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
        raise _problem(option, given, exc) from None
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def write_text(path, text: str, option: str, mkdir: bool = True) -> Path:
    """`text` (UTF-8) to `path` through `output`."""
    with output(path, option, mkdir) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_bytes(path, data: bytes, option: str, mkdir: bool = True) -> Path:
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
