"""The physics answers in a notebook (runtime/ui/answer_view.py): `_repr_html_` is a small table of
their plain view in the scene's display units (cm and Hz in an SI scene, no SI unit in a
dimensionless one), the text escaped; `text_repr` is the one-line repr."""
from __future__ import annotations

import re

import pytest

from levitron.runtime.ui.answer_view import html_table, text_repr
from tests.helpers.dimensionless import SCENE as DIMENSIONLESS

SI_UNIT = re.compile(r"\d ?(m|cm|mm|kg|g|s|ms|Hz|rpm|rad/s|N/m)\b")


def test_the_table_escapes_its_text_and_draws_a_figure_it_closes():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots()
    ax.plot([0, 1], [1, 0])
    page = html_table("A <b>", ["key: 1 < 2", "a line & more"], fig)
    assert "<th style='text-align:left'>key</th><td>1 &lt; 2</td>" in page and "a line &amp; more" in page
    assert "A &lt;b&gt;" in page and "<svg" in page and not plt.fignum_exists(fig.number)
    assert text_repr("A", ["x: 1", "", "y", "success=True"]) == "A(x: 1; y; success=True)"


@pytest.fixture(scope="module")
def answers(tmp_path_factory):
    import levitron as lev
    path = tmp_path_factory.mktemp("dimless") / "unit_annulus.toml"
    path.write_text(DIMENSIONLESS)
    out = {}
    for kind, study in (("si", lev.load("thesis_stable")), ("dimensionless", lev.load(str(path)))):
        eq = study.equilibria()
        st = study.stability()
        spin = (st.spin_interval[0] * st.spin_interval[1]) ** 0.5
        out[kind] = {"Equilibria": eq, "Equilibrium": eq.equilibria[0], "Stability": st,
                     "Simulation": study.simulate(spin, t_end=0.05 if kind == "si" else 1.0, n_out=20),
                     "Simulations": study.simulate_many([spin], t_end=0.05 if kind == "si" else 1.0)}
    return out


@pytest.mark.parametrize("name", ["Equilibria", "Equilibrium", "Stability", "Simulation", "Simulations"])
def test_each_answer_is_a_table_in_the_scenes_units(answers, name):
    si, dl = answers["si"][name]._repr_html_(), answers["dimensionless"][name]._repr_html_()
    for page in (si, dl):
        assert page.startswith("<div><table><caption") and f"<b>{name}</b>" in page
    table = si.split("</table>")[0]
    assert re.search(r"\d cm\b", table) or name == "Simulations", table
    if name == "Stability":
        assert " Hz" in table and "rpm" in table
    dl_table = re.sub(r"<[^>]+>", " ", dl.split("</table>")[0])
    dl_table = re.sub(r"\S+ (us|ms|s) of wall time", "", dl_table)     # the computer's seconds, in every scene
    assert not SI_UNIT.search(dl_table), dl_table
    assert repr(answers["si"][name]).startswith(name + "(")
