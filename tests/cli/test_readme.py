"""The README tells the truth: every `$ levitron ...` example in it runs, and the lines it shows
appear in the real output.

Abridgement rule (stated in the README): a line `...` stands for any number of lines left out; a
line ending in ` ...` matches an output line that starts with the text before it; every other shown
line must equal an output line. Shown lines appear in the output in order, and two shown lines with
no `...` line between them are consecutive in the output. Output paths `out/...` are redirected
into a temporary folder.
"""
from __future__ import annotations

import re
import shlex

import pytest

from levitron.scene.paths import ROOT
from levitron.runtime.cli import main as cli

README = ROOT / "README.md"


def examples() -> list[tuple[str, list[str]]]:
    """(command line, shown lines) for every `$ levitron` line in the README's code blocks."""
    out, in_block, current = [], False, None
    for line in README.read_text().splitlines():
        if line.startswith("```"):
            in_block, current = not in_block, None
            continue
        if not in_block:
            continue
        m = re.match(r"^\$ (?:\.venv/bin/)?levitron (.*)$", line)
        if m:
            current = (m.group(1).split("  #")[0].strip(), [])
            out.append(current)
        elif line.startswith("$ "):
            current = None
        elif current is not None:
            current[1].append(line.rstrip())
    return out


def _matches(shown: str, actual: str) -> bool:
    if shown.endswith(" ..."):
        return actual.startswith(shown[:-4])
    return shown == actual.rstrip()


def find_in_order(shown: list[str], output: list[str]) -> str | None:
    """None if `shown` (with the abridgement rule) appears in `output`, else what is missing."""
    pos, gap = 0, True            # gap: the next shown line may come after skipped lines
    for line in shown:
        if line == "...":
            gap = True
            continue
        candidates = range(pos, len(output)) if gap else range(pos, min(pos + 1, len(output)))
        hit = next((i for i in candidates if _matches(line, output[i])), None)
        if hit is None:
            return line
        pos, gap = hit + 1, False
    return None


def test_rule_itself():
    out = ["a", "b 1", "c", "d"]
    assert find_in_order(["a", "b ...", "c"], out) is None
    assert find_in_order(["a", "c"], out) == "c"            # not consecutive without `...`
    assert find_in_order(["a", "...", "d"], out) is None
    assert find_in_order(["d", "...", "a"], out) == "a"     # order matters
    assert find_in_order(["b 2 ..."], out) == "b 2 ..."


EXAMPLES = examples()


def test_readme_has_examples():
    assert len(EXAMPLES) >= 6
    assert any(shown for _, shown in EXAMPLES)


@pytest.mark.parametrize("command,shown", EXAMPLES, ids=[c for c, _ in EXAMPLES])
def test_readme_example(command, shown, tmp_path, capsys):
    argv = [str(tmp_path / a) if a.startswith("out/") else a for a in shlex.split(command)]
    assert cli.main(argv) == 0, capsys.readouterr().err
    output = capsys.readouterr().out.replace(str(tmp_path) + "/", "")
    missing = find_in_order(shown, output.splitlines())
    assert missing is None, f"README line not in the output of `levitron {command}`: {missing!r}\n{output}"


def python_blocks() -> list[str]:
    """The README's indented Python examples (a block of 4-space lines that starts with an import
    of levitron)."""
    blocks, lines = [], README.read_text().splitlines()
    for i, line in enumerate(lines):
        if line.startswith("    import levitron"):
            block = []
            for more in lines[i:]:
                if not more.startswith("    "):
                    break
                block.append(more[4:])
            blocks.append("\n".join(block))
    return blocks


def test_readme_python_examples_run(capsys):
    """Every Python example of the README runs as written (its comments state the units)."""
    blocks = python_blocks()
    assert blocks
    for src in blocks:
        exec(compile(src, "README.md", "exec"), {})       # the README's own example, as a reader runs it
    assert "top.mass" in capsys.readouterr().out
