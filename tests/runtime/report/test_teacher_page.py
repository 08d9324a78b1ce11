"""The page a teacher shows (issue 28): the launch animated (it plays in headless Chromium and asks
the network for nothing), the set-up drawn to scale, the report of a launch in air, a report that
rebuilds from its embedded TOML, one hash however a number is spelled, stated reference values
beside the answers, simulate --animate and --save's columns."""
from __future__ import annotations

import html
import io
import json
import re
import shlex
import shutil
import subprocess
from contextlib import redirect_stdout
from pathlib import Path

import numpy as np
import pytest

from levitron.scene.inputs import input_hash
from levitron.scene.load import SceneError, load_scene
from levitron.runtime.cli import main as cli
from tests.helpers.dimensionless import SCENE as DIMENSIONLESS, si_units

ROOT = Path(__file__).resolve().parents[3]
CHROMIUM = shutil.which("chromium")


def _json(argv: list[str]) -> dict:
    buf = io.StringIO()
    with redirect_stdout(buf):
        assert cli.main([*argv, "--json", "--quiet"]) == 0
    return json.loads(buf.getvalue())


def _text(page: str) -> str:
    page = re.sub(r"<img[^>]*>|<style>.*?</style>|<script>.*?</script>", "", page, flags=re.S)
    return html.unescape(re.sub(r"<[^>]+>", " ", page))


@pytest.fixture(scope="module")
def air(tmp_path_factory):
    out = tmp_path_factory.mktemp("air") / "thesis_air.html"
    return out, _json(["report", "thesis_air", "--out", str(out)])


@pytest.fixture(scope="module")
def dimensionless(tmp_path_factory):
    folder = tmp_path_factory.mktemp("dimless")
    scene = folder / "unit_annulus.toml"
    scene.write_text(DIMENSIONLESS)
    out = folder / "unit_annulus.html"
    return out, _json(["report", str(scene), "--out", str(out)])


# ---- the report of a launch in air

def test_air_report_has_the_flight_the_odds_and_the_trim(air):
    path, facts = air
    text = _text(path.read_text())
    fl = facts["air"]
    assert fl["flight_time"] is not None and fl["t_cross"] is not None
    assert abs(fl["flight_time"] - fl["t_cross"]) / fl["t_cross"] < 0.05     # adiabatic: tau ln(w0/lo)
    odds = fl["odds"]
    lo, hi = odds["probability_ci95"]
    assert lo <= odds["probability"] <= hi and odds["n"] == 200
    assert "Launch odds:" in text and "Wilson" in text and "Matters most:" in text
    T = [w["temperature"] for w in fl["mass_windows"]]
    assert T == [12.0, 20.0, 28.0]
    # the magnets weaken as they warm: the masses that hover fall with the temperature
    m = [w["mass"][0] for w in fl["mass_windows"]]
    assert m[0] > m[1] > m[2]
    assert "12 degC" in text and "28 degC" in text
    assert "still floating at the run's end" not in text or "still up" in text
    anim = facts["animation"]
    assert anim["frames"] > 100
    # time scaled so that a turn of the precession takes at least a second on the screen, 1-2-5
    assert anim["precession"] is not None and anim["precession"] / 2 < anim["speed"] <= anim["precession"]
    assert anim["speed"] in (1.0, 2.0, 5.0)


def test_nice_floor():
    from levitron.runtime.simulate.animation import nice_floor
    assert [nice_floor(v) for v in (2.49, 1.0, 0.99, 7.3, 0.0123, 480.0)] == [2.0, 1.0, 0.5, 5.0, 0.01, 200.0]


def test_air_report_names_the_thesis_at_first_use(air):
    path, _ = air
    text = _text(path.read_text())
    first = re.search(r"\bthesis\b", text).start()        # not the scene's name, thesis_air
    assert text[first:first + 60].startswith("thesis: K. F. Lüskow"), text[first - 20:first + 60]
    assert text.count("Lüskow") == 1


def test_the_page_is_offline(air):
    """No reference to anything outside the page: no src or href but data: and #, no script src."""
    page = air[0].read_text()
    for m in re.finditer(r'\b(src|href)="([^"]*)"', page):
        assert m.group(2).startswith(("data:", "#")), m.group(0)[:80]
    assert not re.search(r"<script[^>]+src=", page)
    assert "fetch(" not in page and "XMLHttpRequest" not in page and "http://" not in page.replace(
        "http://www.w3.org/2000/svg", "")


# ---- a report that rebuilds

def test_footer_command_on_the_embedded_toml_rebuilds(tmp_path, monkeypatch):
    """Save the embedded block, run the footer's command: the same scene hash and numbers
    (thesis at another temperature: a quick page, the override carried)."""
    first = tmp_path / "first.html"
    facts = _json(["report", "thesis", "--temperature", "25", "--out", str(first)])
    page = first.read_text()
    toml = html.unescape(re.search(r'<pre class="toml" id="scene-toml">(.*?)</pre>', page, re.S).group(1))
    assert toml == (ROOT / "scenes" / "thesis.toml").read_text()
    command = html.unescape(re.search(r'<code class="rebuild">(.*?)</code>', page, re.S).group(1))
    assert command == facts["rebuild"]["command"] and "thesis.toml" in command and "25" in command
    folder = tmp_path / "saved"
    folder.mkdir()
    (folder / "thesis.toml").write_text(toml)
    monkeypatch.chdir(folder)
    assert "--out thesis.html" in command           # beside the saved file, not over the first page
    again = _json(shlex.split(command)[1:])          # the command exactly as the page gives it
    assert (folder / "thesis.html").is_file()
    assert again["provenance"]["scene_hash"] == facts["provenance"]["scene_hash"]
    assert again["rebuild"]["scene_hash"] == facts["rebuild"]["scene_hash"]
    for key in ("equilibria", "stable_band", "spin_interval", "z_s", "hints"):
        assert again[key] == facts[key], key


def test_a_number_spelled_two_ways_is_one_scene(tmp_path):
    text = (ROOT / "scenes" / "thesis_air.toml").read_text()
    assert "spin_decay_time = 150.0" in text
    a, b = tmp_path / "a" / "thesis_air.toml", tmp_path / "b" / "thesis_air.toml"
    for path, spelled in ((a, "150.0"), (b, "150")):
        path.parent.mkdir()
        path.write_text(text.replace("spin_decay_time = 150.0", f"spin_decay_time = {spelled}"))
    sa, sb = load_scene(a), load_scene(b)
    assert sa.scene_hash() == sb.scene_hash()
    assert input_hash(sa.data) == input_hash(sb.data)
    other = tmp_path / "c.toml"
    other.write_text(text.replace("spin_decay_time = 150.0", "spin_decay_time = 150.5"))
    assert load_scene(other).scene_hash() != sa.scene_hash()


# ---- stated reference values

REFERENCE = """
[reference]
source = "Smith 2020, a measured top"
z_stable = [0.1060, 0.002]
spin_interval = [470.0, 2700.0]
mass_window = [0.0505, 0.0525]
"""


def test_reference_values_shown_beside_ours_with_the_difference(tmp_path, capsys):
    from levitron.runtime.model.scenes import load_scene as load_with
    from levitron.runtime.ui import reference
    scene = tmp_path / "measured.toml"
    scene.write_text((ROOT / "scenes" / "thesis_stable.toml").read_text().split("[reference]")[0] + REFERENCE)
    sc = load_scene(scene)
    answers = {"z_stable": 0.1065, "spin_interval": [459.6, 2740.0], "mass_window": [0.05035, 0.05249],
               "flight_time": None}
    rows = reference.rows(sc, answers, _units(sc))
    assert rows[0] == ("z stable: Smith 2020, a measured top", "10.6 cm +/- 2 mm; here 10.65 cm (+0.47 %)")
    assert rows[1][1].endswith("(-2.2 %, +1.5 %)"), rows[1]
    assert len(rows) == 3 and all(reference.MODIFIED not in v for _, v in rows)
    for changed in (load_with(str(scene), ["top.mass=0.0510"]), load_with(str(scene), ["temperature=25.0"])):
        marked = reference.rows(changed, answers, _units(changed))
        assert len(marked) == 3 and all(reference.MODIFIED in v for _, v in marked)
    out = _plain(capsys, "equilibrium", str(scene), "--set", "top.mass=0.0510")
    assert "Smith 2020, a measured top: 10.6 cm (reference is for the unmodified scene)" in out


def test_reference_values_are_checked(tmp_path):
    base = (ROOT / "scenes" / "thesis_stable.toml").read_text().split("[reference]")[0]
    for bad in ("spin_interval = 470.0", "spin_interval = [2700.0, 470.0]", "flight_time = [1, 2, 3]",
                "mass_window = [0.05, 'x']"):
        path = tmp_path / "bad.toml"
        path.write_text(base + "\n[reference]\n" + bad + "\n")
        with pytest.raises(SceneError, match="reference"):
            load_scene(path)


def _units(scene):
    from levitron.runtime.ui.human import Units
    return Units.of_scene(scene)


def _plain(capsys, *argv) -> str:
    assert cli.main(list(argv)) == 0
    return capsys.readouterr().out


# ---- simulate --animate and --save

def test_simulate_animate_writes_an_offline_page_and_save_has_the_spin(tmp_path):
    page, csv = tmp_path / "run.html", tmp_path / "run.csv"
    r = _json(["simulate", "thesis_stable", "--spin", "1000", "--t-end", "2", "--n-out", "400",
               "--animate", str(page), "--save", str(csv)])
    assert r["animation"] == str(page) and "setup" not in r and "trajectory" not in r
    text = page.read_text()
    assert "<svg" in text and "<script>" in text and "real time" in text
    units, header = csv.read_text().splitlines()[:2]     # the units' comment line, then the names
    names = header.split(",")
    assert units.startswith("# units: t=s, x=m,") and units.endswith(", spin=rad/s")
    assert names[:13] == ["t", "x", "y", "z", "phi", "vartheta", "zeta", "p_x", "p_y", "p_z", "p_phi",
                          "p_vartheta", "p_zeta"] and names[-1] == "spin"
    table = np.loadtxt(csv, delimiter=",", skiprows=2)
    assert table.shape == (401, len(names))
    # omega_3 = -p_zeta / C (thesis 3.2.9): a second route to the spin column
    C = 1.32e-6
    assert np.allclose(table[:, -1], -table[:, names.index("p_zeta")] / C, rtol=1e-12)
    assert abs(table[0, -1] - 1000) < 1e-9


def test_animate_gif_has_the_frames(tmp_path, monkeypatch):
    """--animate FILE.gif (Pillow): a GIF of the run's frames (few here: the test stays quick)."""
    from PIL import Image
    from levitron.runtime.simulate import animation_video
    monkeypatch.setattr(animation_video, "VIDEO_FRAMES", 6)
    gif = tmp_path / "run.gif"
    _json(["simulate", "thesis_stable", "--spin", "1000", "--t-end", "1", "--n-out", "100", "--animate", str(gif)])
    with Image.open(gif) as im:
        assert im.format == "GIF" and im.n_frames == 6


def test_animate_refuses_another_suffix(tmp_path, capsys):
    assert cli.main(["simulate", "thesis_stable", "--spin", "1000", "--animate", str(tmp_path / "a.txt")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and ".html" in err


# ---- the animation plays in headless Chromium

def _chromium(page: Path, shot: Path, budget_ms: int) -> None:
    argv = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
            "--window-size=1100,1400", f"--virtual-time-budget={budget_ms}", f"--screenshot={shot}"]
    subprocess.run([*argv, page.as_uri()], check=True, capture_output=True, timeout=120)


def _dom(page: Path, budget_ms: int) -> str:
    return subprocess.run([CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu",
                           f"--virtual-time-budget={budget_ms}", "--dump-dom", page.as_uri()],
                          check=True, capture_output=True, timeout=120, text=True).stdout


# the test's probe, added to a copy of the page: every resource the page asked for (images,
# scripts, fetch, XHR: the Resource Timing list), written into the DOM that --dump-dom prints
PROBE = ("<script>setTimeout(function () { var p = document.createElement('pre'); p.id = 'probe'; "
         "p.textContent = JSON.stringify(performance.getEntriesByType('resource').map("
         "function (e) { return e.name; })); document.body.appendChild(p); }, 1200);</script>")


@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (Debian: apt-get install chromium)")
@pytest.mark.parametrize("which", ["air", "dimensionless"])
def test_the_animation_plays_offline(which, request, tmp_path):
    """Two screenshots a (virtual) second apart differ, and only in the animation's area (the rest
    of the page stands still); the page asks for no resource (Resource Timing, through a probe in
    a copy of the page); a dimensionless scene's page, as drawn, shows no SI unit."""
    import matplotlib.image
    page = request.getfixturevalue(which)[0]
    shots = [tmp_path / "a.png", tmp_path / "b.png"]
    _chromium(page, shots[0], 1000)
    _chromium(page, shots[1], 2000)
    a, b = (matplotlib.image.imread(str(s))[..., :3] for s in shots)
    rows = np.nonzero(np.abs(a - b).max(axis=(1, 2)) > 0.05)[0]
    assert len(rows) > 20, "the animation did not move"
    assert rows.max() - rows.min() < 520, (rows.min(), rows.max())   # the animation's 440 px and its controls
    probed = tmp_path / "probed.html"
    probed.write_text(page.read_text().replace("</body>", PROBE + "</body>"))
    dom = _dom(probed, 3000)
    assert len(re.findall("<svg", dom)) >= 2              # the set-up, then the animation
    asked = json.loads(html.unescape(re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S).group(1)))
    assert asked == []
    if which == "dimensionless":
        text = _text(re.sub(r'<pre class="toml".*?</pre>', "", dom, flags=re.S))   # the author's TOML
        assert "time units" in text and si_units(text) == [], si_units(text)[:10]


def test_the_setup_is_drawn_to_scale_with_its_dimensions():
    """The cut through the axis (runtime/report/setup_drawing.py): the ring magnet's 12 cm, its 6 cm
    hole and 2 cm thickness, the top at z_s, the band and z_c, all to one scale (the drawn widths
    of the base and of the top are in the ratio of their sizes)."""
    from levitron.scene.load import load_scene as load
    from levitron.runtime.model.load import load_model
    from levitron.runtime.report.setup_drawing import drawing
    from levitron.runtime.simulate.setup_shape import setup_of, top_disc
    model = load_model(load("ring_magnet"))
    setup = setup_of(model, bands=True)
    svg = drawing(setup, _units(model.scene))
    for text in ("diameter 12 cm, hole 6 cm, thickness 2 cm", "hover height z_s = 7.047 cm", "stable band",
                 "z_c = 6.529 cm"):
        assert text in svg, text
    r, h = top_disc(0.0182, 2.2e-6, 1.32e-6)
    assert abs(0.5 * 0.0182 * r * r - 1.32e-6) < 1e-18                      # C = m r^2 / 2
    assert abs(0.0182 * (3 * r * r + h * h) / 12 - 2.2e-6) < 1e-18          # A = m (3 r^2 + h^2) / 12
    widths = [float(w) for w in re.findall(r'<rect x="[^"]+" y="[^"]+" width="([^"]+)" height="[^"]+" '
                                           r'fill="#(?:8a8f99|c0392b)"', svg)]
    ring, top = widths[0], widths[-1]          # one side of the ring (r_out - r_in), the top's diameter
    assert abs(ring / top - 0.03 / (2 * r)) < 0.01


def test_a_simulation_shows_its_animation_in_a_notebook():
    """Study.simulate's Simulation: _repr_html_ is the table of its plain view and the animation
    (inline, offline)."""
    import levitron as lev
    sim = lev.load("thesis_stable").simulate(1000.0, t_end=1.0)
    page = sim._repr_html_()
    assert page.startswith("<div><table><caption") and "levitating</th><td>yes" in page
    assert '<div class="levitron-animation"' in page
    assert "<script>" in page and not re.search(r'\b(src|href)="(?!data:|#)', page)
    assert len(page) < 400_000


@pytest.mark.parametrize("seed", range(3))
def test_spelling_never_changes_the_hash(seed):
    """Random nested tables: writing every integral number as a float (200 -> 200.0) keeps the
    canonical form; changing one number's value changes it."""
    from levitron.scene.load import spelled_alike
    rng = np.random.default_rng(seed)

    def table(depth):
        out = {}
        for k in range(int(rng.integers(1, 5))):
            kind = rng.integers(0, 4) if depth < 2 else rng.integers(0, 3)
            out[f"k{k}"] = (int(rng.integers(-10**6, 10**6)) if kind == 0 else float(rng.normal()) if kind == 1
                            else [int(rng.integers(0, 9)), float(rng.integers(0, 9))] if kind == 2
                            else table(depth + 1))
        return out

    def as_floats(node):
        if isinstance(node, dict):
            return {k: as_floats(v) for k, v in node.items()}
        if isinstance(node, list):
            return [as_floats(v) for v in node]
        return float(node) if isinstance(node, int) and not isinstance(node, bool) else node

    for _ in range(50):
        data = table(0)
        dump = lambda d: json.dumps(spelled_alike(d), sort_keys=True)  # noqa: E731
        assert dump(data) == dump(as_floats(data))
        bumped = dict(data, extra=1)
        assert dump(bumped) != dump(dict(data, extra=1.5))
    assert spelled_alike(True) is True and spelled_alike(2.0 ** 60) == 2.0 ** 60


def test_launch_histogram_labels_its_censored_bar(tmp_path, legend_texts):
    """`launch --out`: the runs still up at the run's end are a bar of their own, labelled with
    their count, and the axis ends just past the run length."""
    r = _json(["launch", "thesis_air", "--n", "12", "--t-end", "20", "--out", str(tmp_path / "h.png")])
    up = r["flight_time"]["censored"]
    assert 0 < up <= 12
    assert f"still floating at the run's end ({up})" in legend_texts
    assert (tmp_path / "h.png").stat().st_size > 10_000


def test_the_packed_frames_round_trip():
    """animation.pack/unpack: the page's whole numbers give back the run's centre and axis to the
    quantum (1/30000 of the largest excursion; 1e-5 in n) and the rim mark lies on the disc's rim
    plane (perpendicular to n, unit length)."""
    from levitron.runtime.simulate import animation
    rng = np.random.default_rng(4)
    x, y, dz = rng.normal(size=(3, 50)) * np.array([[3e-4], [2e-4], [1e-5]])
    n = rng.normal(size=(50, 3)) * [0.05, 0.05, 0] + [0, 0, 1]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    phi = np.linspace(0, 40, 50)
    data = {"pack": animation.pack(x, y, dz, n, phi), "z_s": 0.1}
    back = animation.unpack(data)
    assert np.max(np.abs(back["x"] - x)) <= 0.5 * data["pack"]["q_xy"] * (1 + 1e-9)
    assert np.max(np.abs(back["z"] - 0.1 - dz)) <= 0.5 * data["pack"]["q_z"] * (1 + 1e-9) + 1e-15
    assert np.max(np.abs(back["n"] - n)) < 2e-5
    m = back["mark"]
    assert np.allclose(np.linalg.norm(m, axis=1), 1) and np.max(np.abs(np.sum(m * back["n"], axis=1))) < 1e-12


def test_air_report_leads_with_what_a_maker_decides(air):
    """Right under the answer: the odds with their interval, the mass margins to both edges of the
    masses that hover, the temperatures at which the top stops hovering; the 28 degC row says the
    51.5 g top does not hover there (its band is 49.07-51.16 g)."""
    path, facts = air
    text = _text(path.read_text())
    fl = facts["air"]
    below, above = fl["stops_hovering"]["below"], fl["stops_hovering"]["above"]
    assert 8 < below < 20 < above <= 28            # 28 degC: too heavy, 12 degC: too light (README)
    lo, hi = fl["mass_windows"][1]["mass"]
    summary = fl["summary"]
    assert summary.startswith("Launch odds: ") and "still hover" in summary and "stops hovering" in summary
    first = text.index(summary.split(";")[0])
    assert first < text.index("The set-up, to scale") and summary.split(";")[0] in text
    assert "the scene's 51.5 g top does not hover" in text
    assert lo < 0.0515 < hi
