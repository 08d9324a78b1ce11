"""The Study methods' options are keyword parameters an IDE completes (levitron/study_options.py): each
option the command takes is one, None is the command's default exactly as if it were not passed, and a
call that forgets the spin says so (it said "argument 't_end' is unknown: use one of spin")."""
from __future__ import annotations

import inspect

import pytest

import levitron as lev
from levitron import study_options as so


def keywords(method) -> dict[str, inspect.Parameter]:
    return {n: p for n, p in inspect.signature(method).parameters.items() if p.kind is p.KEYWORD_ONLY}


def test_no_study_method_takes_arbitrary_keywords():
    for name, fn in vars(lev.Study).items():
        if inspect.isfunction(fn) and not name.startswith("_"):
            kinds = {p.kind for p in inspect.signature(fn).parameters.values()}
            assert inspect.Parameter.VAR_KEYWORD not in kinds, f"Study.{name} takes **kwargs"


@pytest.mark.parametrize("method, options", [
    ("simulate", (*so.SIMULATE_OPTIONS, *so.SIMULATE_ALIASES)),
    ("simulate_many", (*so.MANY_OPTIONS, *so.SIMULATE_ALIASES)),
    ("scan", so.SCAN_OPTIONS)])
def test_every_option_is_a_keyword_parameter_defaulting_to_none(method, options):
    params = keywords(getattr(lev.Study, method))
    assert set(params) == set(options)
    assert all(p.default is None and p.annotation is not p.empty for p in params.values())
    assert all(name in getattr(lev.Study, method).__doc__ or method == "simulate_many" for name in options)


def test_the_scan_options_are_the_maps_keywords():
    from levitron.runtime.scan.stability_map import scan
    assert set(so.SCAN_OPTIONS) == set(inspect.signature(scan).parameters) - {"model", "spins", "axis", "others"}


@pytest.mark.parametrize("method", ["launch", "trim", "optimize"])
def test_the_launch_options_are_keyword_parameters(method):
    from levitron.runtime.scan.launch_odds import LAUNCH_OPTIONS
    params = keywords(getattr(lev.Study, method))
    assert set(LAUNCH_OPTIONS) <= set(params)
    assert all(params[n].default is None for n in LAUNCH_OPTIONS)


def test_a_forgotten_spin_is_missing_not_an_unknown_option(study):
    with pytest.raises(lev.UserError) as exc:
        study.simulate(t_end=1)
    msg = str(exc.value)
    assert msg.startswith("Study.simulate: the argument spin is missing: call Study.simulate(spin, ...)"), msg
    assert "unknown" not in msg and "\n" not in msg
    with pytest.raises(lev.UserError, match=r"Study.scan: the argument axis and values are missing"):
        study.scan([1000.0])
    with pytest.raises(lev.UserError, match="Study.simulate: too many positional arguments"):
        study.simulate(1000.0, 0.01)


def test_an_unknown_keyword_is_refused_in_the_methods_words(study):
    with pytest.raises(lev.UserError, match=r"simulate_many option 'tlt' is unknown: did you mean 'tilt'\?"):
        study.simulate_many([1000.0], tlt=0.01)
    with pytest.raises(lev.UserError, match=r"launch: unknown option 'colour': use success_time"):
        study.trim(n=4, colour=3)
    with pytest.raises(lev.UserError, match=r"Study.optimize: argument 'colour' is unknown: use one of maximize"):
        study.optimize("spin-range", {"top.mass": (0.05, 0.052)}, colour=3)
    with pytest.raises(lev.UserError, match=r"Study.keys: argument 'colour' is unknown: .* takes no argument"):
        study.keys(colour=3)


def test_none_is_the_commands_default(study):
    """An option passed as None runs what leaving it out runs, bit for bit."""
    a = study.simulate(1000.0, t_end=0.05)
    b = study.simulate(1000.0, t_end=0.05, tilt=None, offset=None, integrator=None, tol=None, box=None, part=None,
                       h=None, step=None, n_out=None, azimuth=None, tilt_azimuth=None, plot=None, save=None)
    assert a.final_state == b.final_state and a.details["integrator"] == b.details["integrator"]
    with pytest.raises(lev.UserError, match="pass tilt_azimuth or azimuth, not both"):
        study.simulate(1000.0, t_end=0.05, azimuth=0.1, tilt_azimuth=0.1)
