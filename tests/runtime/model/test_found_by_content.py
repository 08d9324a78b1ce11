"""A scene's model is found by its content's hash, whatever its name (runtime/model/locate.py,
scene/inputs.py structure): a renamed copy of a shipped scene uses the shipped generated/ model
without deriving; a copy that differs in one structural key derives its own."""
from __future__ import annotations

import shutil
import subprocess
import time
from pathlib import Path

import levitron.runtime.model.locate as where
from levitron.scene.inputs import input_hash, structure
from levitron.scene.load import load_scene
from levitron.scene.paths import GENERATED, SCENES_DIR


def _copy(folder: Path, scene: str, name: str, edit=lambda text: text) -> Path:
    text = (SCENES_DIR / f"{scene}.toml").read_text()
    assert f'name = "{scene}"' in text
    path = folder / f"{name}.toml"
    path.write_text(edit(text.replace(f'name = "{scene}"', f'name = "{name}"\ndescription = "my own base"')))
    return path


def _no_subprocess(monkeypatch):
    def refuse(*a, **k):
        raise AssertionError(f"a derivation subprocess ran: {a[0] if a else k}")
    monkeypatch.setattr(where.subprocess, "Popen", refuse)


def test_the_hash_leaves_out_the_name_and_the_description(tmp_path):
    mine = load_scene(str(_copy(tmp_path, "thesis", "mine")))
    thesis = load_scene("thesis")
    assert mine.name == "mine" and "name" not in structure(mine.data)
    assert input_hash(mine.data) == input_hash(thesis.data)
    changed = load_scene(str(_copy(tmp_path, "thesis", "other", lambda t: t.replace("order = 2", "order = 4"))))
    assert input_hash(changed.data) != input_hash(thesis.data)


def test_a_renamed_shipped_scene_loads_the_shipped_model_without_deriving(tmp_path, monkeypatch, capsys):
    from levitron.runtime.model.load import load_model
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))     # an empty cache: nothing there
    _no_subprocess(monkeypatch)
    scene = load_scene(str(_copy(tmp_path, "thesis", "mine")))
    t0 = time.perf_counter()
    found = where.locate(scene)
    took = time.perf_counter() - t0
    assert found.folder == GENERATED / "thesis" and not found.derived
    assert found.manifest.scene == "thesis" and found.manifest.input_hash == input_hash(scene.data)
    assert took < 1.0, took
    model = load_model(scene)
    assert model.folder == GENERATED / "thesis" and model.scene.name == "mine"
    assert "deriving" not in capsys.readouterr().err
    assert not (tmp_path / "cache" / "derived").exists()


def test_a_renamed_copy_finds_a_model_cached_under_another_name(tmp_path, monkeypatch):
    monkeypatch.setattr(where, "GENERATED", tmp_path / "no-generated")      # the cache's route only
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    _no_subprocess(monkeypatch)
    first = load_scene(str(_copy(tmp_path, "reduced_only", "first")))
    cached = where.cache_folder(first)
    shutil.copytree(GENERATED / "reduced_only", cached)       # as if `first` had been derived there
    second = load_scene(str(_copy(tmp_path, "reduced_only", "second")))
    found = where.locate(second)
    assert found.folder == cached and not found.derived


def test_a_damaged_model_of_another_name_is_passed_over(tmp_path, monkeypatch):
    monkeypatch.setattr(where, "GENERATED", tmp_path / "no-generated")
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    first = load_scene(str(_copy(tmp_path, "reduced_only", "first")))
    cached = where.cache_folder(first)
    shutil.copytree(GENERATED / "reduced_only", cached)
    (cached / "model.c").write_bytes((cached / "model.c").read_bytes() + b"/* edit */\n")
    second = load_scene(str(_copy(tmp_path, "reduced_only", "second")))
    ran = []

    def derive(scene, out, ihash, note=None):       # a derivation, as the subprocess would leave it
        ran.append(out)
        shutil.copytree(GENERATED / "reduced_only", out)
    monkeypatch.setattr(where, "_derive_into", derive)
    found = where.locate(second)
    assert ran == [where.cache_folder(second)] and found.folder == ran[0] and found.derived


def test_a_scene_that_differs_in_one_structural_key_derives_its_own(tmp_path, monkeypatch):
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    calls = []
    popen = subprocess.Popen

    def counting(*a, **k):
        calls.append(a[0])
        return popen(*a, **k)
    monkeypatch.setattr(where.subprocess, "Popen", counting)
    scene = load_scene(str(_copy(tmp_path, "reduced_only", "mine", lambda t: t.replace("order = 2", "order = 4"))))
    found = where.locate(scene)
    assert found.derived and len(calls) == 1
    assert found.folder == where.cache_folder(scene) and found.folder.parent == tmp_path / "cache" / "derived"
    assert found.manifest.scene == "mine" and found.manifest.field_order == 4
