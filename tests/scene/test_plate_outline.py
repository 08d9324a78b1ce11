"""Every plate kind declares its drawn outline and its quarter-turn symmetry beside its keys
(scene/plates/base.py `outline`, `quarter_turn`): neither has a default, so a new kind cannot be
drawn without a base, or taken for axisymmetric, by oversight."""
from __future__ import annotations

import dataclasses

import pytest
import tomllib

from levitron.scene import plates
from levitron.scene.plates import docs
from levitron.scene.plates.base import PlateKind
from levitron.scene.load import validate

DECLARED = ("outline", "quarter_turn", "exact_field")
SHAPES = {"disc", "ring", "rect", "loop"}


@pytest.mark.parametrize("name", DECLARED)
def test_a_kind_must_say_its_outline_and_its_symmetry(name):
    field = {f.name: f for f in dataclasses.fields(PlateKind)}[name]
    assert field.default is dataclasses.MISSING and field.default_factory is dataclasses.MISSING
    given = {"name": "new", "doc": "", "keys": (), "resolve": lambda t, c: {}, "example": "",
             **{n: None for n in DECLARED if n != name}}
    with pytest.raises(TypeError, match=name):
        PlateKind(**given)


@pytest.mark.parametrize("kind", sorted(plates.KINDS))
def test_every_registered_kind_has_an_outline_or_says_it_has_none(kind):
    k = plates.KINDS[kind]
    assert k.outline is None or callable(k.outline)
    assert k.quarter_turn is None or callable(k.quarter_turn)
    assert k.exact_field is None or callable(k.exact_field)
    table = tomllib.loads(docs.example_scene(k))["plate"]
    if k.outline is None:
        return
    shape = k.outline(table)
    assert shape["kind"] in SHAPES
    assert all(isinstance(v, float) and v >= 0 for key, v in shape.items() if key != "kind")
    assert max(shape.get("r_out", 0.0), shape.get("half_x", 0.0)) > 0


def test_only_a_compound_and_a_formula_have_no_outline_of_their_own():
    """A compound plate is drawn as its parts' outlines (has_parts); an expression plate has no shape."""
    none = {name for name, k in plates.KINDS.items() if k.outline is None}
    assert none == {"compound", "expression"}
    assert plates.KINDS["compound"].has_parts and not plates.KINDS["expression"].has_parts


def test_a_quarter_turn_swaps_a_rectangles_sides_and_signs_its_strength():
    data = tomllib.loads(docs.example_scene(plates.KINDS["annulus"]))
    data["plate"] = {"kind": "rectangle", "side_x": 0.1, "side_y": 0.04, "thickness": 0.02,
                     "remanence": 0.39}
    params = {k[len("plate_"):]: v for k, v in validate(data).params.items() if k.startswith("plate_")}
    part, turned = plates.KINDS["rectangle"].quarter_turn(params, -1.0)
    assert part[0] == (0.1, 0.04) and turned[0] == (0.04, 0.1) and part[1] == turned[1]
    assert dict(part[1])["magnetization"] == -params["magnetization"]
    assert dict(part[1])["thickness"] == params["thickness"]
