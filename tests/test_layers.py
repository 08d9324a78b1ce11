"""The house's rooms: runtime/ in subpackages by idea, imports only down the layers, no import
cycles (function-level imports counted too), no private name across packages, and a public API
(levitron) that stands on the runtime, not on the command line."""
from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RUNTIME = ROOT / "runtime"

# bottom to top: a module may import from its own layer and the ones below it
LAYERS = ("errors", "ui", "model", "integrate", "physics", "simulate", "scan", "design", "report",
          "bench", "cli")
RANK = {name: i for i, name in enumerate(LAYERS)}
TOP_LEVEL = {"__init__.py", "__main__.py", "errors.py", "csrc", "__pycache__"}


def module_name(path: Path) -> str:
    """The import name of a file of the checkout: derive/ and runtime/ sit under levitron."""
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts if parts[0] == "levitron" else ["levitron", *parts])


def imports(path: Path):
    """(imported module, imported names) of every import in the file, nested ones included; a
    runtime module imports by absolute path only (levitron's own modules relatively)."""
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, ()
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                assert RUNTIME not in path.parents, f"{path}: relative import (write levitron.runtime.<package>)"
                continue
            yield node.module or "", tuple(a.name for a in node.names)


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


def test_the_top_level_holds_entry_points_errors_csrc_and_subpackages():
    extra = sorted(p.name for p in RUNTIME.iterdir()
                   if p.name not in TOP_LEVEL and not (p.is_dir() and (p / "__init__.py").exists()))
    assert extra == []
    assert sorted(p.name for p in RUNTIME.iterdir() if p.is_dir() and p.name != "csrc"
                  and p.name != "__pycache__") == sorted(n for n in LAYERS if n != "errors")


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


def test_the_input_hash_covers_what_shapes_generated_only():
    """derive's scene reader and checks, paths, docs and fault injection are not hashed: a fix to an
    error message leaves every generated model current; the code that shapes models is hashed."""
    from levitron.derive.inputs import DERIVE_DIR, NOT_SHAPING, hashed_sources
    names = {p.relative_to(DERIVE_DIR).as_posix() for p in hashed_sources()}
    assert all((DERIVE_DIR / n).exists() for n in NOT_SHAPING)
    assert not names & NOT_SHAPING
    assert {"spec.py", "mechanics.py", "friction.py", "emit/lower.py", "emit/c/printer.py",
            "plates/annulus.py", "inputs.py", "build.py"} <= names
    assert any(n.endswith(".j2") for n in names)


def test_every_public_name_of_every_package_resolves():
    """Each subpackage's lazy surface (runtime.lazy_surface) names only what exists."""
    import importlib
    for name in LAYERS[1:]:
        pkg = importlib.import_module(f"levitron.runtime.{name}")
        for public in pkg.__all__:
            assert getattr(pkg, public) is not None, (name, public)
            assert public in dir(pkg)
