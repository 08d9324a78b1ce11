"""Bad scenes fail with one line naming the key and the fix, exit code 2, and touch nothing."""
import hashlib
import os
import subprocess
import sys
from pathlib import Path

import pytest

from levitron.derive.build import GENERATED
from levitron.scene.paths import ROOT

GOOD = (ROOT / "scenes" / "thesis.toml").read_text()


def _snapshot(folder: Path) -> dict:
    return {p.relative_to(folder).as_posix(): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


CASES = [
    ("missing mass", GOOD.replace("mass = 0.0284", ""), "top.mass is missing"),
    ("unknown key", GOOD.replace("[top]", "[top]\ncolour = 1"), "unknown key `colour`: allowed keys are"),
    ("misspelt key", GOOD.replace("hole = 0.03", "hloe = 0.03"), "unknown key `hloe`: did you mean `hole`?"),
    ("negative mass", GOOD.replace("mass = 0.0284", "mass = -0.0284"), "top.mass = -0.0284 must be positive"),
    ("negative inertia", GOOD.replace("A = 2.2e-6", "A = -2.2e-6"), "top.A"),
    ("hole too big", GOOD.replace("hole = 0.03", "hole = 0.10"), "plate.hole = 0.1 is not smaller than plate.radius"),
    ("odd order", GOOD.replace("order = 2", "order = 3"), "field.order = 3 must be an even integer"),
    ("order below 2", GOOD.replace("order = 2", "order = 0"), "field.order = 0"),
    ("unknown plate", GOOD.replace('kind = "annulus"', 'kind = "pyramid"'), "plate.kind = 'pyramid' is unknown"),
    ("bad toml", GOOD + "\n[[[", "not valid TOML"),
    ("impossible inertia", GOOD.replace("C = 1.32e-6", "C = 9e-6"), "top.C"),
]


@pytest.mark.parametrize("label,text,message", CASES, ids=[c[0] for c in CASES])
def test_bad_scene_is_refused_cleanly(tmp_path, label, text, message):
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    cache = tmp_path / "cache"
    before = _snapshot(GENERATED)
    env = dict(os.environ, LEVITRON_CACHE=str(cache))
    for cmd in (["-m", "levitron.runtime.cli.main", "info", str(scene)], ["-m", "levitron.derive", str(scene)]):
        res = subprocess.run([sys.executable, *cmd], cwd=ROOT, env=env, capture_output=True, text=True, check=False)
        assert res.returncode == 2, (cmd, res.stdout, res.stderr)
        lines = res.stderr.strip().splitlines()
        assert len(lines) == 1, res.stderr
        assert message in lines[0], lines[0]
        assert res.stdout == ""
    assert _snapshot(GENERATED) == before
    derived = cache / "derived"
    assert not derived.exists() or not any(derived.iterdir())


def test_bad_override_is_refused():
    res = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", "info", "thesis", "--set", "top.mass"],
                         cwd=ROOT, capture_output=True, text=True, check=False)
    assert res.returncode == 2 and "has no '='" in res.stderr


def test_unknown_scene_names_the_known_ones():
    res = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", "info", "nosuchscene"],
                         cwd=ROOT, capture_output=True, text=True, check=False)
    assert res.returncode == 2 and "thesis" in res.stderr


# ---------------------------------------------------------------- absurd numbers

@pytest.mark.parametrize("override,message", [
    ("top.A=1e100", "top.A = 1e+100 is outside"),
    ("top.mass=1e308", "top.mass = 1e+308 is outside"),
    ("top.mass=1e-300", "top.mass = 1e-300 is outside"),
    ("top.mass=inf", "top.mass = inf is not finite"),
    ("top.mass=1" + "0" * 400, "top.mass = inf is not finite"),
    ("top.mass=nan", "top.mass = nan is not finite"),
    ("top.mass=-1", "top.mass = -1 must be positive"),
    ("top.mass=heavy", "top.mass = 'heavy' is not a number"),
    ("top.moment=0", "top.moment = 0 must be nonzero"),
    ("plate.radius=-0.1", "plate.radius = -0.1 must be positive"),
    ("plate.murho=1e20", "plate.murho = 1e+20 is outside"),
    ("g=-9.81", "g = -9.81 must be positive"),
    ("field=3", "field = 3 is not a section"),
    ("model=[1]", "model = [1] is not a section"),
    ("name=caf\u00e9", "name = 'caf\u00e9'"),
])
def test_absurd_numbers_are_one_line_scene_errors(override, message):
    from levitron.scene.load import SceneError, load_scene
    with pytest.raises(SceneError) as info:
        load_scene("thesis", [override])
    text = str(info.value)
    assert message in text and "\n" not in text, text


def test_ring_magnet_absurd_magnetization():
    from levitron.scene.load import SceneError, load_scene
    with pytest.raises(SceneError, match="plate.remanence = 1e\\+13 is outside"):
        load_scene("ring_magnet", ["plate.remanence=1e13"])


@pytest.mark.parametrize("args", [
    ["info", "thesis", "--set", "top.A=1e100"],
    ["info", "scenes"],                     # a directory as the scene
    ["info", "thesis", "--set", "top.mass=inf"],
])
def test_absurd_input_through_the_command_line(tmp_path, args):
    env = dict(os.environ, LEVITRON_CACHE=str(tmp_path / "cache"))
    res = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", *args], cwd=ROOT, env=env,
                         capture_output=True, text=True, check=False)
    assert res.returncode == 2, (res.stdout, res.stderr)
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in res.stderr, res.stderr


def test_binary_scene_file_is_refused(tmp_path):
    from levitron.scene.load import SceneError, load_scene
    bad = tmp_path / "bin.toml"
    bad.write_bytes(b"\xff\xfe\x00name")
    with pytest.raises(SceneError, match="not a text file"):
        load_scene(bad)


@pytest.mark.parametrize("name", ["a\0b", "x" * 5000, "x" * 300 + ".toml"])
def test_unusable_scene_names_are_one_line_errors(name):
    from levitron.scene.load import SceneError, load_scene
    with pytest.raises(SceneError) as info:
        load_scene(name)
    assert "\n" not in str(info.value) and len(str(info.value)) < 400


COMPOUND = """name = "two_rings"
[top]
mass = 0.0515
A = 2.2e-6
C = 1.32e-6
moment = -1.0
[plate]
kind = "compound"
[[plate.parts]]
kind = "annulus"
radius = 0.10
hole = 0.03
murho = -0.0026209383
[[plate.parts]]
kind = "disk"
radius = 0.02
murho = 0.001
"""


def test_override_reaches_a_compound_plates_parts(tmp_path):
    """--set enters a list of tables by its index (plate.parts.0.radius); the parameter it sets is
    the part's (plate_p0_a), the other part keeps its own."""
    from levitron.scene.load import load_scene
    path = tmp_path / "two_rings.toml"
    path.write_text(COMPOUND)
    base = load_scene(path)
    sc = load_scene(path, ["plate.parts.0.radius=0.11", "plate.parts.1.murho=0.002"])
    assert base.params["plate_p0_a"] == 0.10 and sc.params["plate_p0_a"] == 0.11
    assert sc.params["plate_p1_a"] == base.params["plate_p1_a"]
    assert sc.params["plate_p1_rho"] == 2 * base.params["plate_p1_rho"]


@pytest.mark.parametrize("override, message", [
    ("plate.parts.5.radius=0.11", "'5' is not an index of a list of 2 tables; use 0..1"),
    ("plate.parts.x.radius=0.11", "'x' is not an index of a list of 2 tables"),
    ("plate.parts.0=1", "'parts' is a list of tables: name a key inside one of them"),
])
def test_bad_compound_override_is_one_line(tmp_path, override, message):
    path = tmp_path / "two_rings.toml"
    path.write_text(COMPOUND)
    r = subprocess.run([sys.executable, "-m", "levitron.runtime.cli.main", "info", str(path), "--set", override],
                       capture_output=True, text=True, cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert r.returncode == 2 and message in r.stderr and len(r.stderr.strip().splitlines()) == 1, r.stderr


def test_design_keys_reach_a_compound_plates_parts(tmp_path):
    """optimize --vary and the API name a part's key the same way (runtime/design/scene_keys.py)."""
    from levitron.scene.load import load_scene
    from levitron.runtime.errors import UserError
    from levitron.runtime.design.scene_keys import key_value, with_values
    path = tmp_path / "two_rings.toml"
    path.write_text(COMPOUND)
    sc = load_scene(path)
    assert key_value(sc.data, "plate.parts.1.radius") == 0.02
    assert with_values(sc, {"plate.parts.1.radius": 0.025}).params["plate_p1_a"] == 0.025
    for bad in ("plate.parts.2.radius", "plate.parts.one.radius"):
        with pytest.raises(UserError, match="plate.parts.<i>.<key>"):
            key_value(sc.data, bad)


def test_derive_refuses_a_bad_scene_before_it_loads_sympy(tmp_path):
    """python -m levitron.derive validates every scene before it imports the derivation (sympy, the
    emitters: half a second), so a bad scene is refused at once."""
    scene = tmp_path / "bad.toml"
    scene.write_text(CASES[0][1])
    code = ("import sys; from levitron.derive.__main__ import main; rc = main([sys.argv[1]]); "
            "print(rc, 'sympy' in sys.modules)")
    res = subprocess.run([sys.executable, "-c", code, str(scene)], cwd=ROOT, capture_output=True, text=True,
                         check=False)
    assert res.stdout.split() == ["2", "False"], res.stdout + res.stderr
    assert CASES[0][2] in res.stderr
