"""Fixtures beside their tests: a fixture that several test files use is defined once, in the
conftest.py of the narrowest folder that holds all its users, never copied from file to file.

Read from the source (ast), not from pytest's collection: a copy is a fixture of the same name and
the same definition (arguments and body, docstring aside) in two files; one name defined in two
files, even with different bodies, is allowed only where SAME_NAME says why (the fixtures mean
different things, each beside its own tests)."""
from __future__ import annotations

import ast
import os
from collections import defaultdict
from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]

# A fixture name defined in more than one file, and why each keeps its own.
SAME_NAME = {
    "model": "tests/conftest.py's is the thesis with a 51.5 g top; test_simulate.py's is the thesis as "
             "written, test_rotating_equilibrium.py's thesis_stable with its moment tilted (0.05 rad)",
    "study": "tests/conftest.py's is thesis_stable as written; test_api_and_examples.py's has the "
             "scene-key override top.mass = 0.0512 that its tests read back; runtime/ui/test_plotting_notebook.py's "
             "is the thesis scene (not thesis_stable)",
    "scan_map": "two maps of different grids: the one api/test_answer_types.py compares with the command "
                "line's, and the two-point map runtime/ui/test_plotting_notebook.py draws",
    "air": "tests/runtime/conftest.py's is thesis_air's model; test_teacher_page.py's is the report page "
           "of thesis_air and its JSON",
    "aligned": "the aligned top's tilted analysis of two different models: loop_peer (test_floquet.py) "
               "and thesis_stable with a tilted moment (test_rotating_equilibrium.py)",
    "circle": "the thesis's circle as a C system (tests/c) and as a Python right-hand side "
              "(tests/runtime/integrate/test_solver_compare.py)",
    "tilted": "four different tilted set-ups: a plate tilt of 1.2 mrad (cli), of 1 mrad "
              "(physics/apparatus/test_base_tilt.py), a tilted moment's Floquet top "
              "(physics/apparatus/test_floquet.py), a Study with a level tilt key (scan)",
    "toy": "the levitron_toy scene (tests/scene) and its top's numbers (tests/runtime/physics/stability/test_modes.py)",
    "thesis_report": "the thesis's equilibrium analysis (physics/equilibrium/test_equilibrium.py) and its report "
                     "page (report/test_report.py, also asked for by name through getfixturevalue)",
}


def _fixture_name(node: ast.FunctionDef) -> str | None:
    """The fixture's name if `node` is decorated with pytest.fixture (bare or called), else None."""
    for deco in node.decorator_list:
        call = deco if isinstance(deco, ast.Call) else None
        target = call.func if call else deco
        if ast.unparse(target) in ("pytest.fixture", "fixture"):
            for kw in call.keywords if call else ():
                if kw.arg == "name" and isinstance(kw.value, ast.Constant):
                    return kw.value.value
            return node.name
    return None


def _definition(node: ast.FunctionDef) -> str:
    """The arguments and the body, the docstring left out: what a copy repeats."""
    body = node.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant) \
            and isinstance(body[0].value.value, str):
        body = body[1:]
    return ast.dump(node.args) + "".join(ast.dump(s) for s in body)


def _parametrized(node: ast.FunctionDef) -> set[str]:
    """The argument names a function's parametrize marks give (those are not fixtures)."""
    names: set[str] = set()
    for deco in node.decorator_list:
        if isinstance(deco, ast.Call) and ast.unparse(deco.func).endswith("parametrize") and deco.args:
            first = deco.args[0]
            if isinstance(first, ast.Constant) and isinstance(first.value, str):
                names |= {n.strip() for n in first.value.split(",")}
            elif isinstance(first, (ast.List, ast.Tuple)):
                names |= {e.value for e in first.elts if isinstance(e, ast.Constant)}
    return names


def survey(root: Path):
    """({name: [(file, definition)]} of every fixture under root, {name: files that ask for it}):
    a test or fixture asking by argument, or getfixturevalue / usefixtures by a literal name."""
    defined: dict[str, list[tuple[Path, str]]] = defaultdict(list)
    asked: dict[str, set[Path]] = defaultdict(set)
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and ast.unparse(node.func).endswith(("getfixturevalue", "usefixtures")):
                for arg in node.args:
                    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
                        asked[arg.value].add(path)
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            name = _fixture_name(node)
            if name is not None:
                defined[name].append((path, _definition(node)))
            if name is not None or node.name.startswith("test"):
                args = node.args.posonlyargs + node.args.args + node.args.kwonlyargs
                for arg in {a.arg for a in args} - _parametrized(node):
                    asked[arg].add(path)
    return defined, asked


def _rel(path: Path, root: Path) -> str:
    return path.relative_to(root).as_posix()


def copies(root: Path) -> list[str]:
    """'name: file, file' for every fixture defined with the same definition in two files."""
    defined, _ = survey(root)
    out = []
    for name, defs in sorted(defined.items()):
        by_body: dict[str, set[Path]] = defaultdict(set)
        for path, body in defs:
            by_body[body].add(path)
        out += [f"{name}: " + ", ".join(sorted(_rel(p, root) for p in files))
                for files in by_body.values() if len(files) > 1]
    return out


def test_no_fixture_is_copied_between_files():
    found = copies(TESTS)
    assert not found, ("the same fixture defined in several files: move it into the conftest.py of "
                       f"the narrowest folder that holds its users: {found}")


def test_a_fixture_name_means_one_thing_unless_said_why():
    defined, _ = survey(TESTS)
    several = {name: sorted({_rel(p, TESTS) for p, _ in defs}) for name, defs in defined.items()}
    several = {name: files for name, files in several.items() if len(files) > 1}
    unexplained = {name: files for name, files in several.items() if name not in SAME_NAME}
    assert not unexplained, ("one fixture name defined in several files: share one fixture, rename "
                             f"one, or say why in SAME_NAME: {unexplained}")
    stale = sorted(set(SAME_NAME) - set(several))
    assert not stale, f"SAME_NAME lists names defined in one file only (drop them): {stale}"


def test_a_conftest_fixture_sits_in_the_narrowest_folder_of_its_users():
    defined, asked = survey(TESTS)
    misplaced = []
    for name, defs in sorted(defined.items()):
        for path, _ in defs:
            if path.name != "conftest.py":
                continue
            own = {p for p, _ in defs if p != path and p.parent.is_relative_to(path.parent)}
            shadowed = {p for p in own if p.name != "conftest.py"}
            users = {p for p in asked.get(name, ()) if p.parent.is_relative_to(path.parent)} - shadowed
            if users and Path(os.path.commonpath([p.parent for p in users])) != path.parent:
                misplaced.append(f"{name} ({_rel(path, TESTS)}): used only under "
                                 f"{_rel(Path(os.path.commonpath([p.parent for p in users])), TESTS)}/")
    assert not misplaced, f"move these fixtures down to their users' folder: {misplaced}"


def test_the_survey_sees_a_copy_and_a_fixture_by_another_name(tmp_path):
    """The check itself: a fixture copied into two folders is found, docstring and decorator
    arguments aside; a different body under the same name is not a copy."""
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    (tmp_path / "a" / "test_one.py").write_text(
        "import pytest\n\n@pytest.fixture(scope='module')\ndef lib():\n    '''One.'''\n    return make()\n\n"
        "@pytest.fixture(name='other')\ndef _o():\n    return 1\n")
    (tmp_path / "b" / "test_two.py").write_text(
        "import pytest\n\n@pytest.fixture\ndef lib():\n    return make()\n\n"
        "@pytest.fixture\ndef other():\n    return 2\n\ndef test_x(other, lib):\n    pass\n")
    assert copies(tmp_path) == ["lib: a/test_one.py, b/test_two.py"]
    defined, asked = survey(tmp_path)
    assert len(defined["other"]) == 2 and asked["lib"] == {tmp_path / "b" / "test_two.py"}
