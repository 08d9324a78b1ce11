"""One check per setting: a bad run length, height or tolerance is refused by one function of the
runtime (runtime/ui/validate.py: run_length, height, tolerance, spin_rate), which the command line
and the API both reach, so both faces say one sentence, each in its own words (runtime/words.py:
«t_end» is `--t-end` on the command line, `t_end` in the API), and the refusal carries the setting
as data (`param`, `value`, `unit`, `hint`).

Before, `simulate --t-end -1` said "--t-end -1.0 must be a positive run length in s" and
`Study.simulate(300, t_end=-1)` "run length t_end=-1.0 must be a positive finite time";
`stability --height -1` "--height = -1 must be a positive number in m (above the plate, z > 0)"
(its `param` the flag, its `unit` prose) and `Study.stability(height=-1)` "no top hovers at z = -1 m".
"""
from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import levitron as lev
from levitron.runtime.cli import main as cli
from levitron.runtime.errors import UserError
from levitron.runtime.words import render

SCENE = "thesis_stable"

# a setting: the command line before the value, and the API call with the value
FACES = {
    "simulate-t_end": (["simulate", SCENE, "--spin", "1000", "--t-end"], lambda s, v: s.simulate(1000.0, t_end=v)),
    "simulate-tol": (["simulate", SCENE, "--spin", "1000", "--tol"], lambda s, v: s.simulate(1000.0, tol=v)),
    "stability-height": (["stability", SCENE, "--height"], lambda s, v: s.stability(height=v)),
    "modes-spin": (["stability", SCENE, "--spin"], lambda s, v: s.modes(v)),
    "launch-t_end": (["launch", SCENE, "--n", "5", "--t-end"], lambda s, v: s.launch(n=5, t_end=v)),
    "trim-workers": (["trim", "thesis_air", "--workers"], lambda s, v: s.trim(workers=v)),
    "trim-t_end": (["trim", "thesis_air", "--t-end"], lambda s, v: s.trim(t_end=v)),
}


@pytest.fixture(scope="module")
def stable():
    return lev.load(SCENE)


def _cli_refusal(argv: list[str], value: float, capsys) -> tuple[UserError, str]:
    """The command line's refusal of `value`: the UserError its command raised (the runtime's
    sentence with its markers) and the one line `levitron` printed for it."""
    words = [*argv[:-1], f"{argv[-1]}={value!r}"]      # --t-end=-inf: argparse takes it as a value
    args = cli.build_parser(words[0]).parse_args(words)
    with pytest.raises(UserError) as raised:
        args._run(args)
    assert cli.main(words) == 2
    err = capsys.readouterr().err.strip().splitlines()      # (a first run's compile progress above)
    return raised.value, err[-1]


def _api_refusal(call, study, value: float) -> UserError:
    with pytest.raises(lev.UserError) as raised:
        call(study, value)
    return raised.value


def _one_sentence(name: str, value: float, study, capsys) -> tuple[UserError, UserError]:
    """Both faces refuse `value` with one sentence, each in its words: the command line's line is
    the runtime's sentence worded for it, the API's error the same sentence worded for the API,
    and both carry the same setting, value, unit and hint."""
    argv, call = FACES[name]
    core, line = _cli_refusal(argv, value, capsys)
    api = _api_refusal(call, study, value)
    command = argv[0]
    assert line == f"levitron {command}: error: {core.words('cli', study.units)}", (line, str(core))
    assert str(api) == core.words("api", study.units), (str(api), str(core))
    assert (api.param, api.unit, api.hint) == (core.param, core.unit, render(core.hint, "api", study.units))
    assert api.value == core.value or (math.isnan(api.value) and math.isnan(core.value))
    assert "--" not in str(api) and "\n" not in str(api), str(api)
    return core, api


def test_t_end_minus_one_is_one_sentence_on_both_faces(stable, capsys):
    core, api = _one_sentence("simulate-t_end", -1.0, stable, capsys)
    assert str(core).startswith("«t_end» = -1 must be a positive run length"), str(core)
    assert str(api).startswith("t_end = -1 must be a positive run length in s: pass e.g. t_end=1"), str(api)
    assert (api.param, api.value, api.unit, api.hint) == ("t_end", -1.0, "s", "pass e.g. t_end=1")


def test_height_minus_one_is_one_sentence_on_both_faces(stable, capsys):
    """The height's own check, not the hover mass's "no top hovers at z = -1 m" in one face and
    "must be a positive number" in the other; `param` the setting's name, `unit` its SI unit."""
    core, api = _one_sentence("stability-height", -1.0, stable, capsys)
    assert str(api).startswith("height = -1 must be a positive height in m: pick a height above the plate"), str(api)
    assert (api.param, api.value, api.unit) == ("height", -1.0, "m")
    assert "Study.equilibria()" in api.hint and "levitron equilibrium" in core.words("cli"), (api.hint, str(core))


def test_a_run_length_is_one_check_whichever_command_takes_it(stable, capsys):
    """launch --t-end and simulate --t-end: the same sentence (before: "a positive time" against
    "a positive run length")."""
    simulate, _ = _one_sentence("simulate-t_end", -1.0, stable, capsys)
    launch, _ = _one_sentence("launch-t_end", -1.0, stable, capsys)
    assert str(launch) == str(simulate)



@pytest.mark.parametrize("name, value", [("trim-workers", 0), ("trim-t_end", -1.0)])
def test_a_trim_refuses_a_setting_as_a_launch_does(name, value, capsys):
    """A trim's (and a launch-odds design's) launch settings are checked when its request is made,
    not at each point of its box: before, `trim --workers 0` said "... (and at every point of the
    --vary box's grid): move or widen the box"."""
    core, api = _one_sentence(name, value, lev.load("thesis_air"), capsys)
    assert "box" not in str(api) and api.param == name.split("-", 1)[1], str(api)


BAD = st.one_of(st.sampled_from([0.0, -0.0, -1.0, math.nan, math.inf, -math.inf]),
                st.floats(max_value=0.0, allow_nan=False, allow_infinity=False))


@settings(max_examples=25, derandomize=True, deadline=None, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(name=st.sampled_from(["simulate-t_end", "simulate-tol", "stability-height", "modes-spin"]), value=BAD)
def test_bad_numbers_are_refused_with_one_sentence_on_both_faces(name, value, stable, capsys):
    """Any number a setting cannot take (zero, negative, NaN, infinite) is refused by the command
    line and the API with one sentence, carrying the setting, the value and a hint."""
    core, api = _one_sentence(name, value, stable, capsys)
    assert core.param == name.split("-", 1)[1] and core.hint, (core.param, core.hint)


@pytest.mark.parametrize("given, param", [
    ({"t_end": -1.0}, "t_end"), ({"t_end": math.inf}, "t_end"), ({"t_end": 1e9}, "t_end"),
    ({"method": "rk4", "h": 1e-6, "t_end": 1e5}, "t_end"), ({"tol": 0.0}, "tol"), ({"tol": math.nan}, "tol"),
    ({"tol": 1.0}, "tol"), ({"tol": 1e-16}, "tol"),
])
def test_a_runs_refusals_carry_the_setting_and_the_fix(given, param):
    """The integrator's budget (runtime/integrate/budget.py check_options, every run's last check):
    a refused run length or tolerance carries its setting, value, unit and how to fix it."""
    from levitron.runtime.integrate.budget import check_options
    args = {"method": "dop853", "t_end": 10.0, "tol": 1e-9, "time_scale": 1.0, **given}
    with pytest.raises(UserError) as raised:
        check_options(**args)
    e = raised.value
    assert (e.param, e.unit) == (param, "s" if param == "t_end" else ""), (e.param, e.unit, str(e))
    assert e.value == args[param] or math.isnan(e.value) and math.isnan(args[param]), (e.value, str(e))
    assert e.hint and e.hint in str(e) and "\n" not in str(e), (e.hint, str(e))
