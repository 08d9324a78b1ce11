"""`lev.plate_from_magpylib(collection)` (levitron/from_magpylib.py): a magpylib assembly becomes a
compound [plate] table whose exact field is magpylib's (the independent route: magpylib's own
getB), and what the plate kinds cannot express is refused in one line naming the source."""
from __future__ import annotations

import magpylib as magpy
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import levitron as lev
from levitron.scene import plates
from levitron.scene.constants import MU0
from levitron.scene.load import validate
from levitron.runtime.physics.plates import plate_field

M = 0.39 / MU0          # A/m


def block_with_hole(top: float = 0.0):
    """The toy's base as magpylib users build it: a block, a cylinder of the opposite magnetisation
    for the hole, a ring segment below nothing, a loop in the top plane; top faces at z = top."""
    return magpy.Collection(
        magpy.magnet.Cuboid(dimension=(0.1, 0.08, 0.02), magnetization=(0, 0, M), position=(0, 0, top - 0.01)),
        magpy.magnet.Cylinder(dimension=(0.01, 0.02), magnetization=(0, 0, -M), position=(0, 0, top - 0.01)),
        magpy.magnet.CylinderSegment(dimension=(0.06, 0.07, 0.01, 0, 360), magnetization=(0, 0, M / 2),
                                     position=(0, 0, top - 0.005)),
        magpy.current.Circle(diameter=0.03, current=-40.0, position=(0, 0, top)))


def test_an_assembly_becomes_a_compound_plate_with_magpylibs_field():
    table = lev.plate_from_magpylib(block_with_hole())
    assert [p["kind"] for p in table["parts"]] == ["rectangle", "ring_magnet", "ring_magnet", "loop"]
    validate({"name": "from_magpylib", "top": {"mass": 0.02, "A": 1.32e-6, "C": 2.2e-6, "moment": -0.65},
              "field": {"order": 4}, "plate": table})
    params = {f"plate_{k}": float(v) for k, v in plates.resolve(table, -0.65).items()}
    rng = np.random.default_rng(11)
    pts = np.column_stack([rng.uniform(-0.12, 0.12, (200, 2)), rng.uniform(0.005, 0.2, 200)])
    ours = plate_field(table, params, pts)
    ref = np.asarray(block_with_hole().getB(pts)) * (MU0 / magpy.mu_0)   # mu0: CODATA 2022 -> 2018
    rel = np.linalg.norm(ours - ref, axis=1) / np.linalg.norm(ref, axis=1)
    assert rel.max() <= 1e-12


def test_the_assemblys_top_plane_becomes_z_0():
    assert lev.plate_from_magpylib(block_with_hole(top=0.3)) == lev.plate_from_magpylib(block_with_hole())


def test_one_source_is_a_compound_of_one_part():
    cyl = magpy.magnet.Cylinder(dimension=(0.12, 0.02), magnetization=(0, 0, M), position=(0, 0, -0.01))
    assert lev.plate_from_magpylib(cyl) == {"kind": "compound", "parts": [
        {"kind": "ring_magnet", "r_out": 0.06, "thickness": 0.02, "magnetization": M}]}


def _cuboid(**kw):
    args = {"dimension": (0.1, 0.1, 0.02), "magnetization": (0, 0, M), "position": (0, 0, -0.01)}
    args.update(kw)
    return magpy.magnet.Cuboid(**args)


@pytest.mark.parametrize("source,message", [
    (_cuboid(position=(0.01, 0, -0.01)), "off the z axis"),
    (_cuboid(orientation=Rotation.from_euler("x", 10, degrees=True)), "tilted"),
    (_cuboid(orientation=Rotation.from_euler("z", 30, degrees=True)), "turned about z"),
    (_cuboid(magnetization=(M, 0, 0)), "along z only"),
    (_cuboid(position=[(0, 0, -0.01), (0, 0, -0.02)]), "path of 2 positions"),
    (magpy.magnet.CylinderSegment(dimension=(0.01, 0.02, 0.01, 0, 180), magnetization=(0, 0, M)), "180 deg"),
    (magpy.magnet.Sphere(diameter=0.01, magnetization=(0, 0, M)), "Sphere"),
    (magpy.misc.Dipole(moment=(0, 0, 1.0)), "Dipole"),
    (magpy.magnet.Tetrahedron(vertices=[(0, 0, 0), (0.01, 0, 0), (0, 0.01, 0), (0, 0, -0.01)],
                              magnetization=(0, 0, M)), "Tetrahedron"),
    (magpy.Collection(_cuboid(), magpy.magnet.Cylinder(dimension=(0.01, 0.01), magnetization=(0, 0, M),
                                                       position=(0, 0, -0.03))), "top at z"),
])
def test_what_the_plate_kinds_cannot_express_is_refused_in_one_line(source, message):
    with pytest.raises(lev.UserError) as info:
        lev.plate_from_magpylib(source)
    text = str(info.value)
    assert message in text and "\n" not in text and "source" in text


def test_a_refusal_names_the_source_by_its_label():
    src = _cuboid(orientation=Rotation.from_euler("x", 10, degrees=True), style_label="base")
    with pytest.raises(lev.UserError, match=r"source 1 \(Cuboid 'base'\)"):
        lev.plate_from_magpylib(magpy.Collection(_cuboid(), src))
