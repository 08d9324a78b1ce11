"""A page rendered by headless Chromium to a PNG, and the checks that it is a page, not a blank
(tests/house/test_docs_site.py, test_notebook.py). LEVITRON_DOCS_SHOTS=FOLDER keeps a copy of each
screenshot there (reports/docs/ holds the ones of the docs site and the notebook)."""
from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")


def screenshot(page: Path, shot: Path, size: tuple[int, int] = (1280, 900)) -> Path:
    """page (an HTML file) as chromium draws it in a window of size (width, height) px, to shot."""
    subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
                    f"--window-size={size[0]},{size[1]}", f"--screenshot={shot}", page.resolve().as_uri()],
                   check=True, capture_output=True, timeout=120)
    keep = os.environ.get("LEVITRON_DOCS_SHOTS")
    if keep:
        Path(keep).mkdir(parents=True, exist_ok=True)
        shutil.copy2(shot, Path(keep) / shot.name)
    return shot


def colours_and_ink(shot: Path) -> tuple[int, float]:
    """The number of distinct colours of the image, and the fraction of its pixels darker than
    light grey (text, lines, figures)."""
    import matplotlib.image
    import numpy as np
    data = shot.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{shot} is not a PNG"
    img = matplotlib.image.imread(str(shot))[..., :3]
    colours = len(np.unique((img * 255).astype(np.uint8).reshape(-1, 3), axis=0))
    ink = float((img.mean(axis=2) < 0.8).mean())
    return colours, ink
