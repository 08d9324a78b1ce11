"""The CPU the compiled code targets: what `-march=native` means on this machine, and the portable baseline.

`-march=native` (runtime/model/cbuild.py DEFAULT_FLAGS) lets the compiler use every instruction this CPU
has (fma() is one instruction), so a library built on one CPU may hold instructions another lacks. The
flag string is the same on every machine; `cpu_target` is not: the machine's architecture and the digest
of the compiler's predefined macros under the target flags (`cc -march=native -E -dM`: one macro per ISA
extension the code may use, __AVX2__, __FMA__, __ARM_FEATURE_SVE, and the CPU it is tuned for), probed
once per process. It is part of every compile cache key, so a cache folder shared by machines of
different CPUs (a cluster's home folder) holds one library per CPU and never hands a node another's.

LEVITRON_CFLAGS_PORTABLE=1 trades the speed for one library per architecture: `-march=native` becomes
`-march=x86-64-v2` on x86-64 (SSE4.2 and POPCNT: Intel since 2008, AMD since 2011) and is dropped
elsewhere (the compiler's default target: armv8-a on aarch64). The answers agree to rounding (no
contraction but where the C says so, fma() correctly rounded either way; `stability thesis_stable`'s
interval to a relative 2e-16, its resonances to 1e-12), only slower. Unset or 0: native.
"""
from __future__ import annotations

import hashlib
import os
import platform
import subprocess
from functools import cache

from levitron.runtime.errors import UserError

PORTABLE_ENV = "LEVITRON_CFLAGS_PORTABLE"
PORTABLE_MARCH = {"x86_64": "-march=x86-64-v2", "amd64": "-march=x86-64-v2"}
NATIVE = ("-march=native", "-mcpu=native", "-mtune=native")


def portable() -> bool:
    """Whether LEVITRON_CFLAGS_PORTABLE asks for the portable baseline (1) or this CPU (unset, empty, 0)."""
    value = os.environ.get(PORTABLE_ENV, "").strip()
    if value in ("", "0"):
        return False
    if value == "1":
        return True
    raise UserError(f"{PORTABLE_ENV}={value!r} is neither 0 nor 1: set it to 1 for code every CPU of this "
                    "architecture runs, or to 0 (or unset it) for code tuned to this CPU")


def target_flags(flags: tuple[str, ...]) -> tuple[str, ...]:
    """`flags` as the compiler gets them: unchanged (native), or with the native CPU flags replaced by
    the portable baseline of this architecture when LEVITRON_CFLAGS_PORTABLE=1."""
    if not portable():
        return tuple(flags)
    baseline = PORTABLE_MARCH.get(platform.machine().lower())
    out: list[str] = []
    for flag in flags:
        if flag == "-march=native" and baseline:
            out.append(baseline)
        elif flag not in NATIVE:
            out.append(flag)
    return tuple(out)


@cache
def cpu_target(cc: str, flags: tuple[str, ...]) -> str:
    """The CPU the code built by `cc` with `flags` targets, as a short string for the cache key: the
    machine's architecture, the target flags and the digest of the compiler's predefined macros under
    them (one per ISA extension it may use). Probed once per process and compiler; a compiler that
    refuses the flags gives its first line of complaint instead (the build then fails on its own)."""
    mflags = tuple(f for f in flags if f.startswith("-m"))
    try:
        res = subprocess.run([cc, *mflags, "-E", "-dM", "-x", "c", "-"], input="", capture_output=True,
                             text=True, check=False)
        macros = "\n".join(sorted(res.stdout.splitlines())) if res.returncode == 0 else \
            "unresolved: " + (res.stderr.strip().splitlines() or ["?"])[0]
    except OSError as exc:
        macros = f"unresolved: {exc}"
    digest = hashlib.sha256(macros.encode()).hexdigest()[:16]
    return " ".join([platform.machine(), *mflags, digest])
