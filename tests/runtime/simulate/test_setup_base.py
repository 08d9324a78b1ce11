"""The base the set-up drawing shows (runtime/simulate/setup_shape.py base_of) is what each plate
kind declares (scene/plates/<kind>.py `outline`): the numbers as the scene writes them."""
from __future__ import annotations

import pytest
import tomllib

from levitron.runtime.simulate.setup_shape import base_of, extent
from levitron.scene import plates
from levitron.scene.plates import docs


def _example(kind: str) -> dict:
    return tomllib.loads(docs.example_scene(plates.KINDS[kind]))["plate"]


RING_MAGNET = {"kind": "ring", "r_out": 0.06, "r_in": 0.03, "thickness": 0.02}


@pytest.mark.parametrize("kind,base", [
    ("annulus", [{"kind": "ring", "r_out": 0.10, "r_in": 0.03, "thickness": 0.0}]),
    ("disk", [{"kind": "ring", "r_out": 0.10, "r_in": 0.0, "thickness": 0.0}]),
    ("loop", [{"kind": "loop", "r_out": 0.05, "r_in": 0.05, "thickness": 0.0}]),
    ("ring_magnet", [RING_MAGNET]),
    ("rectangle", [{"kind": "rect", "half_x": 0.05, "half_y": 0.05, "r_in": 0.0, "thickness": 0.02}]),
    ("compound", [RING_MAGNET, {"kind": "loop", "r_out": 0.02, "r_in": 0.02, "thickness": 0.0}]),
    ("expression", []),
])
def test_each_kinds_example_is_drawn_as_its_outline(kind, base):
    assert base_of(_example(kind)) == base


def test_a_rectangle_with_two_sides_and_a_hole_and_a_nested_compound():
    bar = {"kind": "rectangle", "side_x": 0.1, "side_y": 0.04, "hole": 0.01, "murho": -0.002}
    assert base_of(bar) == [{"kind": "rect", "half_x": 0.05, "half_y": 0.02, "r_in": 0.01, "thickness": 0.0}]
    nested = {"kind": "compound", "parts": [{"kind": "compound", "parts": [bar]}, _example("expression")]}
    assert base_of(nested) == base_of(bar)
    assert extent(base_of(nested)) == 0.05 and extent([]) == 0.0


def test_a_kind_the_registry_does_not_know_has_no_outline():
    assert base_of({"kind": "no such kind"}) == [] and base_of({"kind": ["not", "a", "name"]}) == []
