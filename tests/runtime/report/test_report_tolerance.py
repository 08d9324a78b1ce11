"""The report's spin-window figure carries the tilt each spin tolerates (runtime/report/tolerance.py):
the curve is computed once into the cache, keyed by its inputs, a damaged entry computed again;
the figure draws the map above the curve, the resonances marked on both and labelled."""
from __future__ import annotations

import json

import numpy as np
import pytest

from levitron.runtime.model import cbuild
from levitron.runtime.report import tolerance
from levitron.runtime.scan import tilt_tolerance as tt
from levitron.runtime.scan.tilt_tolerance import TiltTolerance

RES = [{"spin": 213.1, "order": 3, "relation": "a = b + c", "explosive": True},
       {"spin": 231.4, "order": 4, "relation": "2 a = b + c", "explosive": False}]


@pytest.fixture(scope="module")
def toy(derived_model):
    return derived_model("levitron_toy")


@pytest.fixture
def counted(monkeypatch, tmp_path):
    """The cache in tmp_path; tilt_tolerance replaced by a stand-in that counts its calls."""
    monkeypatch.setattr(cbuild, "cache_dir", lambda: tmp_path)
    calls = []

    def fake(model, window, z_s, resonances=(), t_end=None, n=tt.N_SPINS):
        calls.append(n)
        spins = np.geomspace(window[0], window[1], n)
        return TiltTolerance(spins, np.full(n, 0.05), float(t_end), list(resonances))
    monkeypatch.setattr(tt, "tilt_tolerance", fake)
    return calls


def test_the_curve_is_computed_once_then_read_from_the_cache(toy, counted):
    c1, cached1 = tolerance.curve(toy, (100.0, 240.0), 0.032, RES, t_end=2.0)
    c2, cached2 = tolerance.curve(toy, (100.0, 240.0), 0.032, RES, t_end=2.0)
    assert (cached1, cached2) == (False, True) and counted == [tolerance.SPINS]
    assert np.array_equal(c1.spins, c2.spins) and np.array_equal(c1.max_tilt, c2.max_tilt)
    assert c2.resonances == RES and c2.t_end == 2.0


def test_other_inputs_are_another_entry_and_a_damaged_one_is_computed_again(toy, counted):
    base = tolerance.entry(toy, (100.0, 240.0), 0.032, 2.0)
    assert base != tolerance.entry(toy, (100.0, 240.0), 0.032, 3.0)             # the run length
    assert base != tolerance.entry(toy, (100.0, 241.0), 0.032, 2.0)             # the window
    assert base != tolerance.entry(toy, (100.0, 240.0), 0.032, 2.0, n=13)       # the grid
    tolerance.curve(toy, (100.0, 240.0), 0.032, RES, t_end=2.0)
    d = json.loads(base.read_text())
    base.write_text(json.dumps({**d, "max_tilt": d["max_tilt"][:-1]}))           # a truncated entry
    _, cached = tolerance.curve(toy, (100.0, 240.0), 0.032, RES, t_end=2.0)
    assert not cached and len(counted) == 2


class _Map:
    """A stand-in for the stability map: its plot draws into the panel given."""

    def plot(self, path=None, title=None, ax=None):
        ax.plot([50.0, 300.0], [0.0, 0.1])
        ax.set_xlim(50.0, 300.0)
        return ax


def test_the_figure_marks_and_labels_the_resonances(toy, tmp_path, monkeypatch):
    from levitron.runtime.ui import plotting
    from levitron.runtime.ui.human import Units
    got = {}
    monkeypatch.setattr(plotting, "save_figure", lambda fig, path: got.setdefault("fig", fig) and path)
    curve = TiltTolerance(np.geomspace(100, 240, 5), np.array([0.01, 0.08, 0.09, 0.02, 0.03]), 2.0, RES)
    tolerance.figure(_Map(), curve, tmp_path / "w.png", Units(si=True))
    top, low = got["fig"].axes[:2]
    labels = [t.get_text() for t in low.texts]
    assert labels == ["3-wave 213.1 rad/s", "4-wave 231.4 rad/s"], labels
    assert low.get_xlim() == top.get_xlim() == (50.0, 300.0)
    marked = {round(line.get_xdata()[0], 1) for line in top.lines if len(set(line.get_xdata())) == 1}
    assert marked == {213.1, 231.4}
