"""`levitron report`: one self-contained HTML page (figures embedded, nothing external) that shows
the numbers; with Chromium installed, a screenshot of it (slow)."""
from __future__ import annotations

import base64
import html
import io
import json
import re
import shlex
import shutil
import subprocess
from contextlib import redirect_stdout
from html.parser import HTMLParser
from pathlib import Path

import pytest

from levitron.runtime.cli import main as cli
from levitron.runtime.ui.human import Units


class Page(HTMLParser):
    """Collects images, references to anything outside the page, and the text."""

    def __init__(self):
        super().__init__()
        self.images, self.external, self.text = [], [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if tag == "img":
            self.images.append(a.get("src", ""))
        for key in ("src", "href", "data", "action"):
            v = a.get(key)
            if v is not None and not v.startswith(("data:", "#")):
                self.external.append(f"{tag} {key}={v}")
        if tag in ("link", "iframe", "object", "embed") or (tag == "script" and "src" in a):
            self.external.append(tag)      # an inline script (the animation's) refers to nothing

    def handle_data(self, data):
        self.text.append(data)


OWN_SCENE = Path(__file__).resolve().parents[3] / "examples" / "scenes" / "small_ring.toml"


def _report(argv: list[str]) -> dict:
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert cli.main([*argv, "--json"]) == 0
    return json.loads(buf.getvalue())


def _text(path: Path) -> str:
    page = re.sub(r"<img[^>]*>|<style>.*?</style>", "", path.read_text(), flags=re.S)
    return html.unescape(re.sub(r"<[^>]+>", "\n", page))


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "thesis_stable.html"
    return out, _report(["report", "thesis_stable", "--out", str(out)])


@pytest.fixture(scope="module")
def thesis_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("thesis") / "thesis.html"
    return out, _report(["report", "thesis", "--out", str(out)])


@pytest.fixture(scope="module")
def varied(tmp_path_factory):
    """A report of a scene with a --set: what the footer must carry to be rebuilt."""
    out = tmp_path_factory.mktemp("varied") / "ring.html"
    return out, _report(["report", "ring_magnet", "--set", "top.mass=0.0180", "--out", str(out)])


def test_page_is_self_contained(report):
    path, facts = report
    page = Page()
    page.feed(path.read_text())
    assert page.external == []
    assert len(page.images) == 3                 # equilibrium, map, launch
    for src in page.images:
        head, _, data = src.partition(",")
        assert head == "data:image/png;base64"
        assert base64.b64decode(data)[:8] == b"\x89PNG\r\n\x1a\n"
    assert facts["bytes"] == len(path.read_bytes())


def test_page_shows_the_numbers(report):
    path, facts = report
    page = Page()
    page.feed(path.read_text())
    text = " ".join(page.text)
    u = Units.of(9.81)
    lo, hi = facts["spin_interval"]
    assert u.rate_span(lo, hi) in text
    assert u.length(facts["z_s"]) in text
    for e in facts["equilibria"]:
        assert u.length(e["z"]) in text
    assert u.length_span(*facts["stable_band"]["z"]) in text
    assert 0 < facts["map"]["fraction_levitating"] < 1
    assert facts["launch"]["levitating"] is True


def test_bad_out_is_one_line(tmp_path, capsys):
    assert cli.main(["report", "thesis_stable", "--out", str(tmp_path / "page.txt")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and ".html" in err




NUMBERS = ("equilibria", "stable_band", "spin_interval", "z_s", "map", "launch", "hints")


def test_footer_command_rebuilds_the_same_numbers(varied, tmp_path):
    """The command at the foot of the page, run again, gives the same numbers (the --set included)."""
    path, facts = varied
    command = facts["provenance"]["command"]
    assert "--set top.mass=0.0180" in command and command in _text(path)
    argv = shlex.split(command)[1:]
    argv[argv.index("--out") + 1] = str(tmp_path / "again.html")
    again = _report(argv)
    for key in NUMBERS:
        assert again[key] == facts[key], key
    assert again["provenance"]["scene_hash"] == facts["provenance"]["scene_hash"]


def test_page_shows_scene_keys_as_written_with_units(varied):
    path, facts = varied
    text = _text(path)
    for row in ("plate.r_out", "6 cm", "plate.remanence", "0.39 T", "top.mass (--set)",
                "18 g", "the top's magnetic moment mu", "-1.2 A m^2", "levitron 0.", "scene hash "):
        assert row in text, row
    for internal in ("plate_magnetization", "plate_rho", "plate_r_out", "plate_w"):
        assert internal not in text, internal
    assert facts["provenance"]["scene_hash"][:12] in text
    assert re.search(r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC", text)


def test_a_top_that_cannot_levitate_leads_with_the_hint(thesis_report):
    """thesis: the 28.4 g top hovers above the band; the page's answer says which tops would hover
    in it, as `levitron equilibrium` does, before any N(t)."""
    out, facts = thesis_report
    page = Page()
    page.feed(out.read_text())
    answer = next(t for t in page.text if t.startswith("No: "))
    assert "a top of mass in 50.35-52.49 g would hover inside it" in answer
    assert "N(t)" not in answer and facts["spin_interval"] is None


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None,
                    reason="chromium not installed (Debian: apt-get install chromium)")
@pytest.mark.parametrize("scene", ["thesis", "thesis_stable", str(OWN_SCENE)],
                         ids=["thesis", "thesis_stable", "small_ring"])
def test_reports_render_in_chromium(scene, tmp_path, request):
    """The report of thesis, thesis_stable and a scene of our own (examples/scenes/small_ring.toml)
    renders in headless Chromium: the screenshot is a page with its figures, not blank. (The pages
    of thesis and thesis_stable are the ones the other tests here read, made by the same command.)"""
    shared = {"thesis": "thesis_report", "thesis_stable": "report"}.get(scene)
    if shared is not None:
        page = request.getfixturevalue(shared)[0]
    else:
        page = tmp_path / "report.html"
        _report(["report", scene, "--out", str(page)])
    shot = tmp_path / "report.png"
    subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                    "--window-size=1200,3000", f"--screenshot={shot}", page.as_uri()],
                   check=True, capture_output=True, timeout=120)
    data = shot.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 50_000
    import matplotlib.image
    img = matplotlib.image.imread(str(shot))
    assert img.shape[:2] == (3000, 1200)
    ink = (img[..., :3].mean(axis=2) < 0.9).mean()          # not blank: text and figures drawn
    assert ink > 0.02


def test_a_top_too_heavy_to_hover_is_told_which_tops_would(tmp_path, capsys):
    """A 60 g top over the thesis plate has no equilibrium at all: the page's answer and
    `levitron equilibrium` name the masses that would hover in the band, in grams."""
    out = tmp_path / "heavy.html"
    _report(["report", "thesis", "--set", "top.mass=0.06", "--out", str(out)])
    page = Page()
    page.feed(out.read_text())
    answer = next(t for t in page.text if t.startswith("No: "))
    assert "the top of mass 60 g is too heavy for the plate, which holds at most 52.49 g" in answer
    assert "a top of mass in 50.35-52.49 g would hover inside the stable band 9.948-11.02 cm" in answer
    assert cli.main(["equilibrium", "thesis", "--set", "top.mass=0.06"]) == 0
    assert "a top of mass in 50.35-52.49 g would hover inside the stable band" in capsys.readouterr().out


def test_a_scene_without_the_full_model_gets_its_page(tmp_path, capsys):
    """A scene that derives only the vertical motion (model.needs = ["reduced"]) with a stable spin
    interval gets its page, the map and the launch (they run the 12-D model) left out with the
    reason; before, the command stopped at the map with an error and wrote no page."""
    out = tmp_path / "r.html"
    argv = ["report", "reduced_only", "--set", "top.mass=0.0515", "--out", str(out), "--json"]
    assert cli.main(argv) == 0, capsys.readouterr().err
    facts = json.loads(capsys.readouterr().out)
    assert facts["spin_interval"] and facts["map"] is None and facts["launch"] is None
    assert 'add "full" to model.needs' in facts["not_drawn"]
    page = out.read_text()
    assert "Spin interval" in page and 'add "full" to model.needs' in html.unescape(page)
