"""Every derivation bounded: a compound plate of more parts than the derivation budget
(scene/plates/compound.py MAX_PARTS, nested compounds' parts counted) is refused before any
derivation, in one line with the count that exceeded it; plate_from_magpylib takes as many sources."""
from __future__ import annotations

import pytest

from levitron.scene.checks import SceneError
from levitron.scene.load import validate
from levitron.scene.plates.compound import MAX_PARTS, leaf_parts


def _ring(i: int) -> dict:
    return {"kind": "ring_magnet", "r_out": 0.05 + 0.001 * i, "r_in": 0.01, "thickness": 0.02, "remanence": 0.39}


def _scene(plate: dict) -> dict:
    return {"name": "many", "top": {"mass": 0.02, "A": 1.32e-6, "C": 2.2e-6, "moment": -0.65}, "plate": plate,
            "field": {"order": 2}, "model": {"needs": ["reduced"]}}


def _compound(parts: list) -> dict:
    return {"kind": "compound", "parts": parts}


def test_a_plate_at_the_budget_is_taken_and_one_part_more_is_refused():
    assert validate(_scene(_compound([_ring(i) for i in range(MAX_PARTS)]))).name == "many"
    with pytest.raises(SceneError) as exc:
        validate(_scene(_compound([_ring(i) for i in range(MAX_PARTS + 1)])))
    msg = str(exc.value)
    assert "\n" not in msg and f"has {MAX_PARTS + 1} parts" in msg and f"budget of {MAX_PARTS}" in msg


def test_nested_compounds_count_their_parts():
    half = MAX_PARTS // 2 + 1
    nested = _compound([_compound([_ring(i) for i in range(half)]), _compound([_ring(i) for i in range(half)])])
    assert leaf_parts(nested) == 2 * half > MAX_PARTS
    assert leaf_parts(_ring(0)) == 1
    with pytest.raises(SceneError, match=f"has {2 * half} parts"):
        validate(_scene(nested))


def test_plate_from_magpylib_takes_the_budget():
    from levitron.from_magpylib import MAX_SOURCES
    assert MAX_SOURCES == MAX_PARTS
