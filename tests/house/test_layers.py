"""The house's rooms: scene/ (the scene language, pure Python) at the bottom, derive/ (sympy) and
runtime/ on it, each taking of the other only what is listed; runtime/ in subpackages by idea,
runtime/physics/ in rooms by idea (PHYSICS_ROOMS), imports only down the layers and the rooms, no
import cycles (function-level imports counted too), no private name across packages, a public API
(levitron) that stands on the runtime, not on the command line; the input hash covers all of
derive/; no module over 400 lines; the tests laid out by room."""
from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
RUNTIME = ROOT / "runtime"

# bottom to top: a module may import from its own layer and the ones below it
LAYERS = ("words", "errors", "ui", "model", "integrate", "physics", "simulate", "scan", "design", "report",
          "bench", "cli")
RANK = {name: i for i, name in enumerate(LAYERS)}
ROOMS = tuple(n for n in LAYERS if n not in ("words", "errors"))      # the subpackages
# runtime/physics/ in rooms by idea, bottom to top: a module imports from its own room and the ones below
# (field: exact fields, truncation; plates: each kind's field; routes: the on-axis stability routes;
# equilibrium: where the top hovers; apparatus: tilted base, tilted magnet, air; stability: over them all)
PHYSICS_ROOMS = ("field", "plates", "routes", "equilibrium", "apparatus", "stability")
TOP_LEVEL = {"__init__.py", "__main__.py", "errors.py", "words.py", "csrc", "__pycache__"}


def module_name(path: Path) -> str:
    """The import name of a file of the checkout: scene/, derive/ and runtime/ sit under levitron."""
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts if parts[0] == "levitron" else ["levitron", *parts])


def imports(path: Path):
    """(imported module, imported names) of every import in the file, nested ones included, a
    relative one as its absolute name; a runtime module imports by absolute path only."""
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, ()
        elif isinstance(node, ast.ImportFrom):
            names = tuple(a.name for a in node.names)
            if node.level:
                assert RUNTIME not in path.parents, f"{path}: relative import (write levitron.runtime.<package>)"
                package = module_name(path).split(".")[:None if path.name == "__init__.py" else -1]
                base = package[:len(package) - node.level + 1]
                yield ".".join(base + ([node.module] if node.module else [])), names
                continue
            yield node.module or "", names


def runtime_files():
    return sorted(p for p in RUNTIME.rglob("*.py") if "__pycache__" not in p.parts)


def layer(module: str) -> str | None:
    parts = module.split(".")
    if parts[:2] != ["levitron", "runtime"] or len(parts) < 3:
        return None
    return parts[2]


def resolve(module: str, names, known: set[str]) -> list[str]:
    """The runtime modules an import statement loads: `from levitron.runtime.a import b` may name
    module b."""
    out = [module] if module in known else []
    out += [f"{module}.{n}" for n in names if f"{module}.{n}" in known]
    return out


def graph():
    files = runtime_files()
    known = {module_name(p) for p in files}
    edges = {}
    for p in files:
        src = module_name(p)
        edges[src] = set()
        for mod, names in imports(p):
            edges[src].update(resolve(mod, names, known))
    return edges


def test_the_top_level_holds_entry_points_errors_words_csrc_and_subpackages():
    extra = sorted(p.name for p in RUNTIME.iterdir()
                   if p.name not in TOP_LEVEL and not (p.is_dir() and (p / "__init__.py").exists()))
    assert extra == []
    assert sorted(p.name for p in RUNTIME.iterdir() if p.is_dir() and p.name != "csrc"
                  and p.name != "__pycache__") == sorted(ROOMS)


def test_imports_go_only_down_the_layers():
    bad = []
    for src, targets in graph().items():
        ls = layer(src)
        if ls in (None, "__main__"):
            continue
        for t in targets:
            lt = layer(t)
            if lt in RANK and RANK[lt] > RANK[ls]:
                bad.append(f"{src} -> {t}")
    assert bad == []


def physics_room(module: str) -> str | None:
    parts = module.split(".")
    return parts[3] if parts[:3] == ["levitron", "runtime", "physics"] and len(parts) > 3 else None


def test_physics_is_in_rooms_and_imports_only_go_down_them():
    """runtime/physics/ holds its rooms and its __init__ alone; a physics module imports from its own
    room and the rooms below it; in a room no module's name is another's with a suffix (equilibrium,
    equilibrium_report)."""
    physics = RUNTIME / "physics"
    assert sorted(p.name for p in physics.glob("*.py")) == ["__init__.py"], "a flat physics module: move it to its room"
    assert sorted(p.name for p in physics.iterdir() if p.is_dir() and p.name != "__pycache__") == sorted(PHYSICS_ROOMS)
    order = {name: i for i, name in enumerate(PHYSICS_ROOMS)}
    bad = [f"{src} -> {t}" for src, targets in graph().items() if physics_room(src)
           for t in targets if physics_room(t) and order[physics_room(t)] > order[physics_room(src)]]
    assert bad == []
    for room in PHYSICS_ROOMS:
        stems = sorted(p.stem for p in (physics / room).glob("*.py") if p.name != "__init__.py")
        assert [(a, b) for a in stems for b in stems if b.startswith(a + "_")] == [], room


def test_no_import_cycles():
    edges = graph()
    index, low, stack, on, cycles = {}, {}, [], set(), []

    def visit(v):        # Tarjan's strongly connected components
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    # a package's __init__ that names its own modules lazily is not an edge (PEP 562 getattr)
    assert cycles == []


def test_no_private_name_crosses_a_package():
    bad = []
    for p in runtime_files() + sorted((ROOT / "levitron").glob("*.py")):
        src_pkg = module_name(p).split(".")[:3]
        for mod, names in imports(p):
            if not mod.startswith("levitron.runtime"):
                continue
            if mod.split(".")[:3] == src_pkg:
                continue
            bad += [f"{module_name(p)}: from {mod} import {n}" for n in names if n.startswith("_")]
    assert bad == []


def test_the_api_does_not_stand_on_the_command_line():
    """levitron/ (the API) imports nothing of runtime.cli; only `python -m levitron` (its
    __main__) starts the command."""
    for p in sorted((ROOT / "levitron").glob("*.py")):
        if p.name == "__main__.py":
            continue
        for mod, _ in imports(p):
            assert not mod.startswith("levitron.runtime.cli"), f"{p.name} imports {mod}"


# The top-level rooms: who may import whom (levitron/ is the public API on top of the runtime).
# scene/ is the bottom: pure Python, standing on nothing of the toolchain. derive/ is sympy, the
# emitters and the build. The runtime takes of derive/ only what is not sympy and not physics:
NOT_IN_SCENE = ("sympy", "numpy", "scipy", "casadi", "jinja2", "levitron.derive", "levitron.runtime",
                "levitron.study", "levitron.results")
RUNTIME_TAKES_OF_DERIVE = {
    "levitron.derive.atomic_dir": "the build's folder swap (pure Python): the runtime's cache of "
                                  "derived models swaps and sweeps its folders the same way",
    "levitron.derive.emit.heyoka": "the bench alone, inside a function: heyoka's system from the "
                                   "same sympy equations (the optional [bench] extra)",
}
# What derive/ takes from scene/, and why none of it can change a generated file without changing
# its input hash (scene/ is not hashed; scene/inputs.py): a new entry needs its reason.
DERIVE_TAKES_OF_SCENE = {
    "SceneError": "errors", "Scene": "the validated scene, hashed as its structure",
    "load_scene": "reads the scene that is hashed", "die_at": "fault injection",
    "SELF_KEY": "manifest digests", "file_digests": "manifest digests",
    "first_changed_file": "manifest digests", "manifest_digest": "manifest digests",
    "input_hash": "the hash itself", "tool_versions": "hashed", "GENERATED": "where files go",
    "SCENES_DIR": "where scenes are", "is_committed_scene": "where files go",
    "formulas": "message text", "expression": "the formula vocabulary: it accepts or refuses a formula, "
    "the formula text is hashed", "KINDS": "the kind's name is hashed", "SIGN": "a key name, hashed",
    "block": "a decision, its value is hashed", "holed": "a decision, its value is hashed",
    "hollow": "a decision, its value is hashed", "MU0": "its value is in the hash payload",
}


def room_files(room: str):
    return sorted(p for p in (ROOT / room).rglob("*.py") if "__pycache__" not in p.parts)


def test_the_scene_language_stands_on_nothing_of_the_toolchain():
    """scene/ imports no sympy, numpy or casadi and nothing of derive/, runtime/ or the API; and
    importing every module of it loads none of them (a second route: the interpreter's own)."""
    bad = [f"{p.relative_to(ROOT)}: {mod}" for p in room_files("scene") for mod, _ in imports(p)
           if mod.startswith(NOT_IN_SCENE) or mod == "levitron"]
    assert bad == []
    import subprocess
    import sys
    names = [module_name(p) for p in room_files("scene")]
    # `import levitron` itself loads levitron.runtime's __init__ (the API's lazy surface): the
    # modules the scene language loads beyond it
    code = (f"import importlib, sys, levitron\nbefore = set(sys.modules)\n"
            f"for n in {names!r}: importlib.import_module(n)\n"
            f"print(sorted(m for m in set(sys.modules) - before if m.split('.')[0] in "
            f"{('sympy', 'numpy', 'scipy', 'casadi', 'jinja2')!r} or m.startswith(('levitron.derive', "
            "'levitron.runtime'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.strip() == "[]"
    assert len(names) >= 20


def test_derive_and_the_runtime_take_of_each_other_only_what_is_listed():
    """derive/ imports nothing of the runtime or the API, and of scene/ only DERIVE_TAKES_OF_SCENE;
    the runtime and the API take of derive/ only RUNTIME_TAKES_OF_DERIVE."""
    bad = []
    for p in room_files("derive"):
        for mod, names in imports(p):
            if mod.startswith("levitron.runtime") or mod in ("levitron", "levitron.study"):
                bad.append(f"{p.relative_to(ROOT)}: {mod}")
            if mod.startswith("levitron.scene"):
                bad += [f"{p.relative_to(ROOT)}: {mod}.{n}" for n in names if n not in DERIVE_TAKES_OF_SCENE]
    for p in room_files("runtime") + room_files("levitron"):
        for mod, _ in imports(p):
            if mod.startswith("levitron.derive") and mod not in RUNTIME_TAKES_OF_DERIVE:
                bad.append(f"{p.relative_to(ROOT)}: {mod}")
    assert bad == []


def test_the_input_hash_covers_all_of_derive():
    """Every .py and .j2 under derive/ is hashed (derive/ is what shapes generated/), nothing of
    scene/ is (a better error message leaves every model current), and the hash moves when a
    derive/ source does (a byte appended to a copy of the list's first file)."""
    from levitron.scene import inputs
    from levitron.scene.paths import DERIVE_DIR
    hashed = inputs.hashed_sources()
    on_disk = sorted(p for p in DERIVE_DIR.rglob("*") if p.suffix in (".py", ".j2")
                     and "__pycache__" not in p.parts)
    assert hashed == on_disk
    names = {p.relative_to(DERIVE_DIR).as_posix() for p in hashed}
    assert {"spec.py", "mechanics.py", "friction.py", "emit/lower.py", "emit/c/printer.py",
            "plate_fields/annulus.py", "expr_parse.py", "build.py", "atomic_dir.py", "__main__.py"} <= names
    assert any(n.endswith(".j2") for n in names)
    assert not any((ROOT / "scene") in p.parents for p in hashed)
    assert not hasattr(inputs, "NOT_SHAPING")


# The house's ceiling: no module over 400 lines (the last over it, runtime/bench/work_precision.py,
# was split: per_call.py, operating_point.py). OVER_TODAY would list a file allowed over it for now,
# with its length: the test fails when one grows, and when one is split under the ceiling.
MAX_LINES = 400
OVER_TODAY: dict[str, int] = {}


def test_no_module_is_over_the_house_ceiling():
    lengths = {p.relative_to(ROOT).as_posix(): len(p.read_text().splitlines())
               for room in ("scene", "derive", "runtime", "levitron") for p in room_files(room)}
    over = {name: n for name, n in lengths.items() if n > MAX_LINES and name not in OVER_TODAY}
    assert over == {}
    grown = {name: (lengths.get(name), was) for name, was in OVER_TODAY.items()
             if lengths.get(name, 0) > was or lengths.get(name, 0) <= MAX_LINES}
    assert grown == {}, "an allowlisted file grew, or is under the ceiling now: drop its entry"


def test_every_public_name_of_every_package_resolves():
    """Each subpackage's lazy surface (runtime.lazy_surface) names only what exists."""
    import importlib
    for name in ROOMS:
        pkg = importlib.import_module(f"levitron.runtime.{name}")
        for public in pkg.__all__:
            assert getattr(pkg, public) is not None, (name, public)
            assert public in dir(pkg)


# The tests' own layout (tests/README.md): a folder per room, what tests share in helpers/.
TEST_ROOMS = {"scene", "derive", "c", "api", "cli", "battery", "house", "helpers", "tools",
              *(f"runtime/{name}" for name in ROOMS if name != "physics"),
              *(f"runtime/physics/{room}" for room in PHYSICS_ROOMS)}


def test_every_test_lives_in_its_rooms_folder():
    tests = ROOT / "tests"
    rooms = {p.parent.relative_to(tests).as_posix() for p in tests.rglob("*.py")
             if "__pycache__" not in p.parts and p.name != "conftest.py"}     # a folder's fixtures: any folder
    assert rooms - {"."} <= TEST_ROOMS, sorted(rooms - {"."} - TEST_ROOMS)
    assert sorted(p.name for p in tests.glob("*.py")) == ["conftest.py"], "a flat test: move it to its room"
    runtime_rooms = {p.name for p in (tests / "runtime").iterdir() if p.is_dir() and p.name != "__pycache__"}
    assert runtime_rooms <= set(ROOMS), "tests/runtime/<sub> names no runtime subpackage"


def test_no_test_module_imports_another():
    """Shared code is in tests/helpers (imported as tests.helpers.<name>), never in a test module."""
    tests = ROOT / "tests"
    bad = []
    for path in tests.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or "", *(f"{node.module}.{a.name}" for a in node.names)]
                     if isinstance(node, ast.ImportFrom) else [])
            bad += [f"{path.relative_to(ROOT)}: {n}" for n in names
                    if n.split(".")[-1].startswith("test_") or n.startswith(("conftest", "tests.test"))]
    assert bad == []


def test_the_c_test_systems_live_under_tests():
    """The systems only the tests integrate are compiled into the tests' library (tests/c/systems.c),
    never into a model's library or the wheel (runtime/csrc/*.c): only the thesis's circle, which
    `levitron bench` runs, stays there."""
    shipped = "".join(p.read_text() for p in sorted((RUNTIME / "csrc").glob("*.c")))
    tests_only = (ROOT / "tests" / "c" / "systems.c").read_text()
    for name in ("lev_oscillator_rhs", "lev_kepler_rhs", "lev_blowup_rhs", "lev_drift_rhs"):
        assert name not in shipped and f"void {name}(" in tests_only, name
    assert "void lev_circle_rhs(" in shipped


def test_the_integrators_pieces_are_one_translation_unit():
    """runtime/csrc/integrators.c includes each fragment integrators_*.c.h once, and nothing else includes
    them (each refuses to compile outside it): the C side is one unit, split by idea. A fragment is
    named .c.h (CPython's convention), a header shared by several units .h (runtime/csrc/README.md)."""
    csrc = RUNTIME / "csrc"
    pieces = sorted(p.name for p in csrc.glob("integrators_*.c.h"))
    assert len(pieces) >= 6
    included = re.findall(r'^#include "(integrators_\w+\.c\.h)"', (csrc / "integrators.c").read_text(), re.M)
    assert sorted(included) == pieces and len(set(included)) == len(included)
    for path in [*csrc.glob("*.c"), *csrc.glob("*.h"), *(ROOT / "derive").rglob("*.j2")]:
        if path.name != "integrators.c":
            assert not re.search(r'#include "integrators_', path.read_text()), path
    for name in pieces:
        assert "#ifndef LEV_INTEGRATORS_TU" in (csrc / name).read_text(), name
    guarded = sorted(p.name for p in [*csrc.glob("*.c"), *csrc.glob("*.h")]
                     if "#ifndef LEV_INTEGRATORS_TU" in p.read_text())
    assert guarded == pieces, "a piece of integrators.c's unit is named .c.h, never .h"
