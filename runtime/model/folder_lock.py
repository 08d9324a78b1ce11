"""An exclusive lock on a cache folder between processes, on every platform.

Where fcntl exists (Linux, macOS, the BSDs): flock on the folder itself, no lock file to leave behind,
released by the kernel when its holder dies. Elsewhere (Windows, or a Python without fcntl): a lock file
`.levitron.lock` in the folder, made with O_CREAT | O_EXCL (one process wins) and removed on release; one
older than STALE_S is taken for a killed holder's and removed. A lock that cannot be had (a file system
without flock, a folder that cannot be opened) is no lock: the callers write by atomic rename, so a
double build is slower, never wrong. fcntl is imported on use, so importing the runtime never needs it.
"""
from __future__ import annotations

import os
import time
from contextlib import contextmanager
from pathlib import Path

LOCK_NAME = ".levitron.lock"
STALE_S = 120.0          # longer than any build under the lock (integrators.c: about 10 seconds)
POLL_S = 0.05


def flock_module():
    """fcntl where the platform has it, else None."""
    try:
        import fcntl
    except ImportError:
        return None
    return fcntl


@contextmanager
def locked(folder: Path):
    """An exclusive lock on `folder` (between processes): flock on the folder where fcntl exists,
    else a lock file beside what it guards."""
    fcntl = flock_module()
    if fcntl is None:
        with lock_file(folder):
            yield
        return
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        yield
        return
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX)
        except OSError:
            pass
        yield
    finally:
        os.close(fd)                           # closing releases the lock


@contextmanager
def lock_file(folder: Path):
    """The lock without fcntl: `folder/.levitron.lock`, made exclusively, waited for while another
    process holds it, broken when older than STALE_S, removed on release."""
    path = Path(folder) / LOCK_NAME
    held = False
    while not held:
        try:
            fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o644)
        except FileExistsError:
            try:
                if time.time() - path.stat().st_mtime > STALE_S:
                    path.unlink()
                    continue
            except FileNotFoundError:       # released meanwhile
                continue
            except OSError:
                break
            time.sleep(POLL_S)
            continue
        except OSError:                     # a folder where no file can be made: no lock
            break
        os.write(fd, f"{os.getpid()}\n".encode())
        os.close(fd)
        held = True
    try:
        yield
    finally:
        if held:
            try:
                path.unlink()
            except OSError:
                pass
