"""Fixtures the runtime's rooms share (tests/conftest.py holds those of the whole suite)."""
from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def air():
    """The model of thesis_air: thesis_stable in still air (its spin decays, e-folding time 150 s)."""
    from levitron.runtime.model.load import load_model
    from levitron.scene.load import load_scene
    return load_model(load_scene("thesis_air"))
