"""Nothing is lost or left behind when a run is killed, and a relative cache stays where the user
is (no data loss).

Kills are real (SIGKILL, which no handler sees) at injected points (scene/faults.py,
LEVITRON_FAULT=POINT:MARKER): between write_atomic's steps, in the derive child, in the runtime while
its derive child runs. After the next run: the folder is there with one complete model, no temporary
of a dead owner is left (their mtime is set back past derive/atomic_dir.py's and
runtime/model/cache_sweep.py's one minute, as if the minute had passed), and no orphaned child runs on.
"""
from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from levitron.derive.atomic_dir import recover
from levitron.derive.build import write_atomic

ROOT = Path(__file__).resolve().parents[2]
OLD = {"manifest.json": b"old", "a": b"old a"}
NEW = {"manifest.json": b"new", "a": b"new a", "b": b"new b"}


def _age(paths, seconds: float = 120.0) -> None:
    """Set the mtime of every path back by `seconds` (as if that time had passed)."""
    t = time.time() - seconds
    for p in paths:
        os.utime(p, (t, t), follow_symlinks=False)


def _contents(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in folder.iterdir()}


def _write_killed(target: Path, point: str, exchange: bool, tmp_path: Path) -> None:
    """write_atomic(target, NEW) in a child that SIGKILLs itself at `point`."""
    marker = tmp_path / f"marker-{point}"
    code = ("import sys; from pathlib import Path; from levitron.derive.build import write_atomic; "
            f"write_atomic(Path(sys.argv[1]), {NEW!r}, exchange={exchange})")
    env = dict(os.environ, LEVITRON_FAULT=f"{point}:{marker}", PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", code, str(target)], env=env, capture_output=True,
                         text=True, timeout=60, check=False)
    assert marker.exists() and res.returncode == -9, (res.returncode, res.stderr)


def _debris(target: Path) -> list[Path]:
    return sorted(target.parent.glob(f".{target.name}.*"))


@pytest.mark.parametrize("point,exchange,left", [
    ("write_atomic.written", True, OLD),            # killed before the swap: the old model stays
    ("write_atomic.swapped", True, NEW),            # killed after the exchange: the new one is in
    ("write_atomic.between_renames", False, None),  # the two-rename fallback: the gap
])
def test_write_atomic_killed_at_each_step(point, exchange, left, tmp_path):
    target = tmp_path / "gen" / "scene"
    write_atomic(target, OLD)
    _write_killed(target, point, exchange, tmp_path)
    if left is not None:
        assert _contents(target) == left, "the folder must be whole, old or new, after any kill"
    else:
        assert not target.exists() and _debris(target), "the fallback's gap did not happen"
        recover(target)                     # what the next derive does first (derive_scene)
        assert _contents(target) == OLD
    assert _debris(target), "the kill left nothing: the test tested nothing"
    _age(_debris(target))
    write_atomic(target, NEW)               # the next run
    assert _contents(target) == NEW
    assert _debris(target) == [], "the next run must sweep the dead writer's temporaries"


def test_a_live_writers_temporaries_are_left_alone(tmp_path):
    target = tmp_path / "gen" / "scene"
    write_atomic(target, OLD)
    mine = target.parent / f".scene.new-{os.getpid()}-abc"
    mine.mkdir()
    _age([mine])
    write_atomic(target, NEW)
    assert mine.exists()


# ---------------------------------------------------------------- the cache and the derive child

def _scene(folder: Path, name: str) -> Path:
    path = folder / f"{name}.toml"
    path.write_text("\n".join([
        f'name = "{name}"', "[top]", "mass = 0.02", "A = 2.2e-6", "C = 1.32e-6", "moment = -1.0",
        "[plate]", 'kind = "expression"', 'phi0 = "b*z/sqrt(z**2 + c**2)"', "[plate.params]",
        "b = 0.01", f"c = {0.05 + 0.001 * (len(name) % 7)!r}", "[field]", "order = 2", "[model]",
        'needs = ["reduced"]']) + "\n")
    return path


def _cli(args, cwd: Path, env: dict, timeout: float = 300) -> subprocess.CompletedProcess:
    full = dict(os.environ, PYTHONPATH=str(ROOT), **env)
    full.pop("LEVITRON_DEBUG", None)
    return subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", *args], cwd=cwd, env=full,
                          capture_output=True, text=True, timeout=timeout, check=False)


def test_a_relative_cache_is_the_users_folder(tmp_path, seed_cache):
    """Before: the derive subprocess (cwd = the repository) wrote under the checkout. (The cache is
    seeded with the runtime/csrc objects only: the derivation and the model's library are made
    there by the run.)"""
    elsewhere = tmp_path / "elsewhere"
    seed_cache(elsewhere / "relcache")
    scene = _scene(elsewhere, "relcache_scene")
    assert not (ROOT / "relcache").exists()
    res = _cli(["equilibrium", scene.name, "--json"], elsewhere, {"LEVITRON_CACHE": "relcache"})
    try:
        assert res.returncode == 0, res.stderr
        assert list((elsewhere / "relcache" / "derived").glob("relcache_scene-*/manifest.json"))
        assert not (ROOT / "relcache").exists(), "the cache went into the repository"
    finally:
        if (ROOT / "relcache").exists():
            import shutil
            shutil.rmtree(ROOT / "relcache")


def _leftovers(cache: Path) -> list[str]:
    return sorted(p.name for p in [*cache.glob(".*"), *(cache / "derived").glob(".*")])


def test_a_killed_derive_child_is_named_and_leaves_nothing(tmp_path):
    """Before: "derive failed ...: no message", and (killed parent) debris for good."""
    cache = tmp_path / "cache"
    scene = _scene(tmp_path, "killed_child")
    res = _cli(["equilibrium", str(scene)], tmp_path, {
        "LEVITRON_CACHE": str(cache), "LEVITRON_FAULT": f"derive.child:{tmp_path / 'marker'}"})
    errors = [ln for ln in res.stderr.splitlines() if not ln.startswith("levitron: ")]
    assert res.returncode == 2 and len(errors) == 1, res.stderr
    assert "was killed (signal 9)" in errors[0], errors[0]
    assert _leftovers(cache) == []


def _processes_mentioning(text: str) -> list[int]:
    found = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                cmd = (d / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            except OSError:
                continue
            if text in cmd:
                found.append(int(d.name))
    return found


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's")
def test_a_killed_parent_takes_its_derive_child_and_the_next_run_sweeps(tmp_path, seed_cache):
    cache = seed_cache(tmp_path / "cache")      # the runtime/csrc objects: not what is tested here
    scene = _scene(tmp_path, "killed_parent")
    res = _cli(["equilibrium", str(scene)], tmp_path, {
        "LEVITRON_CACHE": str(cache), "LEVITRON_FAULT": f"runtime.deriving:{tmp_path / 'marker'}"})
    assert res.returncode == -9, res.stderr
    debris = list((cache / "derived").glob(".killed_parent-*"))
    assert debris, "the kill left no temporary: the test tested nothing"
    deadline = time.monotonic() + 10
    while _processes_mentioning(str(debris[0])) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert _processes_mentioning(str(debris[0])) == [], "the derive child outlived its parent"
    # a compilation's temporaries of a dead owner, as a kill -9 mid-compile leaves them
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True, check=True).stdout.strip()
    lib_debris = [cache / f".lev_0123456789abcdef01234567_{dead}_x1y2.so",
                  cache / f".lev_0123456789abcdef01234567_{dead}_x1y2.sha256"]
    for p in lib_debris:
        p.write_bytes(b"")
    _age([*debris, *lib_debris])
    res = _cli(["equilibrium", str(scene), "--json"], tmp_path, {"LEVITRON_CACHE": str(cache)})
    assert res.returncode == 0, res.stderr
    assert _leftovers(cache) == [], "the next run must sweep the dead run's temporaries"
    assert list((cache / "derived").glob("killed_parent-*/manifest.json"))


def test_a_scene_edited_during_its_derivation_is_filed_under_what_was_read(tmp_path, monkeypatch,
                                                                          seed_cache):
    """Before: the derive child read the file again, so an edit in between filed the new formula's
    model under the old scene's hash (or failed with a wrong reason). Now the child derives a
    snapshot of what this process read and hashed."""
    from levitron.scene.inputs import input_hash
    from levitron.scene.load import load_scene
    from levitron.runtime.model.load import load_model
    monkeypatch.setenv("LEVITRON_CACHE", str(seed_cache(tmp_path / "cache")))
    path = _scene(tmp_path, "edited")
    scene = load_scene(path)
    path.write_text(path.read_text().replace("b*z/sqrt(z**2 + c**2)", "3*b*z/sqrt(z**2 + c**2)"))
    model = load_model(scene)
    assert model.manifest.input_hash == input_hash(scene.data)
    c = scene.params["plate_c"]
    want = 0.01 * 0.1 / (0.1 ** 2 + c ** 2) ** 0.5          # Phi0(0.1) of the formula as read
    assert abs(model.onaxis(0.1)[0] - want) <= 1e-14 * want
