"""Verified artefacts: no generated or cached model file is used unchecked.

An edited model.c, a manifest with swapped parameters or a wrong output size, a truncated .casadi
file or library, a missing manifest key: each is refused with one line naming the file (or key)
and `make derive`, or, in the cache, derived or built again once. Variants never overwrite
generated/; relative scene paths work from any folder; a bad cache is one line. Every test works
on temporary copies (of one session-wide derivation of the smallest scene), never on generated/.
"""
from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from levitron.derive.build import derive_scene
from levitron.scene.digest import SELF_KEY, manifest_digest
from levitron.scene.paths import ROOT
from levitron.scene.load import load_scene
from levitron.runtime.model.cbuild import compile_shared
from levitron.runtime.model.manifest import ArtefactError

SCENE = "reduced_only"
PY = sys.executable


@pytest.fixture(scope="session")
def fresh(tmp_path_factory):
    """A current derivation of scenes/reduced_only.toml in a session folder: (scene, folder)."""
    scene = load_scene(SCENE)
    root = tmp_path_factory.mktemp("fresh")
    derive_scene(scene, root, force=True)
    return scene, root / SCENE


@pytest.fixture(scope="session")
def lib_cache(tmp_path_factory, seed_cache):
    """One cache for the compiled library of the intact model (built once, reused)."""
    return seed_cache(tmp_path_factory.mktemp("libcache"))


@pytest.fixture
def copy(fresh, tmp_path, lib_cache, monkeypatch):
    """A private copy of the fresh model folder (tmp/generated/reduced_only)."""
    monkeypatch.setenv("LEVITRON_CACHE", str(lib_cache))
    folder = tmp_path / "generated" / SCENE
    shutil.copytree(fresh[1], folder)
    return folder


def edit_manifest(folder: Path, edit, redigest: bool = True) -> None:
    """Apply edit(dict) to folder/manifest.json; with redigest its own sha256 is made to match, as
    a careful forger would."""
    path = folder / "manifest.json"
    data = json.loads(path.read_text())
    edit(data)
    if redigest:
        data[SELF_KEY] = manifest_digest(data)
    path.write_text(json.dumps(data, indent=2, sort_keys=True))


def one_line(exc) -> str:
    msg = str(exc.value)
    assert "\n" not in msg, msg
    return msg


def model(scene, folder):
    from levitron.runtime.model.load import Model
    return Model(scene, folder)


# ------------------------------------------------------------------ generated files

def test_intact_copy_loads_and_agrees_with_its_table(fresh, copy):
    m = model(fresh[0], copy)
    phi = m.onaxis(0.1)
    assert phi.shape == (m.manifest.onaxis_K + 1,)
    assert m.call("onaxis", [0.1], backend="casadi") == pytest.approx(phi, rel=1e-12)


def test_edited_model_c_is_refused(fresh, copy):
    with (copy / "model.c").open("a") as f:
        f.write("/* a hand edit */\n")
    with pytest.raises(ArtefactError) as info:
        model(fresh[0], copy)
    msg = one_line(info)
    assert "model.c" in msg and "make derive" in msg


def test_edited_generated_model_is_an_error_not_silently_used(fresh, copy, tmp_path, monkeypatch):
    """load_model: a current generated/<scene> whose model.c was edited is refused, never used."""
    import levitron.runtime.model.load as rm
    import levitron.runtime.model.locate as where
    monkeypatch.setattr(where, "GENERATED", copy.parent)
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    text = (copy / "model.c").read_text()
    (copy / "model.c").write_text(text.replace("out[0] =", "out[0] = 2.0 *", 1))
    with pytest.raises(ArtefactError) as info:
        rm.load_model(fresh[0])
    msg = one_line(info)
    assert f"generated/{SCENE}/model.c" in msg and "make derive" in msg
    assert not (tmp_path / "cache" / "derived").exists()      # nothing derived behind its back


def test_swapped_parameters_are_refused(fresh, copy):
    def swap(d):
        d["parameters"][0], d["parameters"][1] = d["parameters"][1], d["parameters"][0]
    edit_manifest(copy, swap, redigest=False)
    with pytest.raises(ArtefactError) as info:
        model(fresh[0], copy)
    assert "manifest.json" in one_line(info) and "edited" in one_line(info)


def test_swapped_parameters_with_a_forged_digest_are_caught_by_the_library_table(fresh, copy):
    def swap(d):
        d["parameters"][0], d["parameters"][1] = d["parameters"][1], d["parameters"][0]
    edit_manifest(copy, swap)
    m = model(fresh[0], copy)              # consistent on its own ...
    with pytest.raises(ArtefactError) as info:
        m.onaxis(0.1)                      # ... but the compiled model.c says otherwise
    msg = one_line(info)
    assert "parameters" in msg and "make derive" in msg


def test_too_small_n_out_is_refused_by_the_manifest_check(fresh, copy):
    def shrink(d):
        d["functions"]["reduced_rhs"]["n_out"] = 2
        d["functions"]["reduced_rhs"]["shape"] = [2]
    edit_manifest(copy, shrink)
    with pytest.raises(ArtefactError) as info:
        model(fresh[0], copy)
    assert "reduced_rhs" in one_line(info)


def test_too_small_n_out_never_reaches_the_c_code(fresh, copy):
    """A self-consistent manifest (onaxis_K lowered with onaxis' n_out): only the library's table
    shows that onaxis writes 5 values; the call is refused instead of writing past a buffer."""
    def shrink(d):
        d["functions"]["onaxis"]["n_out"] = 2
        d["functions"]["onaxis"]["shape"] = [2]
        d["onaxis_K"] = 1
    edit_manifest(copy, shrink)
    m = model(fresh[0], copy)
    with pytest.raises(ArtefactError) as info:
        m.onaxis(0.1)
    msg = one_line(info)
    assert "onaxis" in msg and "n_out" in msg
    with pytest.raises(ArtefactError):
        m.fast("onaxis")


def test_truncated_casadi_file_is_refused(fresh, copy):
    data = (copy / "onaxis.casadi").read_bytes()
    (copy / "onaxis.casadi").write_bytes(data[: len(data) // 2])
    with pytest.raises(ArtefactError) as info:
        model(fresh[0], copy)
    msg = one_line(info)
    assert "onaxis.casadi" in msg and "make derive" in msg


def test_truncated_casadi_file_with_forged_digests_is_one_line(fresh, copy):
    from levitron.scene.digest import sha256_hex
    data = (copy / "onaxis.casadi").read_bytes()[:3000]
    (copy / "onaxis.casadi").write_bytes(data)
    edit_manifest(copy, lambda d: d["files"].__setitem__("onaxis.casadi", sha256_hex(data)))
    m = model(fresh[0], copy)
    with pytest.raises(ArtefactError) as info:
        m.casadi("onaxis")
    assert "onaxis.casadi" in one_line(info)


TOP_KEYS = ["coordinates", "field_order", "field_order_choice", "files", "functions", "generator",
            "input_hash", "note", "onaxis_K", "parameters", "parts", "plate", "scene", "versions",
            SELF_KEY]


@pytest.mark.parametrize("key", TOP_KEYS + ["functions.onaxis.n_out", "parts.reduced.states",
                                            "functions.reduced_rhs.casadi"])
def test_missing_manifest_key_is_named(fresh, copy, key):
    def drop(d):
        *path, last = key.split(".")
        node = d
        for k in path:
            node = node[k]
        del node[last]
    edit_manifest(copy, drop, redigest=False)
    with pytest.raises(ArtefactError) as info:
        model(fresh[0], copy)
    msg = one_line(info)
    assert f"'{key}'" in msg and "missing" in msg and "make derive" in msg


def test_mistyped_manifest_key_is_named(fresh, copy):
    edit_manifest(copy, lambda d: d["functions"]["onaxis"].__setitem__("n_out", "5"))
    with pytest.raises(ArtefactError) as info:
        model(fresh[0], copy)
    assert "'functions.onaxis.n_out'" in one_line(info)


def test_manifest_file_names_stay_in_the_folder(fresh, copy):
    edit_manifest(copy, lambda d: d["files"].__setitem__("../../etc/passwd", "0" * 64))
    with pytest.raises(ArtefactError) as info:
        model(fresh[0], copy)
    assert "not a plain file name" in one_line(info)


def test_make_derive_repairs_an_edited_file(fresh, copy):
    """derive skips a folder only when every digest holds: `make derive` restores an edited file."""
    good = (copy / "model.c").read_bytes()
    (copy / "model.c").write_bytes(good + b"/* edit */\n")
    res = derive_scene(fresh[0], copy.parent)
    assert not res["skipped"] and (copy / "model.c").read_bytes() == good
    assert derive_scene(fresh[0], copy.parent)["skipped"]


# ------------------------------------------------------------------ the cache

def test_edited_cached_model_is_derived_again_once(fresh, tmp_path, monkeypatch, capsys):
    import levitron.runtime.model.load as rm
    import levitron.runtime.model.locate as where
    monkeypatch.setattr(where, "GENERATED", tmp_path / "no-generated")    # force the cache route
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    scene = fresh[0]
    cached = where.cache_folder(scene)
    shutil.copytree(fresh[1], cached)
    assert rm.load_model(scene).folder == cached                       # intact: used as it is
    assert "deriving" not in capsys.readouterr().err
    good = (cached / "model.c").read_bytes()
    (cached / "model.c").write_bytes(good.replace(b"out[0] =", b"out[0] = 2.0 *", 1))
    m = rm.load_model(scene)
    err = capsys.readouterr().err
    assert "damaged" in err and "model.c" in err and "deriving" in err
    assert m.folder == cached and (cached / "model.c").read_bytes() == good
    assert [p.name for p in cached.parent.iterdir()] == [cached.name]   # no temporary folder left
    rm.load_model(scene)
    assert "deriving" not in capsys.readouterr().err


def test_truncated_cached_library_is_rebuilt(fresh, copy, tmp_path, monkeypatch, seed_cache):
    """A truncated lev_*.so (e.g. a full disk) used to give "Bus error" on every later run: it is
    found by its size and sha256 before any dlopen, and rebuilt once."""
    from levitron.runtime.model.cbuild import is_intact
    cache = seed_cache(tmp_path / "cache")          # the runtime/csrc objects, model.c compiles here
    monkeypatch.setenv("LEVITRON_CACHE", str(cache))
    csrc = ROOT / "runtime" / "csrc"
    lib = compile_shared([copy / "model.c"] + sorted(csrc.glob("*.c")), include_dirs=(copy, csrc))
    data = lib.read_bytes()                        # built, never loaded by this process
    lib.write_bytes(data[: len(data) // 3])
    assert not is_intact(lib)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    script = ("from levitron.scene.load import load_scene; from levitron.runtime.model.load import Model; "
              f"print(Model(load_scene({SCENE!r}), {str(copy)!r}).onaxis(0.1)[0])")
    for attempt in range(2):
        res = subprocess.run([PY, "-c", script], env=env, capture_output=True, text=True,
                             check=False, cwd=tmp_path)
        assert res.returncode == 0, res.stderr
        assert ("damaged" in res.stderr) == (attempt == 0), res.stderr
        assert float(res.stdout) != 0.0
    assert is_intact(lib)
    assert sorted(p.name for p in cache.iterdir()) == [lib.name, lib.name + ".sha256", "obj"]
    objects = sorted((cache / "obj").glob("*.o"))      # one per source, each stamped, nothing else
    assert len(objects) == 1 + len(list(csrc.glob("*.c"))) and all(map(is_intact, objects))
    assert sorted(p.name for p in (cache / "obj").iterdir()) == sorted(
        n for o in objects for n in (o.name, o.name + ".sha256"))


def _cli(args, cwd, cache, root=ROOT, drop_write=False):
    env = dict(os.environ, LEVITRON_CACHE=str(cache), PYTHONPATH=str(root))
    cmd = [PY, "-m", "levitron.runtime.cli.main", *args]
    if drop_write and os.geteuid() == 0:
        setpriv = shutil.which("setpriv")
        if setpriv is None:
            pytest.skip("running as root without setpriv: cannot make a folder read-only")
        cmd = [setpriv, "--bounding-set", "-dac_override,-dac_read_search", "--", *cmd]
    return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, check=False)


def _one_line_error(res, *words):
    assert res.returncode == 2, (res.stdout, res.stderr)
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in res.stderr, res.stderr
    for w in words:
        assert w in lines[0], lines[0]


def _out_of_tree_scene(folder: Path, name: str) -> Path:
    """A copy of scenes/reduced_only.toml under another name and with another field order: a model
    is found by its physics, not its name (runtime/model/locate.py), so a renamed copy alone would
    use generated/reduced_only; the order sends it to the cache."""
    folder.mkdir(parents=True, exist_ok=True)
    text = (ROOT / "scenes" / f"{SCENE}.toml").read_text()
    assert f'\nname = "{SCENE}"\n' in text and text.count("\norder = 2") == 1
    path = folder / f"{name}.toml"
    path.write_text(text.replace(f'\nname = "{SCENE}"\n', f'\nname = "{name}"\n').replace("\norder = 2", "\norder = 4"))
    return path


def test_read_only_cache_is_one_line(tmp_path):
    _out_of_tree_scene(tmp_path, "ro_probe")
    cache = tmp_path / "ro-cache"
    cache.mkdir()
    cache.chmod(0o555)
    try:
        res = _cli(["info", "ro_probe.toml"], tmp_path, cache, drop_write=True)
    finally:
        cache.chmod(0o755)
    _one_line_error(res, str(cache), "LEVITRON_CACHE", "writable")
    assert list(cache.iterdir()) == []


@pytest.mark.parametrize("where", ["file", "under-a-file"])
def test_cache_path_that_is_a_file_is_one_line(tmp_path, where):
    _out_of_tree_scene(tmp_path, "file_probe")
    blocker = tmp_path / "not-a-folder"
    blocker.write_text("x")
    cache = blocker if where == "file" else blocker / "cache"
    res = _cli(["info", "file_probe.toml"], tmp_path, cache)
    _one_line_error(res, "LEVITRON_CACHE", "writable")


def test_relative_scene_path_works_from_any_folder(tmp_path):
    _out_of_tree_scene(tmp_path / "scenes here", "relpath_probe")
    cache = tmp_path / "cache"
    res = _cli(["derive", "scenes here/relpath_probe.toml", "--json"], tmp_path, cache)
    assert res.returncode == 0, res.stderr
    (entry,) = json.loads(res.stdout)["scenes"]
    assert Path(entry["folder"]).parent == cache / "derived" and not entry["skipped"]
    res = _cli(["info", "scenes here/relpath_probe.toml", "--json"], tmp_path, cache)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["generated"] == entry["folder"]
    assert "deriving" not in res.stderr


# ------------------------------------------------------------------ derive never overwrites generated/

def _snapshot(folder: Path) -> dict:
    return {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in sorted(folder.iterdir())}


@pytest.fixture
def repo_copy(tmp_path):
    """The code, scenes and generated/reduced_only in a temporary repository: a regression here
    can only ever damage the copy."""
    repo = tmp_path / "repo"
    for name in ("levitron", "scene", "derive", "runtime", "scenes"):
        # symlinks=True: levitron/ holds relative links to the top-level folders (docs/INTERFACES.md
        # "Layout"), which the copy keeps as links, not as second copies of the code
        shutil.copytree(ROOT / name, repo / name, ignore=shutil.ignore_patterns("__pycache__"), symlinks=True)
    shutil.copy2(ROOT / "pyproject.toml", repo)
    shutil.copytree(ROOT / "generated" / SCENE, repo / "generated" / SCENE)
    return repo


def test_derive_with_set_or_foreign_scene_leaves_generated_alone(repo_copy, tmp_path):
    gen = repo_copy / "generated" / SCENE
    before = _snapshot(gen)
    cache = tmp_path / "cache"
    foreign = _out_of_tree_scene(tmp_path / "elsewhere", SCENE)      # same name as scenes/'s
    runs = [["derive", SCENE, "--set", "top.mass=0.03", "--json"],
            ["derive", SCENE, "--set", 'model.coordinates="euler-zxz"', "--json"],
            ["derive", str(foreign), "--json"]]
    folders = []
    for args in runs:
        res = _cli(args, tmp_path, cache, root=repo_copy)
        assert res.returncode == 0, (args, res.stderr)
        (entry,) = json.loads(res.stdout)["scenes"]
        folders.append(Path(entry["folder"]))
        assert _snapshot(gen) == before, args
    # a number is a runtime parameter: generated/ serves it if current, else the cache does
    assert folders[0] in (gen, cache / "derived" / folders[0].name)
    assert all(f.parent == cache / "derived" for f in folders[1:])
    # python -m levitron.derive without --out (make derive) refuses what is not a scene of scenes/
    env = dict(os.environ, LEVITRON_CACHE=str(cache), PYTHONPATH=str(repo_copy))
    for args in ([SCENE, "--set", "top.mass=0.03"], [str(foreign)]):
        res = subprocess.run([PY, "-m", "levitron.derive", *args], cwd=repo_copy, env=env,
                             capture_output=True, text=True, check=False)
        assert res.returncode == 2, res.stderr
        assert len(res.stderr.strip().splitlines()) == 1 and "--out" in res.stderr, res.stderr
    assert _snapshot(gen) == before
    assert sorted(p.name for p in (repo_copy / "generated").iterdir()) == [SCENE]
