"""The documentation site (mkdocs.yml over docs/, `make docs`): every page of docs/ is in its nav, the
gallery's pictures are commit-sized and each names the command that drew it, the hook
(mkdocs_hooks.py) points the notebook's links at the built pages, and the site builds with
`mkdocs build --strict` into a folder, its API reference names the public API, and its front page
renders in headless Chromium. The build tests need the docs extra (pip install -e '.[docs]', which
`make docs` and CI install) and are skipped without it."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from tests.helpers.screenshot import CHROMIUM, colours_and_ink, screenshot

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
CONFIG = ROOT / "mkdocs.yml"
MAX_PICTURE = 150_000       # bytes: a gallery picture is committed
NAV_PAGE = re.compile(r"^\s*- [^:]+: (\S+\.(?:md|ipynb))\s*(?:#.*)?$", re.M)

needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (Debian: apt-get install "
                                                              "chromium)")


def _nav() -> list[str]:
    return NAV_PAGE.findall(CONFIG.read_text())


def test_every_page_of_docs_is_in_the_nav_and_the_build_is_strict():
    """A page left out of the nav is built but found by no reader; a nav entry without its file is
    a warning, so the strict build would fail; strictness is the config's and `make docs`'s."""
    pages = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*") if p.suffix in (".md", ".ipynb")}
    nav = _nav()
    assert len(nav) == len(set(nav)), "a page is twice in the nav"
    assert sorted(pages - set(nav)) == [], "pages of docs/ missing from mkdocs.yml's nav"
    assert sorted(set(nav) - pages) == [], "mkdocs.yml's nav names pages docs/ does not have"
    assert re.search(r"^strict: true$", CONFIG.read_text(), re.M)
    assert "mkdocs build --strict" in (ROOT / "Makefile").read_text()


def test_gallery_pictures_are_commit_sized_and_each_names_its_command():
    page = (DOCS / "gallery" / "index.md").read_text()
    pictures = sorted(p.name for p in (DOCS / "gallery").glob("*.png"))
    assert {"equilibrium.png", "simulate.png", "stability_map.png", "launch.png", "trim.png",
            "report.png"} <= set(pictures)
    for name in pictures:
        size = (DOCS / "gallery" / name).stat().st_size
        assert size < MAX_PICTURE, f"docs/gallery/{name} is {size} bytes: shrink it below {MAX_PICTURE}"
        assert f"]({name})" in page, f"docs/gallery/{name} is not shown on the gallery page"
        assert re.search(rf"^(levitron|chromium) .*docs/gallery/{re.escape(name)}", page, re.M), \
            f"the gallery page does not say the command that drew {name}"


def test_the_notebook_links_point_at_the_built_pages_and_a_missing_one_is_a_warning(caplog):
    pytest.importorskip("mkdocs", reason="the docs extra: pip install -e '.[docs]'")
    from mkdocs.structure.files import File, Files

    sys.path.insert(0, str(ROOT))
    try:
        import mkdocs_hooks
    finally:
        sys.path.remove(str(ROOT))

    def file(path):
        return File(path, str(DOCS), "/site", use_directory_urls=False)
    notebook = file("tutorial.ipynb")
    files = Files([notebook, file("api.md"), file("gallery/index.md")])
    assert mkdocs_hooks.on_files(files, {"use_directory_urls": False, "site_dir": "/site"}) is files
    assert notebook.url == "tutorial_notebook.html"
    page = type("Page", (), {"file": notebook})()
    html = ('<a href="api.md#units">API</a> <a href="gallery/index.md">gallery</a> '
            '<a href="https://example.org/x.md">out</a> <a href="nothing.md">gone</a>')
    out = mkdocs_hooks.on_page_content(html, page, {}, files)
    assert 'href="api.html#units"' in out and 'href="gallery/index.html"' in out
    assert 'href="https://example.org/x.md"' in out             # other sites' links are theirs
    assert 'href="nothing.md"' in out
    assert [r.levelname for r in caplog.records] == ["WARNING"] and "nothing.md" in caplog.text
    other = type("Page", (), {"file": file("api.md")})()
    assert mkdocs_hooks.on_page_content(html, other, {}, files) == html


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    """The site built as `make docs` builds it, into a temporary folder."""
    for module in ("mkdocs", "material", "mkdocstrings_handlers.python", "mkdocs_jupyter"):
        pytest.importorskip(module, reason="the docs extra: pip install -e '.[docs]'")
    out = tmp_path_factory.mktemp("site")
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1")
    run = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file", str(CONFIG),
                          "--site-dir", str(out)], cwd=ROOT, env=env, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, f"mkdocs build --strict failed:\n{run.stderr[-3000:]}"
    return out


def test_the_site_builds_strictly_with_every_page(site):
    for page in _nav():
        built = "tutorial_notebook.html" if page == "tutorial.ipynb" else re.sub(r"\.md$", ".html", page)
        assert (site / built).is_file(), f"{page} was not built to {built}"
    for picture in (DOCS / "gallery").glob("*.png"):
        assert (site / "gallery" / picture.name).read_bytes() == picture.read_bytes()
    notebook = (site / "tutorial_notebook.html").read_text()
    assert "Does the top levitate? A notebook tutorial" in notebook
    assert not re.search(r'href="[^":]+\.md[#"]', notebook), "the notebook's page links to a .md file"
    assert "Write the scene" in (site / "tutorial.html").read_text()      # tutorial.md kept its own page


def test_the_api_reference_names_the_public_api(site):
    """Every name `import levitron` exports is on the reference page, and the docstrings are there."""
    import levitron
    page = (site / "reference.html").read_text()
    assert 'id="levitron.study.Study"' in page
    assert 'id="levitron.study.Study.simulate"' in page
    for name in levitron.__all__:
        assert re.search(rf">\s*{name}\s*<|<code>{name}</code>", page), f"{name} is not on the API reference"
    assert "A scene and its generated model" in page          # Study's docstring, rendered


@needs_chromium
def test_the_front_page_renders_in_chromium(site, tmp_path):
    shot = screenshot(site / "index.html", tmp_path / "front_page.png")
    colours, ink = colours_and_ink(shot)
    assert colours > 1 and ink > 0.01, f"the front page renders blank ({colours} colours, {ink:.3%} ink)"
