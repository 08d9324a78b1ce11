"""A dimensionless scene (`units = "dimensionless"`, g = 1) shows no SI unit
anywhere: every command's plain text, every plot's text (titles, axis labels, legends, colour
bars) and the report's page. Wall times stay seconds: they are the computer's, not the scene's."""
from __future__ import annotations

import html
import json
import re

import matplotlib.figure
import matplotlib.text
import pytest

from levitron.runtime.cli import main as cli

from tests.helpers.dimensionless import SCENE, SI, si_units


def test_the_grep_finds_si_units():
    assert si_units("z 15.74 cm, spin (rad/s), t_end = 208 s, moment -1 A m^2, 3 N/m, v 0.1 m/s") == \
        ["cm", "s", "A m^2", "N/m", "m/s", "(rad/s)"]
    assert si_units("30.28-119.1 rad/time, tilt 0.01 rad (0.573 deg), 417 ms of wall time, "
                    "height (fraction of z_s), z 0.9948-1.102") == []


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    path = tmp_path_factory.mktemp("dimless") / "unit_annulus.toml"
    path.write_text(SCENE)
    return str(path)


@pytest.fixture
def plot_texts(monkeypatch):
    """Every text of every figure saved while the test runs."""
    seen = []
    save = matplotlib.figure.Figure.savefig

    def recording(fig, *a, **k):
        seen.extend(t.get_text() for t in fig.findobj(matplotlib.text.Text) if t.get_text())
        return save(fig, *a, **k)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", recording)
    return seen


COMMANDS = {
    "info": [],
    "equilibrium": ["--plot", "{tmp}/eq.png"],
    "stability": [],
    "stability-height": ["--height", "1.05"],
    "field": ["--at", "0.1,0,0.5"],
    "simulate": ["--spin", "60", "--tilt", "0.01", "--t-end", "20", "--plot", "{tmp}/sim.png"],
    "scan-tilt": ["--spin", "30:110:3", "--tilt", "0.01:0.05:2", "--out", "{tmp}/map.png"],
    "scan-mass": ["--spin", "30:110:3", "--mass", "0.98:1.03:3", "--t-end", "20", "--out", "{tmp}/m.png"],
    "scan-height": ["--spin", "30:110:3", "--height", "-0.1:0.1:3", "--t-end", "20", "--out", "{tmp}/h.png"],
    "optimize": ["--maximize", "spin-range", "--vary", "top.mass=0.98:1.01"],
    # 2e-6 to 4e-6 below the largest mass that hovers (1.0199985): the vanishing-stiffness warning
    "optimize-edge": ["--maximize", "spin-range", "--vary", "top.mass=1.0199945:1.0199965"],
    "optimize-fit-height": ["--fit-height", "1.0"],
    "optimize-launch": ["--maximize", "launch-odds", "--vary", "top.mass=0.99:1.0", "--n", "12", "--t-end", "20"],
    "trim": ["--n", "12", "--t-end", "20"],
    # a top too heavy to hover: the warnings name the masses that hover
    "trim-heavy": ["--set", "top.mass=1.05", "--n", "12", "--t-end", "20"],
    "report": ["--out", "{tmp}/r.html"],
    "launch": ["--n", "12", "--t-end", "20", "--out", "{tmp}/launch.png", "--save", "{tmp}/launch.csv"],
    "figures": ["--out", "{tmp}/figs", "--quick"],
}


@pytest.mark.parametrize("name", list(COMMANDS))
def test_no_si_unit_in_a_dimensionless_scene(name, scene, tmp_path, plot_texts, capsys):
    argv = [name.split("-")[0], scene] + [a.format(tmp=tmp_path) for a in COMMANDS[name]]
    assert cli.main(argv) == 0, capsys.readouterr().err
    out = capsys.readouterr().out
    assert "dimensionless scene" in out or name == "figures"
    texts = [out, *plot_texts]
    if name == "report":
        page = (tmp_path / "r.html").read_text()
        # the embedded scene file is the author's text (its key `A` is no ampere); the script draws
        # the animation, whose drawn text tests/runtime/report/test_teacher_page.py reads in Chromium
        page = re.sub(r"<img[^>]*>|<style>.*?</style>|<script>.*?</script>|<pre class=\"toml\".*?</pre>", "",
                      page, flags=re.S)
        texts.append(html.unescape(re.sub(r"<[^>]+>", "\n", page)))
    if name == "optimize-edge":
        assert "warning: the optimum sits at vanishing stiffness" in out
    if name == "figures":      # 3.2 and 3.3 are the thesis's solver comparison on a unit circle
        assert plot_texts
    found = [u for t in texts for u in si_units(t)]
    assert found == [], f"`levitron {' '.join(argv)}` shows SI units {found}:\n" + "\n".join(texts)


def _sentences(answer, path=""):
    """(key path, text) of every string of a JSON answer but the provenance (paths, the command
    typed) and the report's `rebuild.toml` (the author's scene file, whose key `A` is no ampere)."""
    if isinstance(answer, dict):
        for k, v in answer.items():
            if k not in ("provenance", "toml"):
                yield from _sentences(v, f"{path}.{k}")
    elif isinstance(answer, list):
        for i, v in enumerate(answer):
            yield from _sentences(v, f"{path}[{i}]")
    elif isinstance(answer, str):
        yield path, answer


@pytest.mark.parametrize("name", list(COMMANDS))
def test_no_si_unit_in_a_dimensionless_scenes_json(name, scene, tmp_path, capsys):
    """The JSON's sentences (reasons, notes, warnings) show a dimensionless scene's quantities in
    its units too: the runtime writes them as quantity markers (runtime/words.py `si`) that the
    command shows in the scene's units. Before, its JSON read "at z_s = 1.99539 m" and "k = 3e-06
    N/m" while the plain view read "1.995"."""
    argv = [name.split("-")[0], scene] + [a.format(tmp=tmp_path) for a in COMMANDS[name]] + ["--json"]
    assert cli.main(argv) == 0, capsys.readouterr().err
    answer = json.loads(capsys.readouterr().out)
    found = [(k, text, si_units(text)) for k, text in _sentences(answer) if si_units(text)]
    assert found == [], f"`levitron {' '.join(argv)}` shows SI units in its JSON: {found}"


def test_an_si_scenes_json_keeps_its_units(capsys):
    """The same check finds the units of an SI scene's JSON sentences (so it can fail)."""
    assert cli.main(["stability", "thesis_stable", "--height", "0.15", "--json"]) == 0
    answer = json.loads(capsys.readouterr().out)
    assert [u for _, text in _sentences(answer) for u in si_units(text)], answer


def test_no_si_unit_in_the_apis_results(scene):
    """The Python API's results (their repr and message) show the scene's units too; the same
    results of an SI scene keep theirs (the check can fail)."""
    import levitron as lev
    with pytest.raises(lev.UserError) as too_heavy:       # a message of the runtime, in the scene's units
        lev.load(scene, {"top.mass": 5.2}).simulate(40.0)
    assert "too heavy" in str(too_heavy.value) and si_units(str(too_heavy.value)) == []
    study = lev.load(scene)
    results = [study.equilibria(), *study.equilibria().equilibria, study.stability(),
               study.simulate(40.0, t_end=5.0), study.simulate_many([30.0, 40.0], t_end=5.0),
               study.launch(n=6, t_end=5.0)]
    texts = [t for r in results for t in (repr(r), r.message if hasattr(r, "message") else "")]
    assert all(si_units(t) == [] for t in texts), [(t, si_units(t)) for t in texts if si_units(t)]
    si = lev.load("thesis_stable")
    assert si_units(repr(si.stability())) and si_units(repr(si.equilibria()))
    odds = lev.load("thesis_air").launch(n=6, t_end=2.0)
    assert si_units(repr(odds)) and si_units(odds.message)


def test_no_si_unit_in_a_dimensionless_scenes_error_line(scene, capsys):
    """The runtime's error messages write their quantities as markers (runtime/words.py `si`); the
    command line shows them in a dimensionless scene's units. An SI scene's keep theirs."""
    assert cli.main(["simulate", scene, "--set", "top.mass=5.2", "--spin", "40"]) == 2
    err = capsys.readouterr().err
    assert "too heavy" in err and si_units(err) == [], err
    assert cli.main(["simulate", "thesis_stable", "--set", "top.mass=0.06", "--spin", "40"]) == 2
    assert si_units(capsys.readouterr().err)


ERRORS = {       # a refusal on a dimensionless scene, and what its one line must say
    "field-no-point": (["field"], "no point given"),
    "field-bad-point": (["field", "--at", "1,2"], "is not a point"),
    "field-far": (["field", "--at", "1e9,0,0"], "plate sizes"),
    "step-longer-than-run": (["simulate", "--spin", "60", "--integrator", "rk4", "--step", "10",
                              "--t-end", "1"], "longer than the run"),
    "offset-outside-box": (["simulate", "--spin", "60", "--offset", "5"], "outside the box"),
    "run-too-long": (["simulate", "--spin", "60", "--t-end", "1e9"], "budget cap"),
    "negative-run": (["simulate", "--spin", "60", "--t-end", "-1"], "positive run length"),
    "no-hover-height": (["stability", "--height", "1e-9"], "no top hovers"),
    "launch-mass": (["launch", "--mass", "normal:100,1"], "reads as the mass in scene units"),
    "negative-box": (["simulate", "--spin", "60", "--box", "-1"], "positive number in scene units"),
    "scan-mass": (["scan", "--spin", "30:60:2", "--mass", "-1:1:2"], "must be positive"),
}


@pytest.mark.parametrize("name", list(ERRORS))
def test_no_si_unit_in_a_dimensionless_scenes_refusals(name, scene, capsys):
    """Every refusal speaks the scene's units: its quantities are markers (runtime/words.py) that
    the command line shows in them ("--step 10 time units", "in scene units"; before, "in metres")."""
    argv, says = ERRORS[name]
    assert cli.main([argv[0], scene, *argv[1:]]) == 2
    err = capsys.readouterr().err
    assert re.search(says, err) and si_units(err) == [], err


def test_no_si_unit_in_design_and_scan_results(scene):
    """The design and scan results (repr, message) and the units their JSON names are the scene's:
    before, a dimensionless scene's optimum read "spin-range 25.3 rad/s" and its map "t_end 20 s
    each", with "objective_unit": "rad/s" and "units": {"spin": "rad/s"} in the JSON. An SI scene's
    keep theirs (the check can fail)."""
    import levitron as lev
    study = lev.load(scene)
    design = study.optimize("spin-range", {"top.mass": (0.98, 1.01)})
    scan = study.scan([40.0, 60.0], "tilt", [0.01], t_end=5.0)
    texts = [repr(design), design.message, repr(scan), scan.message]
    assert all(si_units(t) == [] for t in texts), [(t, si_units(t)) for t in texts if si_units(t)]
    assert design.as_json()["objective_unit"] == "rad/time"
    assert scan.as_json()["units"] == {"spin": "rad/time", "tilt": "rad"}
    si = lev.load("thesis_stable").scan([1000.0], "tilt", [0.01], t_end=0.05)
    assert {"ms", "rad/s"} <= set(si_units(si.message)) and si.as_json()["units"]["spin"] == "rad/s"


# an SI unit named as a word, not after a number: "a positive number in m", "(m)", "number rad/s"
UNIT_WORD = re.compile(rf"(?:\bin |number |\()({SI})(?![\w^/])")


def test_no_si_unit_word_in_a_dimensionless_scenes_argument_errors(scene, capsys):
    """Third audit: a bad argument on a dimensionless scene named an SI unit as a word, through the
    API and the command line: "box = -1 must be a positive number in m", "step = -1 ... in s",
    "spin = nan must be a finite number rad/s", "box half-width -1.0 must be a positive length (m)",
    "t_end = -1 must be a positive time in s". An SI scene's keep theirs (the check can fail)."""
    import levitron as lev
    study, si = lev.load(scene), lev.load("thesis_stable")
    calls = [lambda s: s.simulate(40.0, box=-1), lambda s: s.simulate(40.0, integrator="rk4", h=-1),
             lambda s: s.simulate(float("nan")), lambda s: s.propagator(box=-1.0),
             lambda s: s.launch(n=5, t_end=-1)]
    for call in calls:
        with pytest.raises(lev.UserError) as dl:
            call(study)
        with pytest.raises(lev.UserError) as e_si:
            call(si)
        assert UNIT_WORD.findall(str(dl.value)) == [] and "\n" not in str(dl.value), str(dl.value)
        assert UNIT_WORD.findall(str(e_si.value)), str(e_si.value)
    for argv in (["simulate", scene, "--spin", "40", "--box", "-1"],
                 ["simulate", scene, "--spin", "nan"], ["launch", scene, "--n", "5", "--t-end", "-1"]):
        assert cli.main(argv) == 2
        err = capsys.readouterr().err
        assert "error" in err and UNIT_WORD.findall(err) == [], err


def test_a_refusal_about_a_place_carries_it(scene):
    """A height no top hovers at and an offset outside the box are UserErrors about one setting:
    they carry it (param, value, its SI unit as the key of the quantity) for a program, and their
    sentence and hint in the API's words and the scene's units for a person."""
    import levitron as lev
    study = lev.load(scene)
    with pytest.raises(lev.UserError) as low:
        study.stability(1e-9)
    with pytest.raises(lev.UserError) as out:
        study.simulate(60.0, offset=5.0)
    assert (low.value.param, low.value.value, low.value.unit) == ("height", 1e-9, "m")
    assert (out.value.param, out.value.value, out.value.unit) == ("offset", 5.0, "m")
    assert out.value.hint == "pass a smaller offset or a larger box", out.value.hint
    assert si_units(str(low.value)) == [] and si_units(str(out.value)) == [], (low.value, out.value)


def test_a_plain_view_shows_a_dimensionless_reasons_spans_as_a_person_reads_them(scene, capsys):
    """The plain view reads the reason's quantity markers and shows them in the human form
    (runtime/ui/human.py restate: spans as lo-hi, 4 digits), the JSON keeps them whole; before its
    fix the plain view read the JSON's '[0.978335, 1.02]' on a dimensionless scene."""
    assert cli.main(["equilibrium", scene, "--set", "top.mass=1.5"]) == 0
    reason = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("reason:"))
    assert "mass in 0.9783-1.02 would hover inside the stable band 0.9948-1.102" in reason, reason
    assert cli.main(["equilibrium", scene, "--set", "top.mass=1.5", "--json"]) == 0
    assert "stable band [0.994772, 1.10212]" in json.loads(capsys.readouterr().out)["reason"]
