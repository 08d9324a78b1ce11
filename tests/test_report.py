"""`levitron report`: one self-contained HTML page (figures embedded, nothing external) that shows
the numbers; with Chromium installed, a screenshot of it (slow)."""
from __future__ import annotations

import base64
import json
import shutil
import subprocess
from html.parser import HTMLParser

import pytest

from runtime.cli import main as cli
from runtime.ui.human import Units, span


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
        if tag in ("script", "link", "iframe", "object", "embed"):
            self.external.append(tag)

    def handle_data(self, data):
        self.text.append(data)


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    out = tmp_path_factory.mktemp("report") / "thesis_stable.html"
    import io
    from contextlib import redirect_stdout
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert cli.main(["report", "thesis_stable", "--out", str(out), "--json"]) == 0
    return out, json.loads(buf.getvalue())


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
    assert span(*facts["stable_band"]["z"], u.cm) in text
    assert 0 < facts["map"]["fraction_levitating"] < 1
    assert facts["launch"]["levitating"] is True


def test_bad_out_is_one_line(tmp_path, capsys):
    assert cli.main(["report", "thesis_stable", "--out", str(tmp_path / "page.txt")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and ".html" in err


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("chromium") is None,
                    reason="chromium not installed (Debian: apt-get install chromium)")
def test_page_renders_in_chromium(report, tmp_path):
    path, _ = report
    shot = tmp_path / "report.png"
    subprocess.run(["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                    "--window-size=1200,3000", f"--screenshot={shot}", path.as_uri()],
                   check=True, capture_output=True, timeout=120)
    data = shot.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 50_000    # a page with figures, not blank
