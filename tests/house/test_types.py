"""Seen by type checkers: the package says it is typed (py.typed), the lazily loaded public names are
imported for type checkers too (the same names from the same modules), and `mypy --strict` passes on
the public API (pyproject.toml [tool.mypy]: levitron/__init__.py, study.py, study_options.py), where a
user's code gets real types: a wrong type or a misspelt option is an error, not Any.

mypy reads the checkout itself: levitron.runtime is levitron/runtime/, a link to the top-level runtime/
(docs/INTERFACES.md "Layout"; tests/house/test_import_paths.py)."""
from __future__ import annotations

import ast
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
INIT = ROOT / "levitron" / "__init__.py"
CHECKED = ("levitron/__init__.py", "levitron/study.py", "levitron/study_options.py")

GOOD = '''import levitron as lev

s: lev.Study = lev.load("thesis")
x: float | None = s.stability().z_s
sim: lev.Simulation = s.simulate(1000.0, t_end=1.0, tilt_azimuth=0.1)
odds: lev.LaunchOdds = s.launch(n=10, success_time=2.0, workers=1)
'''
BAD = '''import levitron as lev

s: lev.Study = lev.load("thesis")
y: str = s.stability().z_s
s.simulate(1000.0, tend=1.0)
lev.Nope
'''


def typed_imports() -> tuple[dict[str, str], dict[str, str], list[str]]:
    """({name: module} imported under `if TYPE_CHECKING:`, the lazy map {name: module}, __all__)."""
    tree = ast.parse(INIT.read_text())
    typed: dict[str, str] = {}
    lazy: dict[str, str] = {}
    exported: list[str] = []
    for node in tree.body:
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            for imp in node.body:
                assert isinstance(imp, ast.ImportFrom) and imp.level == 0, ast.dump(imp)
                typed.update({a.name: imp.module for a in imp.names if a.asname is None})
        elif isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name):
            if node.targets[0].id == "_EXPORTS":
                lazy = {f"{k}": f"levitron.{v}" for k, v in ast.literal_eval(node.value).items()}
            elif node.targets[0].id == "__all__":
                exported = ast.literal_eval(node.value)
    return typed, lazy, exported


def test_the_names_type_checkers_see_are_the_lazy_ones():
    typed, lazy, exported = typed_imports()
    assert lazy and typed == lazy
    assert exported == sorted(lazy)
    import levitron
    assert levitron.__all__ == exported
    for name in exported:      # the lazy loader gives the very object the typed import names
        module = __import__(lazy[name], fromlist=[name])
        assert getattr(levitron, name) is getattr(module, name)


def test_the_package_says_it_is_typed():
    assert (ROOT / "levitron" / "py.typed").is_file()
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "py.typed" in config["tool"]["setuptools"]["package-data"]["levitron"]
    assert config["tool"]["mypy"]["strict"] is True


@pytest.fixture(scope="module")
def scripts(tmp_path_factory) -> Path:
    """A user's two scripts, outside the checkout (and mypy's cache beside them)."""
    tmp = tmp_path_factory.mktemp("typed")
    (tmp / "good.py").write_text(GOOD)
    (tmp / "bad.py").write_text(BAD)
    return tmp


def mypy(scripts: Path, *files: str) -> subprocess.CompletedProcess[str]:
    """mypy from the checkout's top: `levitron` is its levitron/ folder (mypy adds the working directory)."""
    return subprocess.run([sys.executable, "-m", "mypy", "--config-file", str(ROOT / "pyproject.toml"),
                           "--cache-dir", str(scripts / ".mypy_cache"), "--no-error-summary", "--hide-error-context",
                           *files], cwd=ROOT, capture_output=True, text=True, timeout=300, check=False)


def test_mypy_strict_passes_on_the_public_api(scripts):
    """The public API module and a user's script that uses it as documented type-check under --strict."""
    run = mypy(scripts, *CHECKED, str(scripts / "good.py"))
    assert run.returncode == 0, run.stdout + run.stderr


def test_mypy_sees_the_public_names_and_the_options(scripts):
    """Not Any: a wrong type, a misspelt option and a name the package lacks are each an error."""
    run = mypy(scripts, str(scripts / "bad.py"))
    assert run.returncode == 1, run.stdout + run.stderr
    errors = [line for line in run.stdout.splitlines() if ": error:" in line]
    assert len(errors) == 3, run.stdout
    assert 'bad.py:4: error: Incompatible types in assignment (expression has type "float | None", variable has ' \
           'type "str")' in run.stdout
    assert 'bad.py:5: error: Unexpected keyword argument "tend" for "simulate" of "Study"; did you mean ' \
           '"t_end"?' in run.stdout
    assert 'bad.py:6: error: Module has no attribute "Nope"' in run.stdout
