"""Shared fixtures: the thesis scene and model, and scenes derived into temporary folders."""
from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from derive.scene import load_scene  # noqa: E402


@pytest.fixture(scope="session")
def thesis_scene():
    return load_scene("thesis")


@pytest.fixture(scope="session")
def thesis_model(thesis_scene):
    from runtime.model import load_model
    return load_model(thesis_scene)


@pytest.fixture(scope="session")
def derived_model(tmp_path_factory):
    """derived_model(scene_name, *overrides) -> a Model derived into a temporary folder."""
    from derive.build import derive_scene
    from runtime.model import Model
    cache = {}

    def make(name, *overrides):
        key = (name, overrides)
        if key not in cache:
            scene = load_scene(name, list(overrides))
            out = tmp_path_factory.mktemp("gen")
            derive_scene(scene, out, force=True)
            cache[key] = Model(scene, out / scene.name)
        return cache[key]
    return make
