"""`optimize` refuses a flag its mode would ignore, in one line, before any work: --grid with the
launch-odds design (its own grid and zoom) or a fit, --param without --fit-height, --constrain with
--fit, launch flags where no launch runs (runtime/cli/commands/optimize.py refuse_ignored)."""
from __future__ import annotations

import pytest

from levitron.runtime.cli import main as cli

BOX = ["--vary", "top.mass=0.0505:0.0524"]


def _refused(capsys, *argv) -> str:
    assert cli.main(["optimize", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "internal error" not in err, err
    return err


def test_launch_odds_refuses_grid(capsys):
    err = _refused(capsys, "thesis_air", "--maximize", "launch-odds", *BOX, "--grid", "30")
    assert "--grid 30" in err and "own grid" in err and "drop --grid" in err


@pytest.mark.parametrize("argv, flag", [
    (["thesis", "--fit-height", "0.09", "--grid", "30"], "--grid 30"),
    (["thesis_stable", "--maximize", "spin-range", *BOX, "--param", "top.mass"], "--param top.mass"),
    (["thesis", "--fit-height", "0.09", "--n", "100", "--temperature-spread", "3"], "--temperature-spread, --n"),
    (["thesis", "--fit", "data.csv", *BOX, "--constrain", "stiffness>=1"], "--constrain"),
    (["thesis_stable", "--maximize", "spin-range", *BOX, "--seed", "3"], "--seed"),
])
def test_a_flag_the_mode_ignores_is_refused(capsys, argv, flag):
    err = _refused(capsys, *argv)
    assert flag in err and "drop" in err, err
