"""MkDocs hooks of the documentation site (mkdocs.yml `hooks:`).

docs/tutorial.md (the command-line tutorial) and docs/tutorial.ipynb (the notebook) would both be
built to tutorial.html; the notebook's page is written to tutorial_notebook.html instead. Links to
tutorial.ipynb from the Markdown pages follow it (MkDocs resolves them through the file's url).

The notebook's own links name the pages as files (`api.md`), as Jupyter opens them beside it;
mkdocs-jupyter leaves them so, and MkDocs does not check them: on its page they are pointed at the
built pages, and one that names no page of docs/ is a warning (an error under `mkdocs build --strict`)."""
from __future__ import annotations

import logging
import os
import re

NOTEBOOK_PAGES = {"tutorial.ipynb": "tutorial_notebook"}
LOG = logging.getLogger("mkdocs.hooks.levitron")
_MD_LINK = re.compile(r'href="(?![a-z]+:|#|/)([^"#?]+)\.(md|ipynb)(#[^"]*)?"')


def on_files(files, config):
    """Runs after the plugins' on_files (mkdocs-jupyter has made the notebook a page by then)."""
    for f in files:
        stem = NOTEBOOK_PAGES.get(f.src_uri)
        if stem is None:
            continue
        f.dest_path = f"{stem}/index.html" if config["use_directory_urls"] else f"{stem}.html"
        f.abs_dest_path = os.path.normpath(os.path.join(config["site_dir"], f.dest_path))
        f.url = f"{stem}/" if config["use_directory_urls"] else f"{stem}.html"
    return files


def on_page_content(html, page, config, files):
    """The notebook page's links to docs/*.md (or a notebook) point at the pages built from them."""
    if page.file.src_uri not in NOTEBOOK_PAGES:
        return html

    def built(match):
        target = files.get_file_from_path(f"{match[1]}.{match[2]}")
        if target is None:
            LOG.warning("%s links to '%s.%s', which is not a page of docs/", page.file.src_uri, match[1], match[2])
            return match[0]
        return f'href="{target.url_relative_to(page.file)}{match[3] or ""}"'
    return _MD_LINK.sub(built, html)
