"""Compile C sources into a shared library, cached by content hash.

The cache key is the SHA-256 of the compiler's identity, the flags, the CPU the code targets and the
bytes of every source file, so an edited model or integrator is rebuilt and an unchanged one is
loaded at once. The CPU is what `-march=native` resolves to on this machine (its architecture and
the compiler's ISA macros under the flags, probed once per process: runtime/model/cpu_target.py),
not the flag string, so a cache folder shared by machines of different CPUs (a cluster's home
folder) never hands one a library with instructions it lacks. LEVITRON_CFLAGS_PORTABLE=1 builds
for the architecture's baseline instead (`-march=x86-64-v2` on x86-64): one library for every CPU,
the answers equal to rounding, slower. The cache folder is $LEVITRON_CACHE, else the platform's user cache
folder (platformdirs: $XDG_CACHE_HOME/levitron, else ~/.cache/levitron on Linux). The
library is written to a temporary name and renamed into place, so an interrupted or failed build
never leaves a half-written file in the cache. Beside each library lies its size and sha256
(`lev_<key>.so.sha256`), checked before the library is returned (so before any dlopen, which can
SIGBUS on a truncated file): a damaged library is rebuilt once. Compiler errors are raised whole.

A library of several sources is linked from one object per source, each cached in `obj/` under
the SHA-256 of the compiler's identity, the flags and the source as the preprocessor sees it
(`cc -E -P`: every header it includes, wherever found), with a size-and-sha256 stamp like a
library's. runtime/csrc/integrators.c (most of the compile time of a model's library) is then
compiled once for all models, not once per model; the library is the same, byte for byte, as
one `cc ... -o lib.so a.c b.c` (gcc compiles each translation unit on its own either way).
Concurrent builds of one library or object (scan workers, test workers) are safe: each writes a
temporary file and renames it into place, and the compiler's output is the same every time; a
missing object is built by one process while the others wait (a lock on obj/: flock where fcntl
exists, a lock file elsewhere, runtime/model/folder_lock.py).
"""
from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from functools import cache
from pathlib import Path

from levitron.runtime.errors import UserError
from levitron.runtime.model.cpu_target import cpu_target, target_flags
from levitron.runtime.model.folder_lock import locked
from levitron.runtime.model.processes import die_with_parent

# no errno from sqrt: the lane variants of model.c vectorise; no contraction of a * b + c into an
# fma but where the C says so (LEV_FMA in model.c, LEV_MADD in integrators.c), so a function and its
# lane variant round alike (derive/emit/c/printer.py); -march=native: fma() is one instruction (the
# cache key holds the CPU it resolves to; LEVITRON_CFLAGS_PORTABLE=1 swaps it for the baseline: cpu_target.py)
DEFAULT_FLAGS = ("-O3", "-std=c99", "-fno-math-errno", "-ffp-contract=off", "-fPIC", "-shared",
                 "-march=native", "-Wall", "-Wextra")
STRICT_FLAGS = DEFAULT_FLAGS + ("-Werror",)       # the hand-written runtime/csrc alone


class CompileError(RuntimeError):
    """The C compiler rejected the sources; the message holds its complete output."""


class CacheError(UserError):
    """The cache folder cannot be made or written."""


def cache_problem(path: Path, exc: OSError) -> CacheError:
    """The one-line error for an OSError met while writing the cache at `path`."""
    why = exc.strerror or type(exc).__name__
    return CacheError(f"the cache {path} is not a writable folder ({why}): set LEVITRON_CACHE to a "
                      "writable folder")


_RESOLVED: dict[str, Path] = {}
_SWEPT: set[Path] = set()


def resolve_cache_env() -> Path:
    """$LEVITRON_CACHE as an absolute path, resolved once per value from the working directory of
    its first use, and written back to the environment, so that the derive subprocess (which runs in
    the repository) and scan workers use the same folder. Unset or empty: the platform's user cache
    folder (platformdirs: $XDG_CACHE_HOME/levitron, else ~/.cache/levitron on Linux;
    ~/Library/Caches/levitron on macOS; %LOCALAPPDATA%/levitron/Cache on Windows)."""
    root = os.environ.get("LEVITRON_CACHE")
    if not root:
        import platformdirs
        return Path(platformdirs.user_cache_dir("levitron", appauthor=False))
    if root not in _RESOLVED:
        _RESOLVED[root] = Path(os.path.abspath(os.path.expanduser(root)))
    path = _RESOLVED[root]
    _RESOLVED.setdefault(str(path), path)
    os.environ["LEVITRON_CACHE"] = str(path)
    return path


def cache_dir() -> Path:
    """Where compiled libraries and derived models live: $LEVITRON_CACHE, else the user cache folder
    (resolve_cache_env). Made if missing; CacheError when that is impossible (a file in the way, no
    permission). The first use in a process sweeps what killed runs left (runtime/model/cache_sweep.py)."""
    path = resolve_cache_env()
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        if os.path.islink(path) and not os.path.exists(path):
            raise CacheError(f"the cache {path} is a symbolic link to nothing (a loop, or its target "
                             "is missing): set LEVITRON_CACHE to a folder") from None
        raise cache_problem(path, exc) from None
    if path not in _SWEPT:
        _SWEPT.add(path)
        from levitron.scene.paths import GENERATED
        from levitron.runtime.model.cache_sweep import sweep_cache, sweep_generated
        sweep_cache(path)
        sweep_generated(GENERATED)
    return path


def compiler() -> str:
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    if not cc:
        raise CompileError("no C compiler on PATH: install gcc (apt-get install gcc) or set CC")
    return cc


@cache
def _compiler_identity(cc: str) -> str:
    out = subprocess.run([cc, "--version"], capture_output=True, text=True, check=False)
    return out.stdout.splitlines()[0] if out.stdout else cc


def source_hash(sources: list[Path], flags: tuple[str, ...],
                include_dirs: tuple[Path | str, ...] = ()) -> str:
    """The cache key: compiler, flags (as target_flags gives them), the CPU they target (cpu_target),
    the bytes of every source and of every header in the include folders or beside the sources (`*.h`,
    which takes in the fragments named .c.h: an edited header or fragment rebuilds too). Contents, not
    locations: the same model in another folder reuses the library."""
    flags = target_flags(tuple(flags))
    cc = compiler()
    h = hashlib.sha256()
    h.update(_compiler_identity(cc).encode())
    h.update("\0".join(flags).encode())
    h.update(b"\0" + cpu_target(cc, flags).encode())
    dirs = [*include_dirs, *(Path(s).parent for s in sources)]
    folders = dict.fromkeys(Path(d).resolve() for d in dirs)
    headers = [hdr for d in folders for hdr in sorted(d.glob("*.h"))]
    for src in [*sources, *headers]:
        h.update(b"\0" + Path(src).name.encode() + b"\0")
        h.update(Path(src).read_bytes())
    return h.hexdigest()[:24]


def _stamp_path(library: Path) -> Path:
    return library.with_name(library.name + ".sha256")


def _stamp(data: bytes) -> str:
    return f"{len(data)} {hashlib.sha256(data).hexdigest()}\n"


def is_intact(library: Path) -> bool:
    """The library exists and has the size and sha256 recorded beside it when it was built."""
    try:
        stamp = _stamp_path(library).read_text()
        size = int(stamp.split()[0])
        if library.stat().st_size != size:       # a truncated file: never read, never dlopen'ed
            return False
        return _stamp(library.read_bytes()) == stamp
    except (OSError, ValueError, IndexError):
        return False


def discard(library: Path) -> None:
    """Remove a cached library and its stamp (the next compile_shared builds it again)."""
    for path in (_stamp_path(library), library):
        try:
            path.unlink()
        except FileNotFoundError:
            pass
        except OSError as exc:
            raise cache_problem(path.parent, exc) from None


def compile_shared(sources: list[Path | str], flags: tuple[str, ...] = DEFAULT_FLAGS,
                   include_dirs: tuple[Path | str, ...] = ()) -> Path:
    """Compile `sources` into one shared library and return its cached, verified path.

    Raises CompileError with the compiler's full stderr when the build fails, CacheError when the
    cache cannot be written.
    """
    sources = [Path(s) for s in sources]
    flags = target_flags(tuple(flags))
    key = source_hash(sources, flags, include_dirs)
    all_flags = tuple(flags) + tuple(f"-I{d}" for d in include_dirs)
    cache = cache_dir()
    target = cache / f"lev_{key}.so"
    if is_intact(target):
        return target
    if target.is_dir():
        raise CacheError(f"{target} is a folder where the compiled library belongs: remove it")
    if target.exists():
        print(f"levitron: the cached library {target} is damaged (size or sha256 differs from "
              f"{_stamp_path(target).name}): rebuilding it", file=sys.stderr)
    cc = compiler()
    from levitron.runtime.ui import progress
    what = (f"{len(sources)} C sources" if len(sources) > 1 else sources[0].name)
    with progress.stages("compiling", [what, "linking"], [0.9, 0.1]) as stage:
        stage(0)
        if len(sources) > 1:        # link the cached objects, in the order of the sources
            objects = [compile_object(src, tuple(flags), include_dirs) for src in sources]
            stage(1)
            try:
                _build(target, [cc, *flags], [*map(str, objects), "-lm"])
            except CompileError:     # a damaged object whose stamp was written with it: built again, once
                print("levitron: linking the cached objects failed (one is damaged?): compiling them "
                      "again", file=sys.stderr)
                for obj in objects:
                    discard(obj)
                objects = [compile_object(src, tuple(flags), include_dirs) for src in sources]
                _build(target, [cc, *flags], [*map(str, objects), "-lm"])
        else:
            _build(target, [cc, *all_flags], [*map(str, sources), "-lm"])
    return target


def compile_object(source: Path | str, flags: tuple[str, ...] = DEFAULT_FLAGS,
                   include_dirs: tuple[Path | str, ...] = ()) -> Path:
    """The cached, verified object file (`obj/<key>.o`) of one source compiled with `flags` and the
    include folders: keyed by the compiler, `flags` and the preprocessed source, so a source that
    sees the same headers in every model's build (runtime/csrc/*.c) has one object for them all.
    One process builds a missing object while the others wait for it (a lock on obj/)."""
    source = Path(source)
    cc = compiler()
    flags = target_flags(tuple(flags))
    all_flags = tuple(flags) + tuple(f"-I{d}" for d in include_dirs)
    cmd = [cc, *all_flags, "-E", "-P", str(source)]
    pre = subprocess.run(cmd, capture_output=True, check=False)
    if pre.returncode != 0:
        raise CompileError(f"C compilation failed ({' '.join(cmd)}):\n"
                           f"{pre.stderr.decode(errors='replace')}")
    h = hashlib.sha256()
    h.update(_compiler_identity(cc).encode())
    h.update("\0".join(flags).encode() + b"\0")
    h.update(cpu_target(cc, flags).encode() + b"\0")
    h.update(pre.stdout)
    folder = cache_dir() / "obj"
    try:
        folder.mkdir(exist_ok=True)
    except OSError as exc:
        raise cache_problem(folder, exc) from None
    target = folder / f"{h.hexdigest()[:24]}.o"
    if is_intact(target):
        return target
    with locked(folder):
        if is_intact(target):                 # built by another process meanwhile
            return target
        if target.exists():
            print(f"levitron: the cached object {target} is damaged (size or sha256 differs from "
                  f"{_stamp_path(target).name}): rebuilding it", file=sys.stderr)
        _build(target, [cc, *all_flags, "-c"], [str(source)])
    return target


def _build(target: Path, before: list[str], after: list[str]) -> None:
    """Run `before -o TMP after` into a temporary file and rename it (and its stamp, first) into
    place: readers never see a half-written file, and a damaged one is replaced, never written in
    place."""
    tmps: list[str] = []
    try:
        try:
            for suffix in (target.suffix, ".sha256"):
                fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}_{os.getpid()}_", suffix=suffix,
                                           dir=target.parent)
                os.close(fd)
                tmps.append(tmp)
        except OSError as exc:
            raise cache_problem(target.parent, exc) from None
        tmp_out, tmp_stamp = tmps
        cmd = [*before, "-o", tmp_out, *after]
        res = subprocess.run(cmd, capture_output=True, text=True, check=False,
                             preexec_fn=die_with_parent)
        if res.returncode != 0:
            if not target.parent.is_dir():
                raise CacheError(f"the cache folder {target.parent} was removed while the C compiler "
                                 "ran: run the command again")
            raise CompileError(f"C compilation failed ({' '.join(cmd)}):\n{res.stderr}{res.stdout}")
        try:
            Path(tmp_stamp).write_text(_stamp(Path(tmp_out).read_bytes()))
            os.replace(tmp_stamp, _stamp_path(target))
            os.replace(tmp_out, target)
        except OSError as exc:
            raise cache_problem(target.parent, exc) from None
    finally:
        for tmp in tmps:
            if os.path.exists(tmp):
                os.unlink(tmp)
