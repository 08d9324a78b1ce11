"""The battery's fixture: a warm, shared cache.

Compiled libraries and derived models are copied into each case's fresh cache from a session
cache (seeded from the developer's cache, never written back there), so that a case compiles or
derives only what no earlier case made; what a case makes whole is kept for the next ones
(tests/helpers/battery.py copy_artefacts).
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from tests.helpers.battery import copy_artefacts


@pytest.fixture(scope="session")
def warm_cache(tmp_path_factory, seed_cache):
    warm = seed_cache(tmp_path_factory.mktemp("warm-cache"))     # at least the runtime/csrc objects
    home = os.environ.get("LEVITRON_CACHE") or str(Path.home() / ".cache" / "levitron")
    copy_artefacts(Path(home), warm)
    return warm
