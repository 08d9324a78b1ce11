"""The import path is the folder path: `levitron.runtime.cli.main` is levitron/runtime/cli/main.py.

The top-level folders runtime/, derive/, scene/, scenes/ and generated/ are the code; levitron/ holds
relative links to them (docs/INTERFACES.md "Layout"), so an IDE, mypy or pyright finds each module of
`levitron` where its name says, with no mapping in pyproject.toml and no `__path__` extension. Checked
without importing anything: every `levitron` import of every .py of the checkout (read with ast) names a
file or a package at that path, and a name it takes from a module is a submodule or bound in that
module's source. And mypy, given levitron/__init__.py alone, reads the modules it imports from there."""
from __future__ import annotations

import ast
import functools
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
LINKS = ("runtime", "derive", "scene", "scenes", "generated")
ROOMS = ("runtime", "derive", "scene", "levitron", "tests")
SCOPES = (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)


def sources(root: Path) -> list[Path]:
    """Every .py of the code and the tests, each once: not again through levitron/'s links."""
    found = []
    for room in ROOMS:
        for path in sorted((root / room).rglob("*.py")):
            inside = path.relative_to(root).parents
            if "__pycache__" not in path.parts and not any((root / p).is_symlink() for p in inside):
                found.append(path)
    return found


def target(root: Path, module: str) -> Path | None:
    """The file the import path names: levitron/a/b.py, or levitron/a/b/__init__.py for a package."""
    folder = root.joinpath(*module.split("."))
    for candidate in (folder.with_suffix(".py"), folder / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


@functools.lru_cache(maxsize=None)
def tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(encoding="utf-8"), filename=str(path))


def statements(node: ast.AST, into_scopes: bool = True):
    """The statements below a node (in blocks of if, try, with, loops; of functions and classes too
    when into_scopes): an import or a binding is a statement, so expressions are not read."""
    for field in ("body", "orelse", "finalbody", "handlers", "cases"):
        for child in getattr(node, field, None) or ():
            if isinstance(child, (ast.stmt, ast.excepthandler, ast.match_case)):
                yield child
                if into_scopes or not isinstance(child, SCOPES):
                    yield from statements(child, into_scopes)


@functools.lru_cache(maxsize=None)
def bound(path: Path) -> frozenset[str]:
    """The names a module binds at its top level, in `if` and `try` blocks too (TYPE_CHECKING imports)."""
    names: set[str] = set()
    for node in statements(tree(path), into_scopes=False):
        if isinstance(node, SCOPES):
            names.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            names.update((a.asname or a.name).partition(".")[0] for a in node.names)
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign, ast.For, ast.With)):
            targets = [getattr(node, "target", None), *getattr(node, "targets", ()),
                       *(i.optional_vars for i in getattr(node, "items", ()))]
            names.update(n.id for t in targets if t is not None for n in ast.walk(t) if isinstance(n, ast.Name))
    return frozenset(names)


def module_name(root: Path, path: Path) -> str | None:
    """A source file's name under `levitron` (runtime/x.py is levitron.runtime.x); None for the tests."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[0] in LINKS:
        parts.insert(0, "levitron")
    elif parts[0] != "levitron":
        return None
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imports(root: Path, path: Path):
    """(line, module, names) of each import of `levitron` in the file, relative ones made absolute;
    names: a `from` import's names, () for a plain import."""
    here = module_name(root, path)
    for node in statements(tree(path)):
        if isinstance(node, ast.Import):
            yield from ((node.lineno, a.name, ()) for a in node.names if a.name.split(".")[0] == "levitron")
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level:
                if here is None:
                    continue
                package = here.split(".") if path.name == "__init__.py" else here.split(".")[:-1]
                module = ".".join(package[:len(package) - node.level + 1] + ([module] if module else []))
            if module.split(".")[0] == "levitron":
                yield node.lineno, module, tuple(a.name for a in node.names)


@functools.lru_cache(maxsize=None)
def lazy(path: Path) -> dict[str, str]:
    """A package's names loaded on first use (runtime/__init__.py lazy_surface): its `_EXPORTS`, {name:
    module relative to the package}; {} for a module without one."""
    for node in tree(path).body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", None) == "_EXPORTS" for t in node.targets):
            return ast.literal_eval(node.value)
    return {}


def provides(root: Path, module: str, found: Path, name: str) -> bool:
    """Whether `from module import name` finds it: a submodule, a name the module's source binds, or
    one it loads lazily from a module (at its folder path) that binds it."""
    if name == "*" or target(root, f"{module}.{name}") is not None or name in bound(found):
        return True
    origin = target(root, f"{module}.{lazy(found)[name]}") if name in lazy(found) else None
    return origin is not None and name in bound(origin)


def unresolved(root: Path) -> tuple[list[str], dict[str, int]]:
    """('file:line: what', ...) of every levitron import, and every name of a lazy map, that names no
    file at its path, and how many imports each room makes."""
    problems: list[str] = []
    counted = dict.fromkeys(ROOMS, 0)
    for path in sources(root):
        where = path.relative_to(root).as_posix()
        for line, module, names in imports(root, path):
            counted[where.split("/")[0]] += 1
            found = target(root, module)
            if found is None:
                problems.append(f"{where}:{line}: {module} is no file at {module.replace('.', '/')}(.py)")
                continue
            problems += [f"{where}:{line}: {module} has no {name} (no {module.replace('.', '/')}/{name}.py, "
                         f"no name in {found.relative_to(root)})"
                         for name in names if not provides(root, module, found, name)]
        package = module_name(root, path)
        for name, home in lazy(path).items():
            origin = target(root, f"{package}.{home}")
            if origin is None or name not in bound(origin):
                problems.append(f"{where}: _EXPORTS: {package}.{home} has no {name}")
    return problems, counted


def test_levitron_holds_relative_links_to_the_top_level_folders():
    for name in LINKS:
        link = ROOT / "levitron" / name
        assert link.is_symlink(), f"levitron/{name} is no link (ln -s ../{name} levitron/{name})"
        assert os.readlink(link) == f"../{name}" and link.resolve() == ROOT / name


def test_every_levitron_import_names_a_file_at_its_folder_path():
    problems, counted = unresolved(ROOT)
    assert not problems, f"{len(problems)} imports name no file where they say:\n" + "\n".join(problems)
    assert all(counted.values()), counted        # every room was read and imports levitron


def test_a_missing_link_or_name_is_reported(tmp_path):
    """The check can fail: without the link levitron/runtime, or for a name the module lacks."""
    (tmp_path / "levitron").mkdir()
    (tmp_path / "runtime").mkdir()
    (tmp_path / "levitron" / "__init__.py").write_text("from levitron.runtime.errors import UserError\n"
                                                       "from .runtime import errors\nimport levitron.runtime\n")
    (tmp_path / "runtime" / "__init__.py").write_text("")
    (tmp_path / "runtime" / "errors.py").write_text("from ..runtime import errors\nfrom . import nothing\n"
                                                    "class UserError(Exception):\n    pass\n")
    problems, _ = unresolved(tmp_path)
    missing = "levitron.runtime is no file at levitron/runtime(.py)"
    assert [p.split(": ")[1] for p in problems] == [      # runtime/errors.py's two, then levitron/__init__.py's
        missing, missing, "levitron.runtime.errors is no file at levitron/runtime/errors(.py)", missing, missing]
    (tmp_path / "levitron" / "runtime").symlink_to("../runtime", target_is_directory=True)
    problems, _ = unresolved(tmp_path)
    assert [p.split(": ")[1] for p in problems] == [
        "levitron.runtime has no nothing (no levitron/runtime/nothing.py, no name in levitron/runtime/__init__.py)"]


def test_mypy_reads_the_modules_from_their_folder_paths(tmp_path):
    """mypy on levitron/__init__.py alone (what it imports read silently) finds no import missing and
    reads every levitron module from the file its name says."""
    run = subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(ROOT / "pyproject.toml"),
                          "--cache-dir", str(tmp_path / "cache"), "--follow-imports=silent", "--no-error-summary",
                          "--verbose", "levitron/__init__.py"], cwd=ROOT, capture_output=True, text=True,
                         timeout=300, check=False)
    assert run.returncode == 0, run.stdout + run.stderr[-3000:]
    read = {module: ROOT / path for path, module in re.findall(r"LOG:  Parsing (\S+) \((levitron[\w.]*)\)", run.stderr)}
    assert {m: p for m, p in read.items() if p != target(ROOT, m)} == {}
    wanted = {module for _, module, _ in imports(ROOT, ROOT / "levitron" / "__init__.py")}
    assert "levitron.runtime.errors" in wanted and wanted <= set(read), sorted(wanted - set(read))


def test_the_modules_that_find_the_checkout_find_it_through_the_links(monkeypatch):
    """Imported through levitron/'s links, a module's __file__ is levitron/scene/paths.py: the paths it
    takes from its own file (after resolve()) are still the checkout's."""
    import importlib.metadata

    from levitron.runtime.cli import schema
    from levitron.runtime.ui import provenance
    from levitron.scene import paths
    from levitron.scene.plates import docs
    assert Path(paths.__file__) == ROOT / "levitron" / "scene" / "paths.py"
    assert (paths.ROOT, paths.SCENES_DIR, paths.GENERATED) == (ROOT, ROOT / "scenes", ROOT / "generated")
    assert schema.default_folder() == ROOT / "docs" / "schemas" and docs.DOC == ROOT / "docs" / "scenes.md"

    def not_installed(name):
        raise importlib.metadata.PackageNotFoundError(name)
    monkeypatch.setattr(importlib.metadata, "version", not_installed)
    provenance.version.cache_clear()
    try:                                 # not installed: the version is read from the checkout's pyproject.toml
        assert provenance.version() == tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    finally:
        provenance.version.cache_clear()
