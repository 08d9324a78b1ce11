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


# the report command's options (runtime/cli/commands/report.py and the options every command takes):
# those that take a value, and those that do not; argparse takes any unique prefix of either
VALUED = ("--set", "--temperature", "--out")
FLAGS = ("--json", "--quiet")


def _option(token: str) -> tuple[str | None, bool]:
    """(the option a token names, whether it carries its value after '='), or (None, False) for a
    positional argument. A unique prefix names its option, as argparse reads it."""
    if not token.startswith("--") or token == "--":
        return None, False
    name, eq, _ = token.partition("=")
    hits = [o for o in VALUED + FLAGS if o == name] or [o for o in VALUED + FLAGS if o.startswith(name)]
    return (hits[0] if len(hits) == 1 else name), bool(eq)


def roles(args: list[str]) -> list[tuple[str, list[str]]]:
    """The report's arguments (after `report`) by role, in order: ("scene", [token]) for the scene,
    (option, [tokens]) for an option with its value, ("", [token]) for anything else."""
    out, i, rest = [], 0, False
    while i < len(args):
        token = args[i]
        name, inline = (None, False) if rest else _option(token)
        if token == "--" and not rest:
            out.append(("", [token]))
            rest = True
        elif name is None:
            out.append(("scene" if not any(r == "scene" for r, _ in out) else "", [token]))
        elif name in VALUED and not inline and i + 1 < len(args):
            out.append((name, [token, args[i + 1]]))
            i += 1
        else:
            out.append((name, [token]))
        i += 1
    return out


def command(provenance: dict | None, scene) -> str:
    """The footer's command: the page's own command with the scene argument (by its place among the
    parsed arguments, not by its spelling) the saved file `<name>.toml`, every --out form dropped
    and the page written beside it as `--out <name>.html` (the overrides and --temperature kept as
    given), so that running it never overwrites this page."""
    name = f"{scene.name}.toml"
    page = ["--out", f"{scene.name}.html"]
    if provenance is None:
        return shlex.join(["levitron", "report", name, *page])
    argv = shlex.split(str(provenance["command"]))
    head, args = argv[:2], argv[2:]
    kept = []
    for role, tokens in roles(args):
        if role == "--out":
            continue
        kept += [name] if role == "scene" else tokens
    if "--" in kept:                    # options before a bare '--': after it all is positional
        cut = kept.index("--")
        kept = kept[:cut] + page + kept[cut:]
    else:
        kept += page
    return shlex.join(head + kept)


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
