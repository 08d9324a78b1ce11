"""A counted task inside a stage is that stage's progress (runtime/ui/progress.py): the report's
last stage, the launch odds, shows the Monte Carlo's count and an ETA that moves with it, off a
terminal in a line at most every LOG_EVERY seconds, on one in the stage's bar; the CLI's spinner
yields its row to the rows inside it. (Before: the Monte Carlo, quiet inside the report, showed
nothing, and the stage's ETA stood still at "2 s" through the whole stage.)"""
from __future__ import annotations

import io
import re
import sys

import pytest

from levitron.runtime.ui import progress


@pytest.fixture
def lines(monkeypatch):
    monkeypatch.delenv("LEVITRON_PROGRESS", raising=False)
    monkeypatch.setattr(progress, "LOG_EVERY", 0.0, raising=False)
    progress.enable()


@pytest.mark.parametrize("quiet", [True, False], ids=["quiet", "loud"])
def test_a_count_inside_a_stage_writes_its_lines_off_a_terminal(quiet, lines, capsys):
    with progress.stages("report x", ["map", "launch odds"], [1, 4]) as stage:
        stage(0)
        stage(1)
        with progress.task("launch", total=4, quiet=quiet) as tick:
            for _ in range(4):
                tick()
    err = capsys.readouterr().err.splitlines()
    counts = [ln for ln in err if re.search(r": launch \d", ln)]
    assert [re.sub(r" \(.*\)$", "", ln) for ln in counts] == [
        f"levitron: report x: launch odds 2/2: launch {k}/4" for k in (1, 2, 3)], err
    assert all(re.search(r"\(\d+:\d\d elapsed, eta \d+:\d\d\)$", ln) for ln in counts[1:]), counts


def test_a_count_outside_a_stage_keeps_its_own_rule(lines, capsys):
    """Outside a stage nothing changes: quiet is silent, log_every as given."""
    with progress.task("scan", total=3, quiet=True) as tick:
        tick(3)
    with progress.task("scan", total=3) as tick:        # no log_every: no lines off a terminal
        tick(3)
    assert capsys.readouterr().err == ""


def test_no_lines_when_progress_is_off(lines, capsys):
    progress.disable()
    try:
        with progress.stages("report x", ["launch odds"]) as stage:
            stage(0)
            with progress.task("launch", total=2) as tick:
                tick(2)
    finally:
        progress.enable()
    assert capsys.readouterr().err == ""


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_on_a_terminal_the_stage_shows_the_count_and_the_spinner_yields(lines, monkeypatch):
    monkeypatch.setattr(sys, "stderr", _Terminal())
    seen = {}
    with progress.task("levitron report"):
        bar = progress._state["bar"]
        spinner = bar.tasks[0].id
        with progress.stages("report x", ["map", "launch odds"], [1, 4]) as stage:
            stage(0)
            stage(1)
            with progress.task("launch", total=4, quiet=True) as tick:
                tick(2)
                seen["rows"] = [(t.description, t.visible) for t in bar.tasks]
                row = bar.tasks[-1]
                seen["share"], seen["eta"] = row.completed / row.total, row.fields["eta"][0]
        seen["after"] = bar._tasks[spinner].visible
    assert seen["rows"] == [("levitron report", False), ("report x: launch odds 2/2: launch 2/4", True)]
    assert seen["share"] == pytest.approx((1 + 4 * 0.5) / 5)      # the stage's weight, half done
    assert seen["eta"] is not None and seen["eta"] >= 0
    assert seen["after"] is True
