"""Numbers typed with a unit on the command line and in the API (scene/quantity.py, docs/contract.md
"Units"): `--set top.mass="51.5 g"` and `--spin "30 Hz"` give the SI run bit for bit; a dimensionless
scene and a wrong dimension are one-line refusals; a bare mass heavy in kg is warned of on stderr."""
from __future__ import annotations

import json
import math

import pytest

from levitron.runtime.cli import main as cli

SPIN = repr(2 * math.pi * 30)       # 188.49555921538757 rad/s: 30 Hz, 1800 rpm
TIMES = ("provenance", "wall_s", "timings_s")     # what two identical runs may differ in


def _answer(argv, capsys) -> dict:
    assert cli.main([*argv, "--json"]) == 0, capsys.readouterr().err
    out = json.loads(capsys.readouterr().out)
    return {k: v for k, v in out.items() if k not in TIMES}


@pytest.fixture(scope="module")
def si_runs():
    """The SI runs the typed ones must equal, once for the module."""
    import contextlib
    import io
    out = {}
    for name, argv in (("mass", ["equilibrium", "thesis", "--set", "top.mass=0.0515"]),
                       ("spin", ["stability", "thesis", "--spin", SPIN])):
        text = io.StringIO()
        with contextlib.redirect_stdout(text):
            assert cli.main([*argv, "--json"]) == 0
        out[name] = {k: v for k, v in json.loads(text.getvalue()).items() if k not in TIMES}
    return out


@pytest.mark.parametrize("typed", ["top.mass=51.5 g", 'top.mass="51.5 g"', "top.mass=51.5g"])
def test_set_mass_in_grams_is_the_si_run(typed, si_runs, capsys):
    assert _answer(["equilibrium", "thesis", "--set", typed], capsys) == si_runs["mass"]
    assert si_runs["mass"]["equilibria"]


@pytest.mark.parametrize("spin", ["30 Hz", "30Hz", "1800 rpm", "1800rpm"])
def test_a_spin_in_hz_or_rpm_is_the_si_run(spin, si_runs, capsys):
    typed = _answer(["stability", "thesis", "--spin", spin], capsys)
    assert typed == si_runs["spin"] and typed["modes"]["spin"] == 2 * math.pi * 30


def test_a_height_in_cm_is_the_si_run(capsys):
    assert (_answer(["stability", "thesis", "--height", "15 cm"], capsys)
            == _answer(["stability", "thesis", "--height", "0.15"], capsys))


def test_a_dimensionless_scene_refuses_a_unit_in_one_line(capsys):
    assert cli.main(["stability", "thesis", "--set", "g=1", "--spin", "30 Hz"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--spin '30 Hz': this scene is dimensionless" in err
    assert cli.main(["equilibrium", "thesis", "--set", "units=dimensionless", "--set", "top.mass=51.5 g"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "top.mass = '51.5 g': this scene is dimensionless" in err


def test_a_wrong_dimension_names_the_expected_unit(capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(["stability", "thesis", "--spin", "30 kg"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "'kg' does not convert to rad/s" in err
    assert cli.main(["equilibrium", "thesis", "--set", "top.mass=51.5 Hz"]) == 2
    assert "'Hz' does not convert to kg" in capsys.readouterr().err


def test_a_bare_number_is_read_as_ever(capsys):
    with pytest.raises(SystemExit):
        cli.main(["stability", "thesis", "--spin", "1_0"])
    assert "invalid float value: '1_0'" in capsys.readouterr().err


def test_a_heavy_bare_mass_is_warned_of_on_stderr_beside_the_json(capsys):
    assert cli.main(["equilibrium", "thesis", "--set", "top.mass=51.5", "--json"]) == 0
    out, err = capsys.readouterr()
    json.loads(out)
    assert ("levitron equilibrium: warning: top.mass = 51.5 kg is heavy for a top: did you mean «51.5 g»? "
            "(a number without a unit is SI)\n") == err
    assert cli.main(["equilibrium", "thesis", "--set", "top.mass=0.0515", "--json"]) == 0
    assert capsys.readouterr().err == ""


def test_the_api_takes_a_quantity_and_refuses_one_in_a_dimensionless_scene():
    import levitron
    study = levitron.load("thesis")
    assert str(study.modes("30 Hz")) == str(study.modes(2 * math.pi * 30))
    assert levitron.load("thesis", overrides={"top.mass": "28.4 g"}).scene.params["m"] == 0.0284
    with pytest.raises(levitron.UserError, match="does not convert to rad/s"):
        study.modes("30 kg")
    with pytest.raises(levitron.UserError, match="this scene is dimensionless"):
        levitron.load("thesis", overrides={"g": 1}).modes("30 Hz")
