"""A fourth battery of hostile inputs, one test (or a few) per class of defect, each through the one
mechanism that now keeps the promise:

  * paths as the user gave them (runtime/ui/atomic.py): a path through a symbolic link writes the
    target, a file name the file system takes is saved whatever the temporary's name would be, and
    every writer treats a missing folder alike (made: plots, pages and animations made it before);
  * the report's rebuild command is built from the arguments by role (runtime/report/rebuild.py);
  * the [launch] table takes every input a flag takes (scene/keys.py LAUNCH_KEYS, checked against
    runtime/scan/launch_inputs.py ALL_INPUTS at import);
  * a spread's support is held to its key's bound (scene/keys.py KEY_BOUNDS, runtime/scan/spreads.py
    check_support), with Hypothesis strategies over spreads against the bounds;
  * no verdict without the physics: a run in air whose spin ends below the window
    (runtime/integrate/verdict.py past_window);
  * impossible geometry refused as geometry (a magnet offset beyond the hover height; magpylib
    sources with NaN, without a dimension, or too many);
  * refusals quote the input as typed.

Each case failed before its fix.
"""
from __future__ import annotations

import math
import os
import tomllib

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from levitron.runtime.errors import UserError
from levitron.scene.checks import SceneError
from levitron.scene.keys import KEY_BOUNDS
from tests.helpers.battery import ROOT

FUZZ = os.environ.get("HYPOTHESIS_PROFILE") == "fuzz"


def budget(n: int):
    """n examples in CI (derandomized), 20 n random ones under `make fuzz` (tests/battery/test_properties.py)."""
    return settings(max_examples=n * (20 if FUZZ else 1), derandomize=not FUZZ, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow], database=None)


def one_line(exc) -> str:
    text = str(exc.value)
    assert "\n" not in text, text
    return text


# ---------------------------------------------------------------- paths as the user gave them

COLUMNS = {"t": np.array([0.0, 1.0]), "z": np.array([0.1, 0.2])}


def test_save_through_a_symlink_writes_its_target(tmp_path):
    """--save through a link replaced the link by a file and left the target's old content."""
    from levitron.runtime.simulate.trajectory_file import read_columns, write_columns
    real = tmp_path / "data" / "real.csv"
    real.parent.mkdir()
    real.write_text("old\n")
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    write_columns(link, COLUMNS)
    assert link.is_symlink() and os.readlink(link) == str(real)
    assert read_columns(real)["z"].tolist() == [0.1, 0.2]
    assert sorted(p.name for p in real.parent.iterdir()) == ["real.csv"]     # no temporary left
    assert sorted(p.name for p in tmp_path.iterdir()) == ["data", "link.csv"]


def test_a_name_the_file_system_takes_is_saved(tmp_path):
    """A 244-byte name could not be saved: the temporary's name added 25 bytes past NAME_MAX."""
    from levitron.runtime.ui.atomic import name_max, temp_beside
    from levitron.runtime.simulate.trajectory_file import check_path, write_columns
    limit = name_max(tmp_path)
    for size in (limit - 11, limit):
        path = tmp_path / ("a" * (size - 4) + ".csv")
        assert len(temp_beside(path).name.encode()) <= limit
        write_columns(check_path(path), COLUMNS)
        assert path.is_file()
    assert len(list(tmp_path.iterdir())) == 2
    with pytest.raises(UserError, match="bytes long") as exc:
        check_path(tmp_path / ("a" * limit + ".csv"))
    one_line(exc)


def test_every_writer_treats_a_missing_folder_alike(tmp_path):
    """--out made missing folders while --save refused them: one check now, the folder made."""
    from levitron.runtime.simulate.trajectory_file import check_path, write_columns
    from levitron.runtime.ui.plotting import check_plot_path
    from levitron.runtime.ui.atomic import write_text
    check_plot_path(tmp_path / "a" / "b" / "p.png", "--out")
    check_path(tmp_path / "c" / "d" / "x.csv")
    assert list(tmp_path.iterdir()) == []                  # checked, nothing made yet
    write_columns(tmp_path / "c" / "d" / "x.csv", COLUMNS)
    write_text(tmp_path / "e" / "f.html", "<p>", "--out")
    assert (tmp_path / "c" / "d" / "x.csv").is_file() and (tmp_path / "e" / "f.html").is_file()
    (tmp_path / "afile").write_text("x")
    for check in (lambda p: check_plot_path(p / "p.png", "--out"), lambda p: check_path(p / "x.csv")):
        with pytest.raises(UserError, match="afile is a file, not a folder") as exc:
            check(tmp_path / "afile" / "sub")
        one_line(exc)


# ---------------------------------------------------------------- the report's rebuild command

class _Scene:
    name, path = "thesis", "/somewhere/scenes/thesis.toml"


@pytest.mark.parametrize("given,expected", [
    # an option's value ending in .toml before the scene was rewritten instead of the scene
    ("levitron report --out=a.toml.html thesis --set top.mass=0.05",
     "levitron report thesis.toml --set top.mass=0.05 --out thesis.html"),
    # --out=PATH was kept: the rebuild overwrote the page
    ("levitron report thesis --out=page.html", "levitron report thesis.toml --out thesis.html"),
    ("levitron report --ou page.html my.toml --temperature -5",
     "levitron report thesis.toml --temperature -5 --out thesis.html"),
    ("levitron report --set plate.file=x.toml /somewhere/scenes/thesis.toml --out p.html",
     "levitron report --set plate.file=x.toml thesis.toml --out thesis.html"),
])
def test_the_rebuild_command_replaces_the_scene_by_its_role(given, expected):
    from levitron.runtime.report.rebuild import command
    assert command({"command": given}, _Scene()) == expected


# ---------------------------------------------------------------- the [launch] table takes every input

def test_the_launch_table_takes_every_input_a_flag_takes():
    """[launch] moment_tilt, which `launch --help` says the table sets, was an unknown key."""
    from levitron.scene.load import validate
    from levitron.scene.keys import LAUNCH_KEYS
    from levitron.runtime.scan.launch_inputs import ALL_INPUTS
    from levitron.runtime.scan.launch_odds import table_settings
    assert set(ALL_INPUTS) <= {k.name for k in LAUNCH_KEYS}
    text = (ROOT / "scenes" / "thesis_stable.toml").read_text()
    data = tomllib.loads(text + '\n[launch]\nmoment_tilt = "uniform:0,0.01"\nbase_tilt = 0\n')
    data["top"]["moment_tilt"] = 0.0
    scene = validate(data)
    inputs, _ = table_settings(scene.data["launch"])
    assert inputs == {"moment_tilt": "uniform:0,0.01", "base_tilt": 0}


# ---------------------------------------------------------------- spreads against the keys' bounds

def _refusal(name, spec):
    from levitron.runtime.scan.launch_inputs import check_bounds
    from levitron.runtime.scan.spreads import parse_input
    reference = 0.0515 if name == "mass" else 1.0
    d = parse_input(name, spec, reference)
    try:
        check_bounds({name: d}, {name: spec})
    except UserError as exc:
        return str(exc)
    return None


@pytest.mark.parametrize("name,spec,bound", [
    ("base_tilt", "1.6", "pi/2"), ("base_tilt", "normal:0,0.2", "pi/2"),
    ("moment_tilt", "uniform:0,1e6", "pi/2"), ("mass", "rel:uniform:-3,-2", "-100 %"),
])
def test_a_spread_beyond_its_keys_bound_is_refused(name, spec, bound):
    """--base-tilt 1.6 and --moment-tilt uniform:0,1e6 were flown while --set plate.tilt=1.6 was refused."""
    why = _refusal(name, spec)
    assert why is not None and spec in why and bound in why and "\n" not in why, why


def test_the_key_and_its_spread_share_one_bound():
    from levitron.scene.load import base_tilt, magnet_tilt
    with pytest.raises(SceneError, match=r"0 <= tilt < pi/2"):
        base_tilt({"tilt": 1.6})
    with pytest.raises(SceneError, match=r"\|moment_tilt\| < pi/2"):
        magnet_tilt({"moment_tilt": -1.6})
    assert _refusal("base_tilt", "uniform:0,1.5") is None


def _spec(kind, a, b):
    return {"fixed": f"{a!r}", "normal": f"normal:{a!r},{abs(b)!r}",
            "uniform": f"uniform:{min(a, b)!r},{max(a, b)!r}"}[kind]


NUMBERS = st.floats(-4.0, 4.0, allow_nan=False, allow_subnormal=False)


@budget(60)
@given(name=st.sampled_from(["base_tilt", "moment_tilt"]),
       kind=st.sampled_from(["fixed", "normal", "uniform"]), a=NUMBERS, b=NUMBERS)
def test_a_spread_is_flown_only_inside_its_keys_bound(name, kind, a, b):
    """Every spread is refused in one line naming it, or every value of its support (a normal's
    mean +- 8 sd) is one the scene key itself takes (scene/load.py, with the key's own bound)."""
    from levitron.scene.load import base_tilt, magnet_tilt
    from levitron.runtime.scan.spreads import parse_input, support
    spec = _spec(kind, a, b)
    why = _refusal(name, spec)
    lo, hi = support(parse_input(name, spec))
    if why is not None:
        assert spec in why and "\n" not in why
        bound = KEY_BOUNDS["plate.tilt" if name == "base_tilt" else "top.moment_tilt"]
        assert not (bound.admits(abs(lo) if name == "base_tilt" else lo)
                    and bound.admits(abs(hi) if name == "base_tilt" else hi))
        return
    for v in (lo, hi):
        assert KEY_BOUNDS["plate.tilt" if name == "base_tilt" else "top.moment_tilt"].admits(
            abs(v) if name == "base_tilt" else v)
        if 0 < abs(v) < 1e-12:          # below the scene's magnitude rule (units), not a bound
            continue
        if name == "base_tilt":
            base_tilt({"tilt": abs(v)})
        else:
            magnet_tilt({"moment_tilt": v})


@budget(40)
@given(kind=st.sampled_from(["fixed", "normal", "uniform"]), a=NUMBERS, b=NUMBERS,
       name=st.sampled_from(["mass", "strength"]))
def test_a_relative_spread_keeps_the_quantity_positive(kind, a, b, name):
    from levitron.runtime.scan.spreads import parse_input, support
    spec = "rel:" + _spec(kind, a / 2, b / 2)
    why = _refusal(name, spec)
    lo, _ = support(parse_input(name, spec))
    assert (why is None) == (lo > -1), (spec, why)
    if why is not None:
        assert spec in why and "non-positive" in why and "\n" not in why


# ---------------------------------------------------------------- no verdict without the physics

def test_past_window_is_no_verdict():
    from levitron.runtime.integrate.verdict import past_window
    assert past_window("completed", 0.01, 459.6, 1.6e-7, 1.55e-7) is not None
    assert past_window("completed", 116.0, 459.6, 461.5, 117.0) is None
    assert past_window("left_box", 0.01, 459.6, 1.6e-7, 1.55e-7) is None
    assert past_window("completed", 0.01, None, 1.6e-7, None) is None


def test_a_run_whose_spin_left_the_window_gives_no_verdict():
    """thesis_air with a decay time of 0.2 us said "levitating: yes" with its spin at 1e-7 rad/s and
    the adiabatic prediction of the fall at 0.16 us."""
    import levitron as lev
    r = lev.load("thesis_air", {"top.spin_decay_time": 2e-7}).simulate(1000, t_end=0.01).as_json()
    assert r["status"] == "completed" and r["levitating"] is None
    assert "lower critical spin" in r["untested"] and "t_end" in r["untested"]


# ---------------------------------------------------------------- impossible geometry

def test_a_magnet_offset_beyond_the_hover_height_is_geometry():
    """top.moment_offset larger than the hover height: 'math domain error' (exit 3), a raw ValueError."""
    import levitron as lev
    with pytest.raises(UserError, match="moment_offset.*hover height") as exc:
        lev.load("thesis_stable", {"top.moment_offset": 0.2}).stability()
    one_line(exc)


@pytest.fixture
def magpy():
    return pytest.importorskip("magpylib")


def test_magpylib_numbers_are_checked(magpy):
    """A NaN position was taken as centred, a NaN magnetisation went into the table, a Cuboid without
    a dimension was a raw TypeError, and any number of sources was taken."""
    from levitron import plate_from_magpylib
    from levitron.from_magpylib import MAX_SOURCES
    cube = dict(dimension=(0.1, 0.1, 0.02), magnetization=(0, 0, 1e6))
    bad = [(magpy.magnet.Cuboid(**cube, position=(math.nan, 0, 0)), "position"),
           (magpy.magnet.Cuboid(dimension=(0.1, 0.1, 0.02), magnetization=(0, 0, math.nan)), "magnetization"),
           (magpy.magnet.Cuboid(magnetization=(0, 0, 1e6)), "no dimension"),
           (magpy.magnet.Cylinder(dimension=(0.1, math.inf), magnetization=(0, 0, 1e6)), "dimension"),
           (magpy.current.Circle(diameter=0.1, current=math.nan), "current"),
           (magpy.Collection(*[magpy.current.Circle(diameter=0.1, current=1.0)
                               for _ in range(MAX_SOURCES + 1)]), str(MAX_SOURCES + 1))]
    for source, needle in bad:
        with pytest.raises(UserError, match=needle) as exc:
            plate_from_magpylib(source)
        one_line(exc)
    assert plate_from_magpylib(magpy.magnet.Cuboid(**cube))["parts"][0]["magnetization"] == 1e6


# ---------------------------------------------------------------- words as typed

@pytest.mark.parametrize("name,spec,never", [
    ("mass", "rel:-100%", "normal:0,-1"), ("mass", "rel:normal:0,-0.1", "'normal:0,-0.1'"),
    ("strength", "rel:uniform:0.1,-0.1", "'uniform:"),
])
def test_a_spread_refusal_quotes_the_input_as_typed(name, spec, never):
    from levitron.runtime.scan.spreads import parse_input
    with pytest.raises(UserError) as exc:
        parse_input(name, spec)
    text = one_line(exc)
    assert repr(spec) in text and never not in text, text


def test_a_bound_refusal_quotes_an_absolute_mass_as_typed():
    why = _refusal("mass", "normal:0.0515,0.01")
    assert "normal:0.0515,0.01" in why and "rel:" not in why, why
