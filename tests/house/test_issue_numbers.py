"""The source says ideas, not tracker numbers: no "issue 27" in a docstring or comment of the
package's code (runtime/, scene/, derive/, levitron/). A number means nothing to a reader without
the tracker; the sentence says what the change is (the tilted base, the design by the launch odds)."""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
ROOMS = ("runtime", "scene", "derive", "levitron")
ISSUE = re.compile(r"\bissues?\b[\s#]*\d+|\(#\d+\)", re.IGNORECASE)


def mentions(root: Path) -> list[str]:
    """'path:line: text' of every line of a .py under the rooms that names an issue by number."""
    found = []
    for room in ROOMS:
        for path in sorted((root / room).rglob("*.py")):
            for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if ISSUE.search(line):
                    found.append(f"{path.relative_to(root).as_posix()}:{n}: {line.strip()}")
    return found


def test_no_issue_number_in_the_source():
    found = mentions(ROOT)
    assert not found, (f"{len(found)} lines name an issue by number: say the idea instead\n"
                       + "\n".join(found))


@pytest.mark.parametrize("text, hit", [
    ("(issue 27)", True), ("Issues #3 and 4", True), ("issue #12", True), ("see (#27)", True),
    ("the tissue 3", False), ("an issue with 3 keys", False), ("colour #222", False),
])
def test_the_pattern(text, hit):
    assert bool(ISSUE.search(text)) is hit
