"""Figures 3.2-3.3 (Euler against RK4 on a circle) do not depend on the scene: computed once into
the cache ($LEVITRON_CACHE/figures, keyed by a hash of their inputs), copied into every new folder;
a damaged entry is computed again. (Before: 14 s of CPU in every new output folder.)"""
from __future__ import annotations

import json

import pytest

from levitron.runtime.bench import solver_compare
from levitron.runtime.cli.commands import figures as cmd


@pytest.fixture(scope="module")
def cache(tmp_path_factory, seed_cache):
    folder = seed_cache(tmp_path_factory.mktemp("cache"))
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("LEVITRON_CACHE", str(folder))
        yield folder


def _counted(monkeypatch) -> list:
    calls, real = [], solver_compare.run

    def run(*args, **kwargs):
        calls.append(args)
        return real(*args, **kwargs)
    monkeypatch.setattr(solver_compare, "run", run)
    return calls


def _refuse(*args, **kwargs):
    raise AssertionError("computed again: the cache was not used")


def _files(folder):
    return {name: (folder / name).read_bytes() for name in (*cmd.SOLVER_PNGS, cmd.SOLVER_JSON)}


def test_a_new_folder_gets_the_cached_figures_byte_for_byte(cache, tmp_path, monkeypatch):
    first, second = tmp_path / "first", tmp_path / "second"
    first.mkdir()
    second.mkdir()
    files, cached = cmd.solver_figures(first, quick=True, fresh=True)
    assert not cached and sorted(files) == sorted(str(first / n) for n in _files(first))
    monkeypatch.setattr(solver_compare, "run", _refuse)
    files, cached = cmd.solver_figures(second, quick=True)
    assert cached and sorted(files) == sorted(str(second / n) for n in _files(second))
    a, b = _files(first), _files(second)
    for name in cmd.SOLVER_PNGS:
        assert a[name] == b[name], name
    # the numbers are the same bytes; the list of PNGs names the folder they are in, as a
    # computation into that folder writes it
    ja, jb = json.loads(a[cmd.SOLVER_JSON]), json.loads(b[cmd.SOLVER_JSON])
    assert jb["files"] == [str(second / n) for n in cmd.SOLVER_PNGS]
    assert b[cmd.SOLVER_JSON] == json.dumps({**ja, "files": jb["files"]}, indent=1).encode()
    assert not [p for p in second.iterdir() if p.name.startswith(".")], "a temporary was left"


def test_a_damaged_cache_entry_is_computed_again(cache, tmp_path, monkeypatch):
    cmd.solver_figures(tmp_path, quick=True)          # computed, or copied from the cache
    calls = _counted(monkeypatch)
    entry = cmd._entry(True)
    png = entry / cmd.SOLVER_PNGS[0]
    png.write_bytes(png.read_bytes()[:100])             # a truncated file
    for folder in ("again", "then_cached"):
        (tmp_path / folder).mkdir()
        cmd.solver_figures(tmp_path / folder, quick=True)
        assert len(calls) == 1, f"{folder}: {len(calls)} computations"
    assert (tmp_path / "again" / cmd.SOLVER_PNGS[0]).read_bytes() == png.read_bytes()
    (entry / cmd.SUMS).write_text("{not json")
    (tmp_path / "third").mkdir()
    cmd.solver_figures(tmp_path / "third", quick=True)
    assert len(calls) == 2


def test_the_key_is_the_inputs(cache):
    assert cmd.solver_key(True) != cmd.solver_key(False)
    assert cmd.solver_key(True) == cmd.solver_key(True)
    assert cmd._entry(True).parent == cache / "figures"
