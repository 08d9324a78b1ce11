"""The plate registry: one entry per kind on each side, the same kinds everywhere, the
structural decisions in the input hash, the length scale, and docs/scenes.md generated from it."""
from __future__ import annotations

import copy
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import tomllib

from levitron.scene import plates
from levitron.scene.inputs import input_hash, structure
from levitron.scene.paths import ROOT
from levitron.scene.plates import docs
from levitron.scene.load import load_scene, validate


def _example(kind: str) -> dict:
    return tomllib.loads(docs.example_scene(plates.KINDS[kind]))


def test_the_three_registries_have_the_same_kinds():
    from levitron.derive.plate_fields import BUILDERS
    from levitron.runtime.physics.plates import FIELDS
    kinds = set(plates.KINDS)
    assert kinds == {"annulus", "disk", "loop", "ring_magnet", "rectangle", "compound", "expression"}
    assert set(BUILDERS) == kinds
    assert set(FIELDS) == kinds
    # one file per kind on each side, named after the kind
    for folder in ("scene/plates", "derive/plate_fields", "runtime/physics/plates"):
        files = {p.stem for p in (ROOT / folder).glob("*.py")}
        assert kinds <= files, (folder, kinds - files)


def test_no_sympy_on_import_of_the_scene_side():
    code = ("import sys, levitron.scene.load as scene, levitron.scene.inputs as inputs, "
            "levitron.scene.plates, levitron.scene.plates.docs, levitron.runtime.physics.plates; "
            "inputs.input_hash(scene.load_scene('ring_magnet').data); print('sympy' in sys.modules)")
    res = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                         check=True)
    assert res.stdout.strip() == "False", res.stderr


@pytest.mark.parametrize("kind", sorted(plates.KINDS))
def test_example_validates_and_both_sides_name_the_same_parameters(kind):
    """Each kind's documented example is a valid scene, and its sympy builder's symbols are exactly
    the parameters its resolver gives (scene side and derive side agree on names)."""
    from levitron.derive.plate_fields import build_plate
    scene = validate(_example(kind))
    resolved = {k for k in scene.params if k.startswith("plate_")}
    assert {s.name for s in build_plate(scene.data["plate"]).symbols} == resolved


@pytest.mark.parametrize("table", [
    {"kind": "ring_magnet", "r_out": 0.06, "r_in": 0.0, "thickness": 0.02, "remanence": 0.39},
    {"kind": "rectangle", "side": 0.1, "murho": -0.002},
])
def test_the_other_branch_names_the_same_parameters(table):
    from levitron.derive.plate_fields import build_plate
    data = _example("annulus")
    data["plate"] = table
    scene = validate(data)
    resolved = {k for k in scene.params if k.startswith("plate_")}
    assert {s.name for s in build_plate(table).symbols} == resolved


@pytest.mark.parametrize("table", [
    *[_example(kind)["plate"] for kind in sorted(set(plates.KINDS) - {"expression"})],
    {"kind": "ring_magnet", "r_out": 0.06, "r_in": 0.0, "thickness": 0.02, "remanence": 0.39},
    {"kind": "rectangle", "side": 0.1, "murho": -0.002},
])
def test_every_resolved_parameter_has_its_unit(table):
    """plates.param_units names the SI unit of every plate parameter the resolver gives (`info`
    shows them), compound parts included; lengths are metres."""
    data = _example("annulus")
    data["plate"] = table
    scene = validate(data)
    resolved = {k for k in scene.params if k.startswith("plate_")}
    units = plates.param_units(scene.data["plate"])
    assert set(units) >= resolved, sorted(resolved - set(units))
    assert all(units[k] == "m" for k in plates.length_names(scene.data["plate"]))
    assert all(units[k] for k in resolved)


def test_ring_r_in_zero_and_positive_have_different_input_hashes():
    """A solid and a hollow ring magnet share no cache key."""
    hollow = load_scene("ring_magnet")
    solid = load_scene("ring_magnet", ["plate.r_in=0"])
    assert structure(hollow.data)["decisions"] == {"kind": "ring_magnet", "hollow": True}
    assert structure(solid.data)["decisions"] == {"kind": "ring_magnet", "hollow": False}
    assert input_hash(hollow.data) != input_hash(solid.data)
    # plain numbers are runtime parameters: the same key
    for change in ("plate.r_in=0.02", "top.mass=0.02", "plate.r_out=0.07", "plate.remanence=0.3"):
        assert input_hash(load_scene("ring_magnet", [change]).data) == input_hash(hollow.data), change


def test_rectangle_block_and_thin_layer_have_different_input_hashes():
    block = load_scene("square")
    data = copy.deepcopy(block.data)
    data["plate"] = {"kind": "rectangle", "side": 0.1, "murho": -0.002}
    thin = validate(data)
    assert input_hash(thin.data) != input_hash(block.data)
    assert input_hash(load_scene("square", ["plate.side=0.2"]).data) == input_hash(block.data)


def test_a_compound_part_decision_is_in_the_hash():
    scene = validate(_example("compound"))
    data = copy.deepcopy(scene.data)
    data["plate"]["parts"][0]["r_in"] = 0
    solid = validate(data)
    assert structure(solid.data)["decisions"]["parts"][0] == {"kind": "ring_magnet", "hollow": False}
    assert input_hash(solid.data) != input_hash(scene.data)


@pytest.mark.parametrize("kind,scale", [("annulus", 0.10), ("disk", 0.10), ("loop", 0.05),
                                        ("ring_magnet", 0.06), ("rectangle", 0.10),
                                        ("compound", 0.06), ("expression", 1.0)])
def test_length_scale(kind, scale):
    """The largest length of the plate (compound parts included); 1 for an expression plate."""
    assert validate(_example(kind)).length_scale == scale


def test_length_scale_of_the_scenes():
    assert load_scene("thesis").length_scale == 0.1
    assert load_scene("thesis", ["plate.radius=0.2"]).length_scale == 0.2
    assert load_scene("ring_magnet").length_scale == 0.06


@pytest.mark.parametrize("kind", sorted(set(plates.KINDS) - {"expression"}))
def test_every_kind_but_expression_has_a_finite_exact_field(kind):
    from levitron.runtime.physics.plates import plate_field
    scene = validate(_example(kind))
    B = plate_field(scene.data["plate"], scene.params, [[0.01, 0.005, 0.08]])
    assert B.shape == (1, 3) and np.all(np.isfinite(B)) and np.linalg.norm(B) > 0


def test_docs_scenes_md_is_current():
    """docs/scenes.md is what `python -m levitron.scene.plates.docs` writes from the registry."""
    assert (ROOT / "docs" / "scenes.md").read_text(encoding="utf-8") == docs.render()


def test_docs_refer_to_no_path_outside_the_repository():
    for path in (ROOT / "docs").glob("*.md"):
        text = path.read_text(encoding="utf-8")
        assert "shared/" not in text and "DESIGN.md" not in text, path


def _module_imports(root: Path, package: str) -> dict[str, set[str]]:
    """Module -> the modules of `package` it imports (at any level of the file), from the source."""
    import ast
    graph: dict[str, set[str]] = {}
    for path in (root / package).rglob("*.py"):
        rel = path.relative_to(root).with_suffix("")
        parts = ["levitron", *rel.parts]          # derive/ is levitron.derive
        is_pkg = parts[-1] == "__init__"
        if is_pkg:
            parts = parts[:-1]
        name = ".".join(parts)
        deps = set()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                base = parts if is_pkg else parts[:-1]
                if node.level:
                    base = base[:len(base) - node.level + 1]
                    mod = ".".join(base + ([node.module] if node.module else []))
                else:
                    mod = node.module or ""
                targets = [mod] + [f"{mod}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            else:
                continue
            deps |= {t for t in targets if t.startswith(f"levitron.{package}.")}
        graph[name] = deps
    return {k: {d for d in v if d in graph and d != k} for k, v in graph.items()}


@pytest.mark.parametrize("package, edges", [("derive", 50), ("scene", 25)])
def test_no_import_cycles_in_derive_and_scene(package, edges):
    """geometry <-> plates_extra and scene <-> plate_kinds were cycles; derive/ and scene/ have none."""
    graph = _module_imports(ROOT, package)
    assert sum(map(len, graph.values())) > edges       # the graph sees the package's imports
    state: dict[str, int] = {}

    def visit(node, trail):
        state[node] = 1
        for dep in sorted(graph[node]):
            # a package's own __init__ is imported before its modules: not a cycle edge
            if node.startswith(dep + "."):
                continue
            if state.get(dep) == 1:
                raise AssertionError("import cycle: " + " -> ".join([*trail, node, dep]))
            if dep not in state:
                visit(dep, [*trail, node])
        state[node] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module, [])
