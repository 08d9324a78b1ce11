"""docs/tutorial.ipynb, the notebook a student follows: committed without outputs, it runs from top
to bottom in a fresh kernel (nbclient; well under a minute on a warm cache) with the answers it
promises (equilibria, stability, a launch shown as an animation, launch odds, a trim, a restyled
Figure), and the executed notebook renders to HTML (nbconvert) that headless Chromium draws. The
docs site shows the notebook as committed (mkdocs.yml: not executed at build); this test runs it."""
from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

from tests.helpers.screenshot import CHROMIUM, colours_and_ink, screenshot

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOK = ROOT / "docs" / "tutorial.ipynb"
BUDGET = 150.0      # s: the notebook is meant to take well under a minute; this catches a runaway cell


def test_the_committed_notebook_has_no_outputs():
    """Outputs are stripped in git (a diff of the notebook is a diff of its cells)."""
    nb = json.loads(NOTEBOOK.read_text())
    assert nb["nbformat"] == 4
    code = [c for c in nb["cells"] if c["cell_type"] == "code"]
    assert len(code) >= 8
    for cell in code:
        assert cell["outputs"] == [] and cell["execution_count"] is None, \
            f"a cell of docs/tutorial.ipynb keeps its outputs: {''.join(cell['source'])[:60]!r}"
    assert "import levitron as lev" in "".join(code[0]["source"])


@pytest.fixture(scope="module")
def executed(tmp_path_factory):
    """(the notebook executed in a fresh kernel in an empty folder, seconds it took)."""
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    nb = nbformat.read(NOTEBOOK, as_version=4)
    folder = tmp_path_factory.mktemp("notebook")
    start = time.perf_counter()
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(folder)}}).execute()
    return nb, time.perf_counter() - start


def _outputs(cell) -> tuple[str, set[str]]:
    """(the cell's printed and plain-text output, the mime types of its rich outputs)"""
    text, kinds = [], set()
    for out in cell.get("outputs", []):
        assert out["output_type"] != "error", f"{out.get('ename')}: {out.get('evalue')}"
        text.append(out.get("text", ""))
        text.append(out.get("data", {}).get("text/plain", ""))
        kinds |= set(out.get("data", {}))
    return "".join(text), kinds


def test_the_notebook_runs_top_to_bottom(executed):
    nb, seconds = executed
    code = [c for c in nb.cells if c.cell_type == "code"]
    seen = {}
    for cell in code:
        text, kinds = _outputs(cell)
        seen["".join(cell.source)] = (text, kinds)
    everything = "".join(text for text, _ in seen.values())
    assert "Study(scene='thesis_stable'" in everything
    assert "10.65 cm (vertically stable)" in everything                           # equilibria
    assert "stable for spin 459.6-2740 rad/s" in everything                       # stability
    assert "launches float at least 5 s" in everything                            # launch odds, n = 40
    assert "set the top to" in everything                                          # the trim's advice
    launch = next(v for k, v in seen.items() if "study.simulate(" in k)
    assert "levitating: yes" in launch[0] and "text/html" in launch[1]             # shown as the animation
    last_text, last_kinds = _outputs(code[-1])
    assert "fig = sim.plot()" in "".join(code[-1].source)
    assert "image/png" in last_kinds and "Figure" in last_text, "the last cell shows no restyled Figure"
    assert seconds < BUDGET, f"the notebook took {seconds:.0f} s"


@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (Debian: apt-get install chromium)")
def test_the_executed_notebook_renders_in_chromium(executed, tmp_path):
    nbconvert = pytest.importorskip("nbconvert", reason="the docs extra: pip install -e '.[docs]'")
    html, _ = nbconvert.HTMLExporter().from_notebook_node(executed[0])
    page = tmp_path / "tutorial.html"
    page.write_text(html)
    shot = screenshot(page, tmp_path / "notebook.png", size=(1280, 2000))
    colours, ink = colours_and_ink(shot)
    assert colours > 1 and ink > 0.01, f"the notebook renders blank ({colours} colours, {ink:.3%} ink)"
