"""The rectangle's centred circular through-hole (scene/plates/rectangle.py `hole`, issue 30).

hole = 0 is the plain rectangle to the last bit (parameters, sympy model, generated files, exact
field); a hole is the plate minus a cylinder (block) or disk (thin layer) of the same magnetisation:
on the axis exactly, in the full model the plain plate's exact field plus the hole's Laplace
expansion to field.order (thesis eq. 2.2.7), which converges to the exact field as the order grows.
magpylib's Cuboid minus Cylinder is the independent reference (tests/runtime/physics/plates/test_magpylib_reference.py).
"""
from __future__ import annotations

import json

import numpy as np
import pytest
import sympy as sp

from levitron.scene import plates
from levitron.derive.build import render
from levitron.scene.digest import SELF_KEY
from levitron.scene.inputs import input_hash
from levitron.derive.plate_fields import build_plate
from levitron.scene.load import SceneError, load_scene, validate
from levitron.derive.symbols import X, Y, Z
from levitron.runtime.physics.plates import plate_field

BLOCK = {"kind": "rectangle", "side": 0.1, "thickness": 0.02, "remanence": 0.39}
THIN = {"kind": "rectangle", "side_x": 0.1, "side_y": 0.08, "murho": -0.002}


def resolved(table: dict) -> dict:
    return {f"plate_{k}": float(v) for k, v in plates.resolve(table, -0.65).items()}


@pytest.mark.parametrize("table", [BLOCK, THIN], ids=["block", "thin"])
def test_hole_zero_is_the_plain_rectangle_to_the_last_bit(table):
    """Same parameters, the same sympy model (phi0, every Phi_k, the 3-D field, no axial part) and
    bit-identical exact fields on and off the axis, inside the block included."""
    zero = {**table, "hole": 0.0}
    assert resolved(zero) == resolved(table)
    plain, with_zero = build_plate(table), build_plate(zero)
    assert with_zero.symbols == plain.symbols and with_zero.axial is None
    assert all(with_zero.phi(k) == plain.phi(k) for k in range(5))
    assert with_zero.model_field(6, X, Y, Z) == plain.model_field(6, X, Y, Z)
    pts = np.random.default_rng(3).uniform(-0.1, 0.1, (200, 3))
    assert np.array_equal(plate_field(zero, resolved(zero), pts), plate_field(table, resolved(table), pts),
                          equal_nan=True)


def _files_without_hash(scene) -> dict[str, bytes]:
    """generated/<scene>/'s files with the input hash (which covers the scene's text) blanked and
    the manifest's digests of those files dropped."""
    files = render(scene)
    ihash = input_hash(scene.data)
    out = {name: data.replace(ihash.encode(), b"H").replace(ihash[:16].encode(), b"H")
           for name, data in files.items() if name != "manifest.json"}
    manifest = json.loads(files["manifest.json"])
    for key in ("input_hash", "files", SELF_KEY):
        manifest.pop(key)
    out["manifest.json"] = json.dumps(manifest, sort_keys=True).encode()
    return out


def test_hole_zero_derives_the_square_scene_byte_for_byte():
    """scenes/square.toml with plate.hole = 0 generates the same C, CasADi and manifest as without
    (only the input hash, which covers the scene's keys, differs)."""
    plain = _files_without_hash(load_scene("square"))
    zero = _files_without_hash(load_scene("square", ["plate.hole=0"]))
    assert sorted(plain) == sorted(zero)
    for name in plain:
        assert plain[name] == zero[name], name


@pytest.mark.parametrize("table", [BLOCK, THIN], ids=["block", "thin"])
def test_holed_onaxis_is_plate_minus_cylinder_or_disk(table):
    """On the axis the holed plate's Phi_k are the plain plate's minus those of the cylinder (block)
    or disk (layer) of the hole, from the ring_magnet / disk kinds' own builders."""
    holed = {**table, "hole": 0.012}
    p = resolved(holed)
    if "thickness" in table:
        hole_table = {"kind": "ring_magnet", "r_out": 0.012, "thickness": 0.02, "remanence": 0.39}
    else:
        hole_table = {"kind": "disk", "radius": 0.012, "murho": -0.002}
    hp = resolved(hole_table)
    whole, plain, taken = build_plate(holed), build_plate(table), build_plate(hole_table)
    for k in range(1, 5):
        for z in (0.005, 0.032, 0.2):
            got = float(whole.phi(k).xreplace({s: p[s.name] for s in whole.symbols}).subs(Z, z))
            want = (float(plain.phi(k).xreplace({s: p[s.name] for s in plain.symbols}).subs(Z, z))
                    - float(taken.phi(k).xreplace({s: hp[s.name] for s in taken.symbols}).subs(Z, z)))
            assert got == pytest.approx(want, rel=1e-13, abs=1e-15 * abs(want) / z)


def test_holed_model_field_converges_to_the_exact_field():
    """The full model's field of a holed block is the exact block plus the hole's expansion to the
    order: on the axis it is exact, off the axis (r <= 6 mm at the toy's 3.2 cm hover height) its
    error against the exact field (block minus cylinder, runtime) falls by >= 30 per two orders
    (the expansion's radius of convergence, sqrt(z^2 + hole^2) = 3.5 cm, is ~ 6 r)."""
    table = {**BLOCK, "hole": 0.015}
    p = resolved(table)
    plate = build_plate(table)
    sub = {s: p[s.name] for s in plate.symbols}
    pts = np.array([[0.0, 0.0, 0.032], [0.003, 0.002, 0.03], [0.006, 0.0, 0.034], [0.0, -0.004, 0.028]])
    exact = plate_field(table, p, pts)
    errors = []
    for order in (2, 4, 6, 8):
        B = sp.lambdify((X, Y, Z), plate.model_field(order, X, Y, Z).xreplace(sub), "numpy")
        model = np.array([np.asarray(B(*q), dtype=float).ravel() for q in pts])
        rel = np.linalg.norm(model - exact, axis=1) / np.linalg.norm(exact, axis=1)
        assert rel[0] <= 1e-15
        errors.append(rel[1:].max())
    assert all(b <= a / 30 for a, b in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-8


@pytest.mark.parametrize("hole,message", [(-0.01, "plate.hole = -0.01"), (0.05, "half the shorter side"),
                                          (0.045, "0 <= hole < 0.04")])
def test_a_hole_that_does_not_fit_is_one_line(hole, message):
    data = {"name": "bad", "top": {"mass": 0.02, "A": 2e-6, "C": 1.3e-6, "moment": -0.5},
            "field": {"order": 2}, "plate": {**THIN, "hole": hole}}
    with pytest.raises(SceneError) as info:
        validate(data)
    assert message in str(info.value) and "\n" not in str(info.value)


def test_hole_is_a_structural_decision_and_a_length():
    assert plates.decisions({**BLOCK, "hole": 0.01})["holed"] is True
    assert plates.decisions(BLOCK)["holed"] is False
    assert "plate_hole" in plates.length_names({**BLOCK, "hole": 0.01})
