"""The human view: every command's plain output has units and no number with more than 6
significant digits; progress never reaches stdout; --version; a dimensionless scene in its own units."""
from __future__ import annotations

import io
import re

import pytest

from levitron.runtime.cli import main as cli

from levitron.runtime.ui import progress
from levitron.runtime.ui.human import Units, sig
from levitron.runtime.ui.plain_text import shown

# a number as printed: not part of a word, a path or a hash
NUMBER = re.compile(r"(?<![\w/.])(\d+(?:\.\d+)?)(?:e[-+]?\d+)?(?![\w/]|\.\d)")
UNITS = re.compile(r"\d (cm|mm|um|m|g|kg|mT|rad/s|Hz|rpm|rad|deg|s|ms|us|ns|kg m\^2|m/s\^2|N)\b")


def significant_digits(number: str) -> int:
    digits = number.replace(".", "").lstrip("0")
    if "." not in number:
        digits = digits.rstrip("0")
    return len(digits)


def too_precise(text: str) -> list[str]:
    return [m.group(0) for m in NUMBER.finditer(text) if significant_digits(m.group(1)) > 6]


def test_the_digit_counter_fails_on_long_numbers():
    assert too_precise("z: 0.07620000003641508") == ["0.07620000003641508"]
    assert too_precise("z 15.74 cm, 26200 rpm, 1.5e-10, hash bab0a6e68428") == []


COMMANDS = {
    "equilibrium": ["equilibrium", "ring_magnet"],
    "stability": ["stability", "thesis"],
    "simulate": ["simulate", "thesis_stable", "--spin", "1000", "--tilt", "0.02", "--tilt-azimuth",
                 "0.5", "--t-end", "0.5"],
    "info": ["info", "square"],
    "field": ["field", "ring_magnet", "--at", "0.01,0,0.05", "--at", "0,0,0.1"],
    "optimize": ["optimize", "thesis", "--fit-height", "0.0762"],
    "scan": ["scan", "thesis_stable", "--spin", "400:2000:3", "--tilt", "0.01:0.05:2", "--t-end", "0.3"],
    "derive": ["derive", "thesis"],
}


@pytest.mark.parametrize("name", list(COMMANDS))
def test_human_output_has_units_and_sensible_digits(name, capsys):
    assert cli.main(COMMANDS[name]) == 0
    out = capsys.readouterr().out
    assert out.strip()
    assert UNITS.search(out), f"`levitron {name}` shows no unit:\n{out}"
    assert too_precise(out) == [], f"`levitron {name}` prints too many digits:\n{out}"
    assert "{" not in out.splitlines()[0]           # an answer, not a JSON dump


def test_dimensionless_scene_in_its_own_units(capsys):
    """g = 1 marks a scene as dimensionless: no cm, g, Hz or rpm anywhere in the view."""
    assert cli.main(["equilibrium", "thesis", "--set", "g=1"]) == 0
    out = capsys.readouterr().out
    assert "dimensionless scene" in out
    assert not re.search(r"\d (cm|mm|m|g|kg|Hz|rpm)\b", out), out
    assert too_precise(out) == []


def test_json_stays_si_and_complete(capsys):
    assert cli.main(COMMANDS["simulate"] + ["--json"]) == 0
    import json
    r = json.loads(capsys.readouterr().out)
    assert r["tilt_azimuth"] == 0.5
    assert r["z_s"] < 1                             # metres, not cm
    dev = r["conserved_max_deviation"]
    assert set(dev) == {"energy", "L_z", "L_n"} and 0 <= dev["L_z"] < 1e-6


def test_units_rule():
    si, dim = Units.of(9.81), Units.of(1.0)
    assert (si.length(0.1574), si.mass(0.0515), si.length(0.0013)) == ("15.74 cm", "51.5 g", "1.3 mm")
    assert si.rate(1000) == "1000 rad/s (159 Hz, 9550 rpm)"
    assert (dim.length(0.1574), dim.mass(0.0515)) == ("0.1574", "0.0515")   # no cm or g
    assert "Hz" not in dim.rate(1000)
    assert shown("at z_s = ‹0.157391|m› the top, band ‹[0.0994772, 0.110198]|m›", si) == \
        "at z_s = 15.74 cm the top, band 9.948-11.02 cm"
    assert shown("hovers at z = ‹0.3344|m›, band ‹[0.09948, 0.1102]|m›, mass in ‹[0.494, 0.5149]|kg›", dim) == \
        "hovers at z = 0.3344, band 0.09948-0.1102, mass in 0.494-0.5149"
    assert [sig(v) for v in (26163.68, 0.0762, 1.5141e-10, 0)] == ["26160", "0.0762", "1.514e-10", "0"]


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_progress_goes_to_stderr_only(monkeypatch, capsys):
    """On a terminal the bar is drawn on stderr; stdout holds only the answer."""
    fake_err = _Tty()
    monkeypatch.setattr("sys.stderr", fake_err)
    monkeypatch.delenv("LEVITRON_PROGRESS", raising=False)
    assert cli.main(COMMANDS["scan"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("levitating at ") and "\x1b" not in out and "eta" not in out
    assert fake_err.getvalue(), "no progress drawn on a terminal's stderr"


@pytest.mark.parametrize("flag", ["--json", "--quiet"])
def test_progress_off(flag, monkeypatch, capsys):
    fake_err = _Tty()
    monkeypatch.setattr("sys.stderr", fake_err)
    assert cli.main(COMMANDS["equilibrium"] + [flag]) == 0
    assert "\x1b" not in fake_err.getvalue()
    assert not progress.active()


def test_progress_off_without_terminal():
    progress.enable()
    with progress.task("x", total=3) as tick:          # pytest's stderr is not a terminal
        tick()
    assert not progress.active()


def test_version(capsys):
    """`levitron --version` answers before the command modules load (issue: 1 s of imports)."""
    assert cli.main(["--version"]) == 0
    assert re.fullmatch(r"levitron \d+\.\d+\.\d+\n", capsys.readouterr().out)
    with pytest.raises(SystemExit) as exc:          # the parser's own flag, e.g. after an option
        cli.main(["--version", "--version"])
    assert exc.value.code == 0


def test_every_command_has_an_example(capsys):
    from levitron.runtime.cli.commands import COMMANDS as NAMES
    for name in NAMES:
        with pytest.raises(SystemExit):
            cli.main([name, "--help"])
        assert f"example:\n  levitron {name} " in capsys.readouterr().out


def test_tilt_azimuth_turns_the_axis_only():
    """--tilt-azimuth: the axis n = (sin t cos az, sin t sin az, cos t); by the plate's axial
    symmetry the energy and L_z do not depend on az, the tilt and offset are kept."""
    import math

    import numpy as np

    from levitron.scene.load import load_scene
    from levitron.runtime.physics.equilibrium.finder import hover_height
    from levitron.runtime.model.load import load_model
    from levitron.runtime.simulate.invariants import angular_momentum_z, tilt_of
    from levitron.runtime.simulate.rotations import ANGLES, coordinates_of, rotation_bs
    from levitron.runtime.simulate.start import initial_state
    model = load_model(load_scene("thesis_stable"))
    part, z_s, t = model.part("full"), hover_height(model), 0.05
    ref = initial_state(part, z_s, 1000.0, t, 0.0)
    kind = coordinates_of(part)
    for az in (0.0, 0.7, math.pi, -2.0):
        x = initial_state(part, z_s, 1000.0, t, 0.0, azimuth=az)
        ang = [x[list(part.states).index(a)] for a in ANGLES[kind]]
        n = rotation_bs(kind, ang)[:, 2]
        assert np.allclose(n, [math.sin(t) * math.cos(az), math.sin(t) * math.sin(az), math.cos(t)],
                           atol=1e-14)
        assert math.isclose(part.energy(x), part.energy(ref), rel_tol=1e-12)
        assert math.isclose(angular_momentum_z(part, x), angular_momentum_z(part, ref), rel_tol=1e-12)
        assert math.isclose(float(tilt_of(part, x)[0]), t, rel_tol=1e-12)


def test_top_level_help_lists_every_command(capsys):
    """`levitron --help` builds every command's parser (a '%' in a help text broke it once)."""
    from levitron.runtime.cli.commands import COMMANDS as NAMES
    with pytest.raises(SystemExit) as exc:
        cli.main(["--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert all(name in out for name in NAMES)


def test_a_one_shot_command_imports_only_its_own_module():
    """`levitron stability` parses with its own command module only (no design, scan or report)."""
    import subprocess
    import sys
    code = ("import sys; from levitron.runtime.cli import main as m; m.main(['stability', 'thesis_stable', '--json']); "
            "print(sorted(k for k in sys.modules if k.startswith('levitron.runtime.cli.commands.')), file=sys.stderr)")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert res.returncode == 0, res.stderr
    commands = "levitron.runtime.cli.commands"
    assert f"{commands}.stability" in res.stderr and f"{commands}.report" not in res.stderr


def test_top_level_help_is_the_full_parsers_without_importing_the_commands(monkeypatch):
    """`levitron --help` reads each command's help line from its source (runtime.cli.main.
    command_help): the same text as the parser built from the imported modules, and no command
    module, numpy or casadi is loaded for it."""
    import os
    import subprocess
    import sys

    from levitron.runtime.cli.main import build_parser
    monkeypatch.setenv("COLUMNS", "100")             # argparse wraps to the terminal's width
    full = build_parser().format_help()
    assert build_parser(overview=True).format_help() == full
    code = ("import sys\nfrom levitron.runtime.cli import main as m\ntry:\n    m.main(['--help'])\n"
            "except SystemExit:\n    pass\n"
            "print(sorted(k for k in sys.modules if k.startswith(('levitron.runtime.cli.commands.', 'numpy', "
            "'casadi'))), file=sys.stderr)")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False,
                         env={**os.environ, "COLUMNS": "100"})
    assert res.returncode == 0, res.stderr
    assert res.stdout == full
    assert res.stderr.strip() == "[]", res.stderr


def test_a_narrow_span_of_rates_keeps_its_ends_apart():
    """`scan thesis_stable --spin 459.6151:459.6161:5` (1e-6 of the lower critical spin) printed
    'stays up for spin 459.6-459.6 rad/s (73.2-73.2 Hz, 4390-4390 rpm)': a span shown as a point.
    The digits grow (up to the 6 this view allows) until the two ends differ."""
    text = Units(si=True).rate_span(459.6151, 459.6161)
    assert text == "459.615-459.616 rad/s (73.15-73.1502 Hz, 4389-4389.01 rpm)", text
    assert Units(si=True).rate_span(459.6, 2740.0) == "459.6-2740 rad/s (73.1-436 Hz, 4390-26200 rpm)"
    assert Units(si=False).rate_span(30.28281, 30.28289) == "30.2828-30.2829 rad/time"


def test_long_durations_read_in_hours_days_and_years():
    """A flight of 7252946 min read as "7252946 min": above an hour, hours; above a day, days."""
    from levitron.runtime.ui.human import duration
    assert duration(150) == "2 min 30 s" and duration(179.6) == "3 min 0 s"
    assert duration(3599.7) == "1 h 0 min" and duration(18720) == "5 h 12 min"
    assert duration(2.5 * 86400) == "2.5 days" and duration(7252946 * 60) == "13.8 years"
