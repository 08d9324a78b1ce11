"""Compile C sources into a shared library, cached by content hash.

The cache key is the SHA-256 of the compiler's identity, the flags and the bytes of every source
file, so an edited model or integrator is rebuilt and an unchanged one is loaded at once. The
library is written to a temporary name and renamed into place, so an interrupted or failed build
never leaves a half-written file in the cache. Compiler errors are raised whole, never swallowed.
"""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import tempfile
from functools import lru_cache
from pathlib import Path

DEFAULT_FLAGS = ("-O3", "-std=c99", "-fPIC", "-shared", "-march=native", "-Wall", "-Wextra")


class CompileError(RuntimeError):
    """The C compiler rejected the sources; the message holds its complete output."""


def cache_dir() -> Path:
    """Where compiled libraries live: $LEVITRON_CACHE, else ~/.cache/levitron."""
    root = os.environ.get("LEVITRON_CACHE")
    path = Path(root) if root else Path.home() / ".cache" / "levitron"
    path.mkdir(parents=True, exist_ok=True)
    return path


def compiler() -> str:
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        raise CompileError("no C compiler on PATH: install gcc (apt-get install gcc) or set CC")
    return cc


@lru_cache(maxsize=None)
def _compiler_identity(cc: str) -> str:
    out = subprocess.run([cc, "--version"], capture_output=True, text=True, check=False)
    return out.stdout.splitlines()[0] if out.stdout else cc


def source_hash(sources: list[Path], flags: tuple[str, ...]) -> str:
    h = hashlib.sha256()
    h.update(_compiler_identity(compiler()).encode())
    h.update("\0".join(flags).encode())
    for src in sources:
        h.update(b"\0" + Path(src).name.encode() + b"\0")
        h.update(Path(src).read_bytes())
    return h.hexdigest()[:24]


def compile_shared(sources: list[Path | str], flags: tuple[str, ...] = DEFAULT_FLAGS,
                   include_dirs: tuple[Path | str, ...] = ()) -> Path:
    """Compile `sources` into one shared library and return its cached path (thesis-independent).

    Raises CompileError with the compiler's full stderr when the build fails.
    """
    sources = [Path(s) for s in sources]
    all_flags = tuple(flags) + tuple(f"-I{d}" for d in include_dirs)
    key = source_hash(sources, all_flags)
    target = cache_dir() / f"lev_{key}.so"
    if target.exists():
        return target
    cc = compiler()
    fd, tmp = tempfile.mkstemp(prefix=f".lev_{key}_", suffix=".so", dir=cache_dir())
    os.close(fd)
    cmd = [cc, *all_flags, "-o", tmp, *map(str, sources), "-lm"]
    try:
        res = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if res.returncode != 0:
            raise CompileError(f"C compilation failed ({' '.join(cmd)}):\n{res.stderr}{res.stdout}")
        os.replace(tmp, target)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return target
