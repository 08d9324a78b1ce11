"""A misspelt flag or command is one line that names the closest one and the help to read."""
from __future__ import annotations

import pytest

from levitron.runtime.cli import main as cli
from levitron.runtime.cli.suggest import choice_hint, closest, options_hint


def _error(capsys, argv) -> str:
    with pytest.raises(SystemExit) as exc:
        cli.main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    return err.strip()


def test_misspelt_flag(capsys):
    assert _error(capsys, ["launch", "thesis", "--sucess-time", "10"]) == (
        "levitron: error: unrecognized arguments: --sucess-time 10; did you mean --success-time? "
        "(see `levitron launch --help`)")


def test_misspelt_flag_with_value_and_one_dash(capsys):
    err = _error(capsys, ["equilibrium", "thesis", "--jsn"])
    assert err.endswith("--jsn; did you mean --json? (see `levitron equilibrium --help`)")
    err = _error(capsys, ["launch", "thesis", "-sucess-time=10"])
    assert "did you mean --success-time?" in err


def test_nothing_close_no_guess(capsys):
    err = _error(capsys, ["info", "thesis", "--frobnicate"])
    assert err == "levitron: error: unrecognized arguments: --frobnicate (see `levitron info --help`)"


def test_misspelt_command(capsys):
    err = _error(capsys, ["stabilty", "thesis"])
    assert "invalid choice: 'stabilty'" in err and err.endswith("; did you mean stability? (see `levitron --help`)")
    err = _error(capsys, ["frobnicate", "thesis"])
    assert "did you mean" not in err


def test_rules():
    assert closest("sceens", ["scenes", "keys"]) == "scenes" and closest("zzz", ["scenes"]) is None
    assert choice_hint("argument COMMAND: invalid choice: 'kyes' (choose from 'scenes', 'keys')").endswith(
        "; did you mean keys?")
    assert choice_hint("argument --x: expected one argument") == "argument --x: expected one argument"

    class P:
        _actions = [type("A", (), {"option_strings": ["-h", "--help"]})(),
                    type("A", (), {"option_strings": ["--tilt"]})()]
    assert options_hint(P, ["--tlit", "-0.5", "--hepl"]) == "; did you mean --tilt or --help?"
    assert options_hint(P, ["-0.5", "1e-3", "thesis"]) == ""
