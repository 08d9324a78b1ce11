"""The report's rebuild block: the scene's TOML exactly as its author wrote it (the file's text),
the overrides, and the command that rebuilds the page from a saved copy of that text, with the
scene hash it gives (scene/load.py scene_hash: the resolved scene, so a copy saved anywhere
gives the same hash and the same numbers).
"""
from __future__ import annotations

import html
import shlex
from pathlib import Path


def scene_text(scene) -> str | None:
    """The scene file's text as written (None for a scene made in memory)."""
    if scene.path is None:
        return None
    try:
        return Path(scene.path).read_text(encoding="utf-8")
    except OSError:
        return None


def command(provenance: dict | None, scene) -> str:
    """The footer's command: the page's own command with the scene named by the saved file
    `<name>.toml` and the page written beside it as `<name>.html` (the overrides and --temperature
    kept as given)."""
    name = f"{scene.name}.toml"
    if provenance is None:
        return f"levitron report {shlex.quote(name)} --out {shlex.quote(scene.name + '.html')}"
    argv = shlex.split(str(provenance["command"]))
    given = {scene.name, str(scene.path)} | ({Path(scene.path).name} if scene.path else set())
    for i, token in enumerate(argv[2:], start=2):
        if token in given or token.endswith(".toml"):
            argv[i] = name
            break
    if "--out" in argv[:-1]:        # the page beside the saved file, not over this one
        argv[argv.index("--out") + 1] = f"{scene.name}.html"
    return shlex.join(argv)


def section(scene, overrides, provenance: dict | None) -> tuple[str, dict]:
    """The block's HTML and its facts: {"toml", "command", "scene_hash"}."""
    text = scene_text(scene)
    cmd = command(provenance, scene)
    digest = scene.scene_hash()
    facts = {"toml": text, "command": cmd, "scene_hash": digest, "overrides": list(overrides)}
    if text is None:
        return ("<h2>Rebuild this page</h2><p class=\"note\">The scene was made in memory: there is no "
                "file to embed.</p>"), facts
    over = (f" The page was made with --set {html.escape(' '.join(overrides))}, which the command keeps."
            if overrides else "")
    body = (f"<h2>Rebuild this page</h2><p>Save the block below as <code>{html.escape(scene.name)}.toml"
            f"</code> and run <code class=\"rebuild\">{html.escape(cmd)}</code>: it gives the scene hash "
            f"<code>{digest[:12]}</code> and the numbers of this page.{over}</p>"
            f"<pre class=\"toml\" id=\"scene-toml\">{html.escape(text)}</pre>")
    return body, facts
