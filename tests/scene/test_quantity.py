"""Numbers typed with a unit (scene/quantity.py): converted once to the key's SI unit, exactly the
double the SI number is; refused in a dimensionless scene, in another dimension or in any other shape;
a bare SI number that reads as grams meant warned of."""
from __future__ import annotations

import math
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from levitron.scene.checks import SceneError
from levitron.scene.load import load_scene
from levitron.scene.paths import SCENES_DIR
from levitron.scene.quantity import convert_scene, has_unit, setting_value, si_value

TWO_PI = 2 * math.pi


@pytest.fixture(scope="module", autouse=True)
def _pint_loaded():
    """pint's one registry (about a second of imports on first use) made before the tests time themselves."""
    si_value("1 m", "m", "warm-up")


@pytest.mark.parametrize("text,unit,si", [
    ("51.5 g", "kg", 0.0515), ("28.4g", "kg", 0.0284), ("3 mm", "m", 0.003), ("10 cm", "m", 0.1),
    ("30 Hz", "rad/s", TWO_PI * 30), ("30Hz", "rad/s", TWO_PI * 30), ("1800 rpm", "rad/s", TWO_PI * 30),
    ("0.39 T", "T", 0.39), ("390 mT", "T", 0.39), ("2 min", "s", 120.0), ("20 ms", "s", 0.02),
    ("2.2 g cm^2", "kg m^2", 2.2e-7), ("2.2 g*cm**2", "kg m^2", 2.2e-7), ("981 cm/s^2", "m/s^2", 9.81),
    ("28 degC", "degC", 28.0), ("300 K", "degC", 26.85), ("-0.2 %/K", "1/K", -0.002),
    ("0.0515 kg", "kg", 0.0515), ("188.5 rad/s", "rad/s", 188.5),
])
def test_a_quantity_is_the_double_its_si_number_is(text, unit, si):
    assert si_value(text, unit, "key") == si     # ==, not approx: the same double as the typed SI number


def test_a_spin_in_hz_or_rpm_is_an_angular_frequency_not_pints_radian_one():
    assert si_value("1 Hz", "rad/s", "spin") == TWO_PI
    assert si_value("60 rpm", "rad/s", "spin") == TWO_PI
    assert si_value("1 1/s", "rad/s", "spin") == TWO_PI        # cycles per second, as Hz
    assert si_value("90 deg", "rad", "tilt") == pytest.approx(math.pi / 2, rel=1e-15)


def test_only_a_relative_key_takes_a_percent():
    assert si_value("2 %", "", "field.tolerance", relative=True) == 0.02
    assert setting_value("0.0001 %", "tol") == pytest.approx(1e-6, rel=1e-15)
    with pytest.raises(SceneError, match="plain number and takes no unit"):
        si_value("2 %", "", "field.order")
    with pytest.raises(SceneError, match="is not a fraction"):
        si_value("2 rad", "", "launch.mass", relative=True)


@pytest.mark.parametrize("text,expected", [
    ("51.5 Hz", "does not convert to kg"), ("51.5 m", "does not convert to kg"),
    ("51.5 K", "a temperature is not kg"), ("51.5 gramz", "not a unit pint knows"),
])
def test_a_wrong_unit_is_one_line_naming_the_expected_unit(text, expected):
    with pytest.raises(SceneError, match=expected) as err:
        si_value(text, "kg", "top.mass")
    assert "\n" not in str(err.value) and "kg" in str(err.value)


@pytest.mark.parametrize("text", [
    "1 __import__('os').system('true')", "1 m; rm", "1 (m)", "1 m m 2", "1 2 m", "1 m + 1 mm",
    "1e3 m " * 30, "1 m\nx", "lambda: 1", "1 m.__class__",
])
def test_anything_but_one_number_and_one_unit_is_refused_before_pint_reads_it(text):
    assert not has_unit(text)
    with pytest.raises(SceneError):
        si_value(text, "m", "plate.radius")


def test_a_setting_takes_its_flags_unit_and_an_unknown_setting_none():
    assert setting_value("30 Hz", "spin") == TWO_PI * 30
    assert setting_value("15 cm", "height") == 0.15
    with pytest.raises(SceneError, match="takes no unit"):
        setting_value("3 s", "n_out")


def _params(*overrides):
    return load_scene("thesis", list(overrides))


@pytest.mark.parametrize("typed,si", [("top.mass=28.4 g", "top.mass=0.0284"),
                                      ("top.mass=\"28.4 g\"", "top.mass=0.0284"),
                                      ("plate.radius=100mm", "plate.radius=0.1"),
                                      ("plate.hole=3 cm", "plate.hole=0.03")])
def test_set_with_a_unit_is_the_si_scene_bit_for_bit(typed, si):
    a, b = _params(typed), _params(si)
    assert a.params == b.params and a.scene_hash() == b.scene_hash() and a.data == b.data


def test_a_scene_files_strings_with_units_are_its_si_numbers(tmp_path):
    text = (SCENES_DIR / "thesis.toml").read_text()
    typed = text.replace("mass = 0.0284 ", 'mass = "28.4 g" ').replace("radius = 0.10 ", 'radius = "10 cm" ')
    assert typed.count('"28.4 g"') == typed.count('"10 cm"') == 1
    path = tmp_path / "thesis.toml"
    path.write_text(typed)
    a, b = load_scene(path), load_scene("thesis")
    assert a.params == b.params and a.scene_hash() == b.scene_hash()


@pytest.mark.parametrize("dimensionless", ["g=1", "units=dimensionless"])
def test_a_dimensionless_scene_refuses_a_unit_in_one_line(dimensionless):
    with pytest.raises(SceneError, match="this scene is dimensionless") as err:
        _params(dimensionless, "top.mass=28.4 g")
    assert "\n" not in str(err.value)
    assert _params("g=1", "top.mass=0.0284").params["m"] == 0.0284    # a bare number as ever


def test_a_bare_mass_heavy_in_kg_is_warned_of_as_grams_meant():
    notes = _params("top.mass=51.5").notes
    assert [n for n in notes if n.startswith("warning:")] == [
        "warning: top.mass = 51.5 kg is heavy for a top: did you mean «51.5 g»? (a number without a unit is SI)"]
    assert not [n for n in _params("top.mass=0.0515").notes if n.startswith("warning:")]
    assert not [n for n in _params("top.mass=51.5 kg").notes if n.startswith("warning:")]   # said so
    assert not [n for n in _params("g=1", "top.mass=51.5").notes if n.startswith("warning:")]
    assert any("30 mm" in n for n in _params("plate.radius=30").notes)


def test_text_that_is_no_quantity_is_left_to_the_validator():
    data = {"top": {"mass": "0.05", "A": "heavy"}, "plate": {"kind": "expression", "phi0": "2 z"},
            "launch": {"spin": "normal:400,10"}, "name": "x"}
    assert convert_scene(data) == []
    assert data["top"] == {"mass": "0.05", "A": "heavy"} and data["plate"]["phi0"] == "2 z"
    assert data["launch"]["spin"] == "normal:400,10"
    with pytest.raises(SceneError, match="is not a number"):
        _params('top.mass="0.05"')


UNITS = {"g": (Fraction(1, 1000), 0, "kg"), "mm": (Fraction(1, 1000), 0, "m"), "cm": (Fraction(1, 100), 0, "m"),
         "ms": (Fraction(1, 1000), 0, "s"), "min": (Fraction(60), 0, "s"), "mT": (Fraction(1, 1000), 0, "T"),
         "Hz": (Fraction(1), 1, "rad/s"), "rpm": (Fraction(1, 60), 1, "rad/s"), "deg": (Fraction(1, 360), 1, "rad"),
         "kg": (Fraction(1), 0, "kg"), "m": (Fraction(1), 0, "m")}


@settings(max_examples=60, deadline=None)
@given(st.decimals(min_value="-1e6", max_value="1e6", allow_nan=False, allow_infinity=False, places=4),
       st.sampled_from(sorted(UNITS)), st.sampled_from(["", " ", "  "]))
def test_value_times_unit_round_trips_to_si(value, unit, space):
    """Any decimal times a unit is, in SI, the exact product rounded once (2 pi the double 2 pi)."""
    factor, turns, si_unit = UNITS[unit]
    text = f"{value}{space}{unit}"
    exact = Fraction(str(value)) * factor * Fraction(TWO_PI) ** turns
    got = si_value(text, si_unit, "key")
    assert got == float(exact)
    assert got == pytest.approx(float(value) * float(factor) * TWO_PI ** turns, rel=1e-15, abs=1e-300)
