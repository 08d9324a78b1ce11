"""The tests' C library: runtime/csrc (the integrators, the scan driver, the thesis's circle) with the
test systems of tests/c/systems.c linked in (the oscillator, Kepler, the blow-up, the drift), built
once per run into the cache like any library (runtime/integrate/c_backend.py csrc_library)."""
from __future__ import annotations

import ctypes
from functools import cache
from pathlib import Path

SYSTEMS = Path(__file__).resolve().parents[1] / "c" / "systems.c"


@cache
def library() -> ctypes.CDLL:
    from levitron.runtime.integrate.c_backend import csrc_library
    return csrc_library((SYSTEMS,))
