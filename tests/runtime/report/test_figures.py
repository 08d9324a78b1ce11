"""`levitron figures`: the thesis's chapter 3 figures. 3.4-3.8 are drawn per scene with ranges from
the scene; 3.2-3.3 (the solver comparison on a circle, thesis 3.1.3) do not depend on the scene and
are written once per folder; the count printed is the count of files written."""
from __future__ import annotations

import json
import os

import numpy as np
import pytest

from levitron.runtime.cli import main as cli


def _run(capsys, *argv) -> tuple[int, dict]:
    code = cli.main(["figures", *argv, "--json"])
    return code, json.loads(capsys.readouterr().out)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("figures")


def _mtimes(folder):
    return {p.name: p.stat().st_mtime_ns for p in folder.iterdir()}


def test_every_figure_of_chapter_3_and_the_count_is_the_count_written(folder, capsys):
    code, r = _run(capsys, "ring_magnet", "--out", str(folder), "--quick")
    assert code == 0
    names = sorted(p.name for p in folder.iterdir())
    assert sorted(os.path.basename(f) for f in r["files"]) == names       # every file written, listed
    for n in ("3_4_phase_portrait", "3_5_equilibrium", "3_6_forces", "3_7_critical_spins",
              "3_8_stability_map"):
        assert f"ring_magnet_fig{n}.png" in names
    assert {"solver_compare_fig3_2.png", "solver_compare_fig3_3.png", "solver_compare.json"} <= set(names)
    assert not any(n.startswith("ring_magnet_solver") for n in names)


def test_scene_independent_figures_are_not_rewritten_for_another_scene(folder, capsys):
    before = _mtimes(folder)
    code, r = _run(capsys, "thesis", "--out", str(folder), "--quick")
    assert code == 0 and r["solver_files_kept"] is True
    after = _mtimes(folder)
    for name in ("solver_compare_fig3_2.png", "solver_compare_fig3_3.png", "solver_compare.json"):
        assert after[name] == before[name]
    assert len(r["files"]) == 5 and all("thesis_fig3_" in f for f in r["files"])
    assert cli.main(["figures", "thesis", "--out", str(folder), "--quick"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("figures of thesis: 5 files written")
    assert "do not depend on the scene: kept" in out


def test_figure_3_6_shows_the_crossings_of_a_new_scene(ring_magnet_model):
    """The range of fig. 3.6 starts below the lowest equilibrium (ring_magnet's 6.09 cm lies below the
    plate scale where the range used to begin)."""
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.report.figures import _range_36
    lo, hi = _range_36(ring_magnet_model, eqm.scale_of(ring_magnet_model))
    zs = [e.z for e in eqm.equilibria_of(ring_magnet_model).equilibria]
    assert len(zs) == 2 and lo < min(zs) and max(zs) < hi


def test_figure_3_4_orbits_keep_the_reduced_energy(ring_magnet_model, tmp_path, monkeypatch):
    """Every orbit of the phase portrait is closed around z_s and stays on its energy (thesis
    3.2.12): the curves are level sets of the reduced Hamiltonian, integrated, not sketched."""
    import levitron.runtime.integrate
    from levitron.runtime.integrate.run import integrate
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.report.figures import figure_3_4
    runs = []

    def spy(*a, **k):
        runs.append(integrate(*a, **k))
        return runs[-1]
    monkeypatch.setattr(levitron.runtime.integrate, "integrate", spy, raising=False)
    figure_3_4(ring_magnet_model, tmp_path / "p.png")
    assert (tmp_path / "p.png").stat().st_size > 10_000 and len(runs) == 7
    part = ring_magnet_model.part("reduced")
    z_s = eqm.equilibria_of(ring_magnet_model).stable[0].z
    for r in runs:
        E = np.array([part.energy(x) for x in r.X])
        assert np.ptp(E) <= 1e-8 * abs(E[0]) + 1e-12
        assert r.X[:, 0].min() < z_s < r.X[:, 0].max()
        assert r.X[:, 2].min() < 0 < r.X[:, 2].max()          # both halves: the orbit closes


@pytest.fixture(scope="module")
def ring_magnet_model():
    from levitron.scene.load import load_scene
    from levitron.runtime.model.load import load_model
    return load_model(load_scene("ring_magnet"))


def test_equilibrium_plot_zooms_where_the_crossings_sit_close(ring_magnet_model, tmp_path, monkeypatch):
    """ring_magnet's crossings and band (6.09-7.25 cm) fill a tenth of the 0-12 cm range: a zoom row
    shows them; the thesis plate's (7.62-15.74 cm of 0-20 cm) needs none."""
    import matplotlib.figure

    from levitron.scene.load import load_scene
    from levitron.runtime.model.load import load_model
    from levitron.runtime.report.figures import figure_3_5
    seen = []
    save = matplotlib.figure.Figure.savefig

    def recording(fig, *a, **k):
        seen.append([ax.get_xlabel() for ax in fig.axes])
        return save(fig, *a, **k)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", recording)
    figure_3_5(ring_magnet_model, tmp_path / "ring.png")
    figure_3_5(load_model(load_scene("thesis")), tmp_path / "thesis.png")
    ring, thesis = seen
    assert "zoom: z (cm)" in ring
    assert not any(label.startswith("zoom") for label in thesis)


def test_map_spins_resolve_a_narrow_interval():
    """The sketch maps (report, fig. 3.8) run 0.5 lo to 1.25 hi; an interval narrower than three of
    those steps (a dimensionless ring's 4.09-4.093) gets a grid around it instead, with points inside."""
    from levitron.runtime.scan.physics import spins_around
    wide = spins_around((459.6, 2740.0), 8)
    assert wide[0] == pytest.approx(229.8) and wide[-1] == pytest.approx(3425.0)
    narrow = spins_around((4.09, 4.093), 8)
    inside = narrow[(narrow >= 4.09) & (narrow <= 4.093)]
    assert len(inside) >= 2 and narrow[0] < 4.09 and narrow[-1] > 4.093


def test_a_figure_the_scene_cannot_have_is_named_not_drawn(tmp_path, capsys):
    """reduced_only has no full model: fig. 3.8 (a map of full runs) is not drawn and says why;
    the others are, and the count is the files in the folder."""
    code, r = _run(capsys, "reduced_only", "--out", str(tmp_path), "--quick")
    assert code == 0
    assert set(r["not_drawn"]) == {"3.8"} and "full model" in r["not_drawn"]["3.8"]
    assert len(r["files"]) == len(list(tmp_path.iterdir())) == 4 + 3


def test_figure_3_4_draws_a_separatrix_only_through_an_unstable_equilibrium(ring_magnet_model, tmp_path,
                                                                            legend_texts):
    """Issue 28: the dashed separatrix is the energy of the unstable equilibrium below z_s; the solid
    cylinder magnet (ring_magnet with r_in = 0: one root, vertically stable) has none, and gets none."""
    from levitron.runtime.model.load import load_model
    from levitron.runtime.model.scenes import load_scene as load_with
    from levitron.runtime.physics.equilibrium import finder as eqm
    from levitron.runtime.report import figures
    figures.figure_3_4(ring_magnet_model, tmp_path / "with.png")
    assert any("separatrix" in t for t in legend_texts)
    legend_texts.clear()
    solid = load_model(load_with("ring_magnet", ["plate.r_in=0"]))
    assert [e.vertically_stable for e in eqm.equilibria_of(solid).equilibria] == [True]
    figures.figure_3_4(solid, tmp_path / "without.png")
    assert legend_texts and not any("separatrix" in t or "unstable" in t for t in legend_texts), legend_texts
    assert any("U(z_s / 2)" in t for t in legend_texts)
