"""One import name: the wheel puts `levitron` alone into a fresh venv's site-packages, and the package
it installs answers a command by itself (its own scenes, generated models and C sources).

The repository keeps scene/, derive/, runtime/, scenes/ and generated/ at its top level; levitron/ holds
links to them (docs/INTERFACES.md "Layout"), and the wheel holds their files in levitron/. The wheel is
built without network (--no-build-isolation: setuptools comes from the test extra) and installed without
dependencies; the fresh venv borrows numpy, casadi and the rest from this one's site-packages through
PYTHONPATH, which processes no .pth file, so this checkout's editable install cannot leak into it.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import sysconfig
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def test_the_package_list_is_every_package_of_the_tree():
    """pyproject's explicit package list (it names scenes/ and generated/, data folders without an
    __init__.py) names every package there is."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    listed = set(config["packages"])
    on_disk = {"levitron", "levitron.scenes", "levitron.generated"}
    for top in ("scene", "derive", "runtime"):
        for init in (ROOT / top).rglob("__init__.py"):
            on_disk.add(".".join(["levitron", *init.parent.relative_to(ROOT).parts]))
    assert listed == on_disk


@pytest.fixture(scope="module")
def fresh_venv(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("wheel")
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", str(ROOT), "--no-deps", "--no-build-isolation",
                            "--quiet", "-w", str(tmp / "dist")], capture_output=True, text=True, check=False)
    assert build.returncode == 0, build.stderr[-3000:]
    (wheel,) = (tmp / "dist").glob("levitron-*.whl")
    venv = tmp / "venv"           # without pip (ensurepip took 4 s): this venv's pip installs into it
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    py = venv / "bin" / "python"
    site = Path(subprocess.run([str(py), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                               capture_output=True, text=True, check=True).stdout.strip())
    before = {p.name for p in site.iterdir()}
    subprocess.run([sys.executable, "-m", "pip", "--python", str(py), "install", "--quiet", "--no-deps",
                    "--no-index", str(wheel)], check=True)
    after = {p.name for p in site.iterdir()}
    return venv, sorted(after - before), tmp


def test_the_wheel_installs_one_top_level_name(fresh_venv):
    venv, added, _ = fresh_venv
    assert [n for n in added if not n.endswith(".dist-info")] == ["levitron"]
    assert (venv / "bin" / "levitron").is_file()


def test_the_installed_package_answers_from_its_own_files(fresh_venv):
    """`levitron stability thesis_stable` from the installed copy: its committed model is current
    (not re-derived), compiled from its own csrc, and gives the checkout's interval."""
    venv, _, tmp = fresh_venv
    env = dict(os.environ, PYTHONPATH=sysconfig.get_paths()["purelib"], LEVITRON_CACHE=str(tmp / "cache"))
    work = tmp / "elsewhere"
    work.mkdir()
    res = subprocess.run([str(venv / "bin" / "levitron"), "stability", "thesis_stable", "--json"], cwd=work,
                         env=env, capture_output=True, text=True, check=False)
    assert res.returncode == 0, res.stderr
    assert "stale" not in res.stderr and "deriving" not in res.stderr
    out = json.loads(res.stdout)
    assert out["provenance"]["scene_path"].startswith(str(venv))
    mine = subprocess.run([sys.executable, "-m", "levitron", "stability", "thesis_stable", "--json"], cwd=ROOT,
                          capture_output=True, text=True, check=True)
    assert out["spin_interval"] == json.loads(mine.stdout)["spin_interval"]
    assert list(work.iterdir()) == []


def test_the_wheel_carries_its_licence_version_and_types(fresh_venv):
    """A real package's papers: the licence as SPDX metadata with its file, `levitron.__version__`
    equal to the metadata's version, and py.typed for type checkers."""
    venv, added, _ = fresh_venv
    (dist,) = [n for n in added if n.endswith(".dist-info")]
    site = (venv / "lib").glob("python*/site-packages")
    site = next(iter(site))
    meta = (site / dist / "METADATA").read_text()
    assert "License-Expression: BSD-3-Clause" in meta and "Classifier: Typing :: Typed" in meta
    assert list((site / dist).rglob("LICENSE"))
    assert (site / "levitron" / "py.typed").is_file()
    env = dict(os.environ, PYTHONPATH=sysconfig.get_paths()["purelib"])
    got = subprocess.run([str(venv / "bin" / "python"), "-c", "import levitron; print(levitron.__version__)"],
                         cwd=venv, env=env, capture_output=True, text=True, check=True).stdout.strip()
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert got == version


def test_the_installed_command_lists_its_scenes_and_a_kinds_keys(fresh_venv):
    """A wheel's user, outside the repository, meets the shipped scenes (`levitron scenes`: the
    checkout's scenes/, from the installed copy's own folder) and a plate kind's keys with their
    units (`levitron keys annulus`): exit 0, in the human view and in JSON."""
    from levitron.scene.plates import KINDS
    venv, _, tmp = fresh_venv
    env = dict(os.environ, PYTHONPATH=sysconfig.get_paths()["purelib"], LEVITRON_CACHE=str(tmp / "cache"))
    work = tmp / "a_users_folder"
    work.mkdir()

    def levitron(*argv) -> str:
        res = subprocess.run([str(venv / "bin" / "levitron"), *argv], cwd=work, env=env, capture_output=True,
                             text=True, check=False, timeout=120)
        assert res.returncode == 0, f"levitron {' '.join(argv)}: {res.stderr[-2000:]}"
        return res.stdout

    shipped = sorted(p.stem for p in (ROOT / "scenes").glob("*.toml"))
    listed = json.loads(levitron("scenes", "--json"))
    assert sorted(s["name"] for s in listed["scenes"]) == shipped
    assert all(s["file"].startswith(str(venv)) for s in listed["scenes"]), listed["folder"]
    text = levitron("scenes")
    assert all(name in text.split() for name in shipped)

    keys = json.loads(levitron("keys", "annulus", "--json"))
    units = {k["name"]: k["unit"] for k in keys["keys"]}
    assert keys["kind"] == "annulus" and units == {k.name: k.unit for k in KINDS["annulus"].keys}
    assert units["radius"] == "m" and units["murho"] == "J m"
    text = levitron("keys", "annulus")
    assert all(f"{name}  " in text and unit in text for name, unit in units.items())
    assert list(work.iterdir()) == []
