"""Plots that leave a notebook as it was (runtime/ui/plotting.py): every figure is a Figure made
without pyplot, in the house style for its own drawing only; `plot()` returns it and writes a file
only when given a path; `plot(ax=...)` draws into the caller's Axes."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest
from matplotlib.figure import Figure

import levitron as lev
from levitron.runtime.ui.plotting import STYLE, save_figure

SCENE = "thesis"
RUN = dict(spin=1100.0, tilt=0.01, t_end=0.05, n_out=60)
MAP = ([900.0, 1100.0], "tilt", [0.01])


@pytest.fixture(scope="module")
def study():
    return lev.load(SCENE)


@pytest.fixture(scope="module")
def sim(study):
    return study.simulate(**RUN)


@pytest.fixture(scope="module")
def scan_map(study):
    return study.scan(*MAP, t_end=0.05)


NOTEBOOK = f"""
import json, os, sys
import matplotlib
matplotlib.use("svg")                  # the user's own backend: not Agg
import matplotlib.pyplot as plt
import levitron as lev
before = dict(matplotlib.rcParams)
study = lev.load({SCENE!r})
sim = study.simulate(**{RUN!r})
fig = sim.plot()
ax = plt.figure().subplots()           # the user's own pyplot figure
got = study.scan(*{MAP!r}, t_end=0.05).plot(ax=ax)
after = dict(matplotlib.rcParams)
print(json.dumps({{
    "backend": matplotlib.get_backend(),
    "changed": sorted(k for k in before if before[k] != after[k]),
    "is_figure": isinstance(fig, matplotlib.figure.Figure),
    "panels": len(fig.axes),
    "into_ax": got is ax and len(ax.collections) > 0,
    "pyplot_figures": plt.get_fignums(),
    "files": sorted(os.listdir(".")),
}}))
"""


def test_a_plot_in_a_notebook_leaves_its_backend_and_style(tmp_path):
    """In a process whose backend is svg (not Agg), sim.plot() and a Scan's plot(ax=...) leave the
    backend and every rcParam as they were, return a Figure (the Axes when given one), register no
    figure with pyplot beside the user's own, and write no file."""
    done = subprocess.run([sys.executable, "-c", NOTEBOOK], cwd=tmp_path, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    got = json.loads(done.stdout.strip().splitlines()[-1])
    assert got["backend"] == "svg"
    assert got["changed"] == []
    assert got["is_figure"] and got["panels"] == 3
    assert got["into_ax"]
    assert got["pyplot_figures"] == [1]          # the user's figure only
    assert got["files"] == []


def test_plot_without_a_path_writes_nothing_and_returns_the_figure(sim, scan_map, tmp_path, monkeypatch):
    import matplotlib
    monkeypatch.chdir(tmp_path)
    before = dict(matplotlib.rcParams)
    for fig in (sim.plot(), scan_map.plot()):
        assert isinstance(fig, Figure)
        assert fig.axes and fig.axes[0].get_lines()
    assert list(tmp_path.iterdir()) == []
    assert dict(matplotlib.rcParams) == before


def test_the_house_style_is_the_figures_own(sim, tmp_path):
    """The style applies at creation and at save (lines, grid, spines, size), whatever the caller's."""
    import matplotlib
    with matplotlib.rc_context({"lines.linewidth": 3.0, "axes.grid": False}):
        fig = sim.plot(tmp_path / "run.svg")
    assert (tmp_path / "run.svg").read_text().lstrip().startswith("<?xml")
    ax = fig.axes[0]
    assert ax.get_lines()[0].get_linewidth() == STYLE["lines.linewidth"]
    assert ax.xaxis._major_tick_kw.get("gridOn") is True
    assert not ax.spines["top"].get_visible()
    assert tuple(fig.get_size_inches()) == (7, 7)


def test_plot_draws_into_the_given_axes(sim, scan_map, tmp_path):
    fig = Figure()
    ax = fig.subplots()
    assert scan_map.plot(ax=ax) is ax
    assert ax.collections and ax.get_title().startswith(f"{SCENE}: levitating vs spin and tilt")
    panels = list(Figure().subplots(3, 1))
    assert sim.plot(ax=panels) == panels
    assert all(a.get_lines() for a in panels)
    sub = Figure().subfigures(1, 2)[1]
    assert sim.plot(fig=sub) is sub and len(sub.axes) == 3
    assert list(tmp_path.iterdir()) == []
    save_figure(sub, tmp_path / "sub.png")            # a SubFigure is saved as its whole figure
    assert (tmp_path / "sub.png").stat().st_size > 0


def test_a_multi_panel_plot_refuses_one_axes(sim):
    with pytest.raises(lev.UserError) as e:
        sim.plot(ax=[Figure().subplots()])
    text = str(e.value)
    assert "\n" not in text and "3 panels" in text and "fig=" in text


def test_save_figure_needs_no_pyplot(tmp_path):
    """save_figure writes a Figure made without pyplot; nothing to close, pyplot never imported."""
    code = ("import sys\nfrom levitron.runtime.ui.plotting import figure, save_figure\n"
            "fig = figure()\nfig.subplots().plot([0, 1])\nsave_figure(fig, 'a/f.png')\n"
            "print('matplotlib.pyplot' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == "False"
    assert [p.name for p in (tmp_path / "a").iterdir()] == ["f.png"]
