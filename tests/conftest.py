"""Shared fixtures: the thesis scene and model, and scenes derived into temporary folders."""
from __future__ import annotations

import shutil
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from levitron.scene.load import load_scene  # noqa: E402


@pytest.fixture(scope="session")
def thesis_scene():
    return load_scene("thesis")


@pytest.fixture(scope="session")
def thesis_model(thesis_scene):
    from levitron.runtime.model.load import load_model
    return load_model(thesis_scene)


LIGHT_TOP = ("top.mass=0.0515",)


@pytest.fixture(scope="module")
def model():
    """The thesis's model with a 51.5 g top (LIGHT_TOP): the one the maps, the C call path and the
    integrator's `auto` run on."""
    from levitron.runtime.model.load import load_model
    return load_model(load_scene("thesis", list(LIGHT_TOP)))


@pytest.fixture(scope="module")
def study():
    """The API's Study of thesis_stable, as written."""
    import levitron
    return levitron.load("thesis_stable")


@pytest.fixture(scope="module")
def toy():
    """levitron_toy's model, as the API loads it (its resonances: the trim's and design's advice)."""
    import levitron
    return levitron.load("levitron_toy").model


@pytest.fixture(scope="module")
def level(derived_model):
    """thesis_stable on a level base: the reference of the tilted-base and tilted-moment tests."""
    return derived_model("thesis_stable")


@pytest.fixture(scope="session")
def lib():
    """The tests' C library: runtime/csrc with the systems of tests/c/systems.c (tests/helpers/c_systems.py)."""
    from tests.helpers import c_systems
    return c_systems.library()


@pytest.fixture(scope="module")
def osc(lib):
    """The unit oscillator of tests/c/systems.c as a C system (x, y, vx, vy; p[0] = w2 = 1)."""
    from levitron.runtime.integrate.c_backend import CSystem
    return CSystem(lib, "lev_oscillator", ["x", "y", "vx", "vy"], [1.0])


@pytest.fixture(scope="session")
def derived_model():
    """derived_model(scene_name, *overrides) -> the Model of a scene variant, as a user gets it
    (runtime/model/load.py load_model: derived once into $LEVITRON_CACHE, verified, then reused by
    every test, worker and run that asks for the same variant; tests of derivation itself,
    tests/derive/test_generated.py and tests/runtime/model/test_artefacts.py, derive afresh)."""
    from levitron.runtime.model.load import load_model
    cache = {}

    def make(name, *overrides):
        key = (name, overrides)
        if key not in cache:
            cache[key] = load_model(load_scene(name, list(overrides)))
        return cache[key]
    return make


@pytest.fixture(scope="session")
def csrc_objects():
    """The objects of runtime/csrc/*.c that every model's library links (runtime/model/cbuild.py), built
    once into the shared cache ($LEVITRON_CACHE; under xdist one worker builds, the others wait)."""
    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compile_object
    from levitron.runtime.model.load import CSRC
    return [compile_object(src, DEFAULT_FLAGS, include_dirs=(CSRC,)) for src in sorted(CSRC.glob("*.c"))]


@pytest.fixture(scope="session")
def seed_cache(csrc_objects):
    """seed_cache(folder) -> folder: a private LEVITRON_CACHE that already holds the runtime/csrc
    objects (stamped copies: verified before use like any cached object), so a test of the cache's
    behaviour does not compile integrators.c again (~6 s); each model's own model.c still compiles
    and links there as in any fresh cache."""
    def seed(folder: Path) -> Path:
        (folder / "obj").mkdir(parents=True, exist_ok=True)
        for obj in csrc_objects:
            for f in (obj, obj.with_name(obj.name + ".sha256")):
                shutil.copy2(f, folder / "obj" / f.name)
        return folder
    return seed


@pytest.fixture
def legend_texts(monkeypatch):
    """The legend entries of every figure saved during the test (a list, filled as they are saved)."""
    import matplotlib.figure
    texts: list[str] = []
    save = matplotlib.figure.Figure.savefig

    def recording(fig, *a, **k):
        for ax in fig.axes:
            if ax.get_legend() is not None:
                texts.extend(t.get_text() for t in ax.get_legend().get_texts())
        return save(fig, *a, **k)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", recording)
    return texts


def _slow_tier() -> set[str]:
    """The node ids of tests/slow.txt (tests/tools/slow_tier.py writes it)."""
    lines = (ROOT / "tests" / "slow.txt").read_text().splitlines()
    return {line.split("\t")[0] for line in lines if line.strip() and not line.startswith("#")}


def pytest_collection_modifyitems(config, items):
    """Mark the slow tier `slow` (make test: -m "not slow"; make test-slow: -m slow). On a whole
    collection of tests/, a listed test that no longer exists fails it: the list stays true."""
    slow = _slow_tier()
    seen = set()
    for item in items:
        if item.nodeid in slow:
            item.add_marker(pytest.mark.slow)
            seen.add(item.nodeid)
    whole = not config.args or [str(Path(a).resolve()) for a in config.args] == [str(ROOT / "tests")]
    missing = sorted(slow - seen)
    if whole and missing and not config.getoption("keyword"):
        raise pytest.UsageError(f"tests/slow.txt names {len(missing)} tests that do not exist, e.g. "
                                f"{missing[0]}: regenerate it (python tests/tools/slow_tier.py DURATIONS.log)")
