"""Input is never dropped or changed without a word, and the CLI and the API check it the same way
(input dropped or changed without a word, and the API's raw Python errors).

Before: a newline in a --set value dropped the rest; the API wrote its overrides as f'{key}="{value}"'
(a quote or a newline rewrote the scene); extra CSV columns and a key overridden twice in a row were
taken silently; the API's fit took a negative sigma and its scan a NaN spin that the CLI refused;
load(123), simulate(spin="1000"), scan([]) raised TypeError / IndexError; a scan of 1e12 points
allocated its axes before refusing them.
"""
from __future__ import annotations

import math
import time

import pytest

import levitron
import levitron.study
from levitron.scene.load import SceneError, load_scene
from levitron.scene.overrides import override_text, parse_override
from levitron.runtime.design import fit, measurements
from levitron.runtime.cli.main import main
from levitron.runtime.errors import UserError
from levitron.runtime.scan.stability_map import scan
from levitron.runtime.scan.grid import parse_range
from levitron.runtime.design.scene_keys import Vary
from levitron.runtime.simulate.run import simulate

HOSTILE = ['x"\nv2 = "y', "a\\b", "line1\nline2", 'quote " and \' both', "tab\there", "#not a comment",
           "]", "\"\"\"", "é ü ∞"]


def _cli(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("value", ["0.03\nplate.hole = 0.05", "0.03\r", "0.03\x00", "0.03\n"])
def test_a_control_character_in_a_set_value_is_refused(value, capsys):
    """Before: `--set "top.mass=0.03<newline>plate.hole=0.05"` set the mass and dropped the rest."""
    code, out, err = _cli(["info", "thesis", "--set", f"top.mass={value}", "--json"], capsys)
    assert code == 2 and out == "", (code, out, err)
    assert len(err.strip().splitlines()) == 1 and "control character" in err, err


def test_an_unbalanced_quote_is_not_taken_as_a_bare_word():
    with pytest.raises(SceneError, match="not a TOML value"):
        parse_override('reference.source="abc')
    assert parse_override("plate.kind=disk") == (["plate", "kind"], "disk")          # bare words stay
    assert parse_override("model.coordinates=euler-zxz")[1] == "euler-zxz"


@pytest.mark.parametrize("value", HOSTILE)
def test_the_api_writes_overrides_with_a_toml_writer(value):
    """The text the API hands to the scene reader gives back exactly the value (before: 'x"\\nv2 = "y'
    became 'x', the rest a new key)."""
    (text,) = levitron.study.override_texts({"reference.source": value})
    assert "\n" not in text
    assert parse_override(text) == (["reference", "source"], value)
    scene = load_scene("thesis", [text])
    assert scene.data["reference"]["source"] == value


@pytest.mark.parametrize("value", [0.05, -3, True, ["reduced", "full"], 1e-300])
def test_override_text_round_trips_every_kind_of_value(value):
    assert parse_override(override_text("a.b", value)) == (["a", "b"], value)


def test_override_text_refuses_what_is_not_one_value():
    for key, value in (("a.b", {"c": 1}), ("a b", 1), ("a.b", object()), ("", 1)):
        with pytest.raises(SceneError):
            override_text(key, value)


# ---------------------------------------------------------------- fit CSVs and rows

@pytest.mark.parametrize("text,message", [
    ("quantity,value,sigma,temperature\nz_s,0.1,1e-4,20\n", "unknown column 'temperature'"),
    ("quantity,value,sigma\nz_s,0.1,1e-4,20\n", "4 fields for 3 columns"),
    ("quantity,value,sigma,sigma\nz_s,0.1,1e-4,1e-3\n", "appears twice"),
    ("quantity,value,sigma,overrides\nz_s,0.1,1e-4,top.mass=0.05;top.mass=0.06\n", "given twice"),
    ("quantity,value,sigma,overrides\nz_s,0.1,1e-4,top.mass=nan\n", "top.mass"),
    ("quantity,value,sigma\nz_s,0.1,1e-320\n", "too small"),
    ("quantity,value,sigma\nz_s,0.1,-1e-4\n", "positive"),
    ("quantity,value,sigma\nz_s,nan,1e-4\n", "finite"),
    ("quantity,value,sigma\n", "no data rows"),
])
def test_fit_csv_problems_are_one_line(tmp_path, text, message):
    f = tmp_path / "d.csv"
    f.write_text(text)
    with pytest.raises(UserError) as err:
        measurements.read_rows(f)
    assert message in str(err.value) and "\n" not in str(err.value), str(err.value)


@pytest.mark.parametrize("rows,message", [
    ([measurements.Row("z_s", 0.1, -1e-4)], "positive"),
    ([measurements.Row("z_s", 0.1, 0.0)], "positive"),
    ([measurements.Row("z_s", 0.1, math.nan)], "finite"),
    ([measurements.Row("z_s", 0.1, 1e-320)], "too small"),
    ([measurements.Row("height", 0.1, 1e-4)], "quantity 'height'"),
    ([measurements.Row("z_s", "0.1", 1e-4)], "not a number"),
    ([measurements.Row("z_s", 0.1, 1e-4, (("top.mass", 0.05), ("top.mass", 0.06)))], "given twice"),
    ([], "no data rows"),
    ("z_s,0.1,1e-4", "CSV path or a list"),
])
def test_the_api_fit_checks_rows_as_the_csv_reader_does(rows, message):
    """levitron.runtime.design.fit.fit (what levitron's Study.fit calls) checks before any model work."""
    with pytest.raises(UserError, match=message):
        fit.fit(None, rows, [Vary("plate.murho", -0.003, -0.002)])


def test_the_api_vary_is_checked_as_the_cli_vary():
    for box in ((-1.0, 1.0), (2.0, 1.0), (math.nan, 1.0), ("a", 1.0)):
        with pytest.raises(UserError):
            Vary.checked("top.mass", *box, where="vary")
    with pytest.raises(UserError, match="straddle"):
        Vary.parse("top.mass=-1:1")


# ---------------------------------------------------------------- scan and simulate inputs

@pytest.mark.parametrize("spins,others,message", [
    ([math.nan, 1000.0], [0.01], "spin: every value must be finite"),
    ([], [0.01], "non-empty"),
    ([1000.0], [math.inf], "tilt: every value must be finite"),
    ("1000", [0.01], "list of numbers"),
    ([["a"]], [0.01], "number"),
])
def test_the_api_scan_checks_the_grid_as_the_cli_does(spins, others, message):
    """levitron.runtime.scan.stability_map.scan (Study.scan and the CLI) refuses before touching the model."""
    with pytest.raises(UserError, match=message):
        scan(None, spins, "tilt", others)


@pytest.mark.parametrize("kwargs,param,message", [
    ({"spin": "1000"}, "spin", "--spin = '1000' is not a number"), ({"spin": math.nan}, "spin", "--spin"),
    ({"spin": 1000.0, "tilt": math.inf}, "tilt", "--tilt"), ({"spin": 1000.0, "tilt": 1e300}, "tilt", "--tilt"),
    ({"spin": 1000.0, "t_end": math.nan}, "t_end", "--t-end"), ({"spin": 1000.0, "n_out": 2.5}, "n_out", "--n-out"),
    ({"spin": 1000.0, "tol": "tight"}, "tol", "--tol"), ({"spin": True}, "spin", "--spin"),
])
def test_simulate_checks_its_numbers_before_the_model(kwargs, param, message):
    """The UserError carries the setting and the value it refused (runtime/errors.py), and the
    command line words it with its flag."""
    with pytest.raises(UserError) as e:
        simulate(None, **kwargs)
    assert e.value.param == param and e.value.words("cli").startswith(message), e.value.words("cli")
    given = kwargs[param]
    assert e.value.value is given or e.value.value == given or math.isnan(e.value.value)


def test_a_huge_grid_is_refused_before_it_is_built():
    """Before: np.linspace(0, 1, 10**12) tried to allocate 7 TiB (MemoryError, exit 3)."""
    t0 = time.perf_counter()
    with pytest.raises(UserError, match="too many"):
        parse_range("0:1:1000000000000", "spin")
    assert time.perf_counter() - t0 < 1.0


def test_a_huge_product_grid_is_refused_before_it_is_built(capsys):
    t0 = time.perf_counter()
    code, out, err = _cli(["scan", "thesis_stable", "--spin", "1:2:100000", "--tilt", "0:0.1:100000"], capsys)
    assert code == 2 and "too many" in err and len(err.strip().splitlines()) == 1, err
    assert time.perf_counter() - t0 < 5.0


def test_the_api_exports_its_error_types():
    assert levitron.UserError is UserError and levitron.SceneError is SceneError
    for bad in (123, None, 1.5):
        with pytest.raises(levitron.UserError, match="scene must be"):
            levitron.load(bad)
    with pytest.raises(levitron.UserError, match="mapping"):
        levitron.load("thesis", [("top.mass", 0.05)])


# ---------------------------------------------------------------- the API raises its own errors

VARY = {"plate.murho": (-0.003, -0.002)}
API_CALLS = {
    "value-not-text": lambda s: s.value(5),
    "value-unknown-key": lambda s: s.value("bogus.key"),
    "p_of-nan": lambda s: s.p_of({"top.mass": math.nan}),
    "gradient-unknown-quantity": lambda s: s.gradient("bogus", ["top.mass"]),
    "gradient-unknown-key": lambda s: s.gradient("z_s", ["top.bogus"]),
    "gradient-keys-a-string": lambda s: s.gradient("z_s", "top.mass"),
    "simulate-spin-text": lambda s: s.simulate(spin="1000"),
    "simulate-tilt-inf": lambda s: s.simulate(spin=1000.0, tilt=math.inf),
    "simulate-integrator-number": lambda s: s.simulate(spin=1000.0, integrator=3),
    "scan-no-spins": lambda s: s.scan([], "tilt", [0.1]),
    "scan-unknown-axis": lambda s: s.scan([1000.0], "bogus", [0.1]),
    "scan-nan-spin": lambda s: s.scan([math.nan], "tilt", [0.1]),
    "fit-sigma-0": lambda s: s.fit([measurements.Row("z_s", 0.1, 0.0)], VARY),
    "fit-sigma-nan": lambda s: s.fit([measurements.Row("z_s", 0.1, math.nan)], VARY),
    "fit-no-rows": lambda s: s.fit([], VARY),
    "fit-unknown-quantity": lambda s: s.fit([measurements.Row("height", 0.1, 1e-4)], VARY),
    "fit-vary-not-numbers": lambda s: s.fit([measurements.Row("z_s", 0.1, 1e-4)], {"plate.murho": (1, "x")}),
    "fit-vary-empty": lambda s: s.fit([measurements.Row("z_s", 0.1, 1e-4)], {}),
    "optimize-unknown-objective": lambda s: s.optimize("bogus", {"top.mass": (0.05, 0.052)}),
    "load-override-a-table": lambda s: levitron.load("thesis", {"top": {"mass": 1}}),
}


@pytest.mark.parametrize("name", sorted(API_CALLS))
def test_the_api_raises_its_own_one_line_errors(name, study):
    """Before: TypeError, KeyError, IndexError, ZeroDivisionError, "math domain error"."""
    with pytest.raises(levitron.UserError) as err:
        API_CALLS[name](study)
    assert "\n" not in str(err.value) and str(err.value)
