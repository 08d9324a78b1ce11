"""generated/ is what `make derive` writes, byte for byte, reproducibly; the C is warning-free."""
import functools
import os
import subprocess
import sys

import pytest

from levitron.derive.build import render
from levitron.scene.paths import GENERATED, ROOT, SCENES_DIR
from levitron.scene.load import load_scene
from levitron.runtime.model.cbuild import compiler

SCENES = sorted(p.stem for p in SCENES_DIR.glob("*.toml"))


@functools.cache
def rendered(name: str) -> dict[str, bytes]:
    """render() of a scene of scenes/ under this process's hash seed, once per test run: under
    pytest-xdist with PYTHONHASHSEED set (`make test`: 0), the worker that renders a scene first
    leaves the files in the run's shared temporary folder and the other workers, under the same
    seed and code, read them there (square takes 7 s); otherwise once per process."""
    shared = _shared_folder()
    if shared is None:
        return render(load_scene(name))
    import fcntl
    import pickle
    done = shared / f"{name}-seed{os.environ['PYTHONHASHSEED']}.pickle"
    with open(shared / f"{done.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)          # one worker renders, the others wait for it
        if not done.exists():
            files = render(load_scene(name))
            tmp = done.with_name(f".{done.name}.{os.getpid()}")
            tmp.write_bytes(pickle.dumps(files))
            os.replace(tmp, done)
            return files
    return pickle.loads(done.read_bytes())


_RUN: dict = {}


def _shared_folder():
    """The folder of this test run that every xdist worker sees (the parent of the workers' own
    temporary folders), or None when not under xdist or when the hash seed is random."""
    if not os.environ.get("PYTEST_XDIST_WORKER") or os.environ.get("PYTHONHASHSEED", "random") == "random":
        return None
    return _RUN.get("shared")


@pytest.fixture(scope="module", autouse=True)
def _run_folder(tmp_path_factory):
    folder = tmp_path_factory.getbasetemp().parent / "rendered"
    folder.mkdir(exist_ok=True)
    _RUN["shared"] = folder
    yield
    _RUN.pop("shared", None)


@pytest.mark.parametrize("name", SCENES)
def test_committed_generated_is_what_derive_writes(name):
    """Golden files: compare in memory; on failure, run `make golden` (python -m levitron.derive --force)."""
    files = rendered(name)
    folder = GENERATED / name
    assert folder.is_dir(), f"generated/{name} is missing: run `make derive`"
    on_disk = sorted(p.name for p in folder.iterdir())
    assert on_disk == sorted(files), f"generated/{name} has other files: run `make golden`"
    for fname, data in files.items():
        current = (folder / fname).read_bytes()
        if current != data:
            import difflib
            diff = "".join(list(difflib.unified_diff(
                current.decode(errors="replace").splitlines(True),
                data.decode(errors="replace").splitlines(True), f"committed/{fname}", f"derived/{fname}"))[:40])
            pytest.fail(f"generated/{name}/{fname} differs from what derive writes; update with "
                        f"`make golden` and review the diff:\n{diff}")


def test_derive_is_byte_reproducible_across_hash_seeds(tmp_path):
    """`python -m levitron.derive` under another hash seed writes, byte for byte, what render() gives
    under this process's seed (whose files the golden test above compares with generated/)."""
    ours = os.environ.get("PYTHONHASHSEED")      # `make test`: 0; unset: a random one
    seed = "12345" if ours != "12345" else "54321"
    env = dict(os.environ, PYTHONHASHSEED=seed)
    res = subprocess.run([sys.executable, "-m", "levitron.derive", "thesis", "square", "--force", "--out",
                          str(tmp_path)], cwd=ROOT, env=env, capture_output=True, text=True, check=False)
    assert res.returncode == 0, res.stderr
    for scene in ("thesis", "square"):     # an axisymmetric plate and the exact 3-D field
        files = rendered(scene)
        assert sorted(p.name for p in (tmp_path / scene).iterdir()) == sorted(files), scene
        for fname, data in files.items():
            assert (tmp_path / scene / fname).read_bytes() == data, f"{scene}/{fname}: seed {seed} vs {ours}"
    # a second run with nothing changed is skipped by the input hash and leaves the bytes alone
    before = {p.name: p.read_bytes() for p in (tmp_path / "thesis").iterdir()}
    res = subprocess.run([sys.executable, "-m", "levitron.derive", "thesis", "--out", str(tmp_path)],
                         cwd=ROOT, capture_output=True, text=True, check=False)
    assert res.returncode == 0 and "unchanged" in res.stderr
    assert before == {p.name: p.read_bytes() for p in (tmp_path / "thesis").iterdir()}


@pytest.mark.parametrize("name", SCENES)
def test_generated_c_compiles_warning_free(name, tmp_path):
    """The generated model.c with the runtime's headers it includes (runtime/csrc: lev_sincos.h,
    lev_taylor.h), as runtime/model/load.py builds it, under -Wall -Wextra -pedantic."""
    from levitron.runtime.model.load import CSRC
    folder = GENERATED / name
    res = subprocess.run([compiler(), "-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic", "-c",
                          str(folder / "model.c"), "-I", str(folder), "-I", str(CSRC), "-o", str(tmp_path / "m.o")],
                         capture_output=True, text=True, check=False)
    assert res.returncode == 0, res.stderr


def test_generated_files_say_what_made_them():
    for folder in GENERATED.iterdir():
        if folder.name.startswith("."):
            continue
        for fname in ("model.c", "model.h"):
            head = (folder / fname).read_text().splitlines()[0]
            assert "DO NOT EDIT" in head and "levitron derive" in head and "Input hash" in head
            assert "Operation counts" in head


def test_unused_part_is_not_emitted(derived_model):
    """Model only what a scene needs: a reduced-only scene has no 12-D function at all."""
    model = derived_model("thesis", 'model.needs=["reduced"]')
    assert set(model.manifest.parts) == {"reduced"}
    assert not any(n.startswith("full_") for n in model.manifest.functions)
    assert "full_" not in (model.folder / "model.c").read_text()
    with pytest.raises(Exception, match="add \"full\" to model.needs"):
        model.part("full")


def test_runtime_never_writes_into_generated(tmp_path, monkeypatch, seed_cache):
    """A stale generated/<scene> is left alone: the runtime derives into the cache and says so."""
    import levitron.runtime.model.load as rm
    import levitron.runtime.model.locate as where
    fake = tmp_path / "generated"
    (fake / "thesis").mkdir(parents=True)
    stale = '{"input_hash": "stale"}'
    (fake / "thesis" / "manifest.json").write_text(stale)
    monkeypatch.setattr(where, "GENERATED", fake)
    monkeypatch.setenv("LEVITRON_CACHE", str(seed_cache(tmp_path / "cache")))
    model = rm.load_model(load_scene("thesis"))
    assert model.folder.parent == tmp_path / "cache" / "derived"
    assert (fake / "thesis" / "manifest.json").read_text() == stale
    assert sorted(p.name for p in (fake / "thesis").iterdir()) == ["manifest.json"]
    assert model.part("reduced").rhs([0.1, 0.0, 0.0, 0.0]).shape == (4,)
    assert [p.name for p in (tmp_path / "cache" / "derived").iterdir()] == [model.folder.name]
