"""A battery of bad and hostile inputs: every failure is one line on stderr and exit 2.

Each case of BATTERY is a tests/helpers/battery.py Case, run by its run_case (the real entry point;
exit 2, one error line naming the cause, no traceback, generated/ untouched, nothing half-written in
the cache; BOUNDED cases return within a time limit, refused or at status "step_budget").
The few cases that must WORK (exit 0) are separate tests below, as are the closed pipe, --version,
`python -m levitron.runtime`, the internal-error line and "no sympy in the runtime".
"""
from __future__ import annotations

import json
import os
import shlex
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from tests.helpers.battery import (GENERATED, ROOT, THESIS, Case, case_env, copy_artefacts, error_lines,
                                   expression_scene, run_case, run_inprocess, thesis)


def bad_key(case_id: str, mention: str, old: str, new: str) -> Case:
    """`levitron info` of the thesis scene with one edit."""
    return Case(case_id, "info {scene}", mention, toml=thesis(old, new))


NEEDS = 'needs = ["reduced", "full", "linear"]'
NESTED = "sin(" * 15 + "z" + ")" * 15


# ---------------------------------------------------------------- special set-ups
# Each takes (tmp_path, case environment dict, request) and prepares files; the case's argv may
# name {tmp} (tmp_path) and {scene} (the case's scene file).

def _unwritable(folder: Path, request) -> None:
    """Make `folder` unwritable even for root (chattr +i), undone after the test."""
    folder.mkdir(parents=True, exist_ok=True)
    if os.geteuid() == 0:
        if shutil.which("chattr") is None:
            pytest.skip("running as root without chattr: cannot make a read-only folder")
        subprocess.run(["chattr", "+i", str(folder)], check=False, capture_output=True)
        request.addfinalizer(lambda: subprocess.run(["chattr", "-i", str(folder)], check=False))
    else:
        folder.chmod(0o555)
        request.addfinalizer(lambda: folder.chmod(0o755))
    probe = folder / "probe"
    try:
        probe.touch()
    except OSError:
        return
    probe.unlink()
    pytest.skip(f"cannot make {folder} read-only on this machine")


def cache_is_file(tmp, env, request):
    (tmp / "store").write_text("not a folder\n")
    env["LEVITRON_CACHE"] = str(tmp / "store")


def cache_below_file(tmp, env, request):
    (tmp / "store").write_text("not a folder\n")
    env["LEVITRON_CACHE"] = str(tmp / "store" / "levitron")


def cache_read_only(tmp, env, request):
    _unwritable(tmp / "store", request)
    env["LEVITRON_CACHE"] = str(tmp / "store")


def a_folder(tmp, env, request):
    (tmp / "figs").mkdir()
    (tmp / "figs.png").mkdir()


def a_file(tmp, env, request):
    (tmp / "afile").write_text("a file\n")


def locked_folder(tmp, env, request):
    _unwritable(tmp / "locked", request)


def binary_scene(tmp, env, request):
    (tmp / "binary.toml").write_bytes(bytes(range(256)) * 8)


def toml_folder(tmp, env, request):
    (tmp / "folder.toml").mkdir()


def _fake_generated(tmp, env, request, damage: Callable[[Path], None]):
    """A copy of generated/thesis, damaged, that the runtime takes for the committed model: every
    loaded module's GENERATED (the one constant naming the folder) points at the copy."""
    fake = tmp / "generated"
    shutil.copytree(GENERATED / "thesis", fake / "thesis")
    damage(fake / "thesis")
    mp = request.getfixturevalue("monkeypatch")
    patched = 0
    for name, mod in list(sys.modules.items()):
        if name.startswith(("levitron.runtime.", "levitron.derive.")) and getattr(mod, "GENERATED", None) == GENERATED:
            mp.setattr(mod, "GENERATED", fake)
            patched += 1
    assert patched, "no module holds GENERATED: update this test to the new constant"


def _edit_manifest(folder: Path, change: Callable[[dict], None]) -> None:
    path = folder / "manifest.json"
    data = json.loads(path.read_text())
    change(data)
    path.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")


def manifest_key_missing(tmp, env, request):
    _fake_generated(tmp, env, request, lambda f: _edit_manifest(f, lambda d: d.pop("parameters")))


def manifest_params_swapped(tmp, env, request):
    def swap(d):
        p = d["parameters"]
        i, j = p.index("A"), p.index("C")
        p[i], p[j] = p[j], p[i]
    _fake_generated(tmp, env, request, lambda f: _edit_manifest(f, swap))


def casadi_truncated(tmp, env, request):
    def cut(folder):
        path = folder / "onaxis.casadi"
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 2])
    _fake_generated(tmp, env, request, cut)


def model_c_edited(tmp, env, request):
    def change(folder):
        path = folder / "model.c"
        path.write_text(path.read_text().replace("*", "* 1.0001 *", 1))
    _fake_generated(tmp, env, request, change)


# ---------------------------------------------------------------- the battery

SIM = "simulate thesis_stable --spin 1000 --tilt 0.01 --json"
OPT = "optimize thesis --fit-height 0.1"

BATTERY = [
    # --- the scene argument
    Case("scene-is-a-folder", "info {tmp}", r"folder|director|\.toml"),
    Case("scene-folder-named-toml", "info {tmp}/folder.toml", r"folder|director", setup=toml_folder),
    Case("scene-unknown-name", "info nosuchscene", r"unknown scene"),
    Case("scene-missing-file", "info {tmp}/missing.toml", r"does not exist"),
    Case("scene-empty", "info {scene}", r"\[top\]|top", toml=""),
    Case("scene-binary", "info {tmp}/binary.toml", r"toml|utf|text", setup=binary_scene),
    Case("scene-bad-toml", "info {scene}", r"not valid TOML", toml=THESIS + "\n[[[\n"),
    Case("derive-bad-scene", "derive {scene}", r"top\.mass", toml=thesis("mass = 0.0284", "mass = -1")),
    Case("derive-unknown-scene", "derive nosuchscene", r"unknown scene"),
    # --- keys and values of a scene
    Case("unknown-top-level-key", "info {scene}", r"unknown key", toml="colour = 3\n" + THESIS),
    bad_key("unknown-top-key", r"colour", "[top]", "[top]\ncolour = 1"),
    bad_key("unknown-plate-kind", r"pyramid", 'kind = "annulus"', 'kind = "pyramid"'),
    bad_key("missing-plate-section", r"\[plate\]|plate", "[plate]", "[plate_x]"),
    bad_key("mass-is-a-string", r"top\.mass", "mass = 0.0284", 'mass = "heavy"'),
    bad_key("mass-is-nan", r"top\.mass", "mass = 0.0284", "mass = nan"),
    bad_key("mass-is-inf", r"top\.mass", "mass = 0.0284", "mass = inf"),
    bad_key("mass-negative", r"top\.mass", "mass = 0.0284", "mass = -0.0284"),
    bad_key("mass-zero", r"top\.mass", "mass = 0.0284", "mass = 0"),
    bad_key("inertia-A-negative", r"top\.A", "A = 2.2e-6", "A = -2.2e-6"),
    bad_key("inertia-C-negative", r"top\.C", "C = 1.32e-6", "C = -1.32e-6"),
    bad_key("inertia-C-above-2A", r"top\.C", "C = 1.32e-6", "C = 9e-6"),
    bad_key("radius-negative", r"plate\.radius", "radius = 0.10", "radius = -0.10"),
    bad_key("hole-not-below-radius", r"plate\.hole", "hole = 0.03", "hole = 0.10"),
    bad_key("hole-negative", r"plate\.hole", "hole = 0.03", "hole = -0.03"),
    bad_key("murho-zero", r"murho", "murho = -0.0026209383", "murho = 0"),
    bad_key("murho-and-dipole-density", r"murho|dipole_density", "murho = -0.0026209383",
            "murho = -0.0026\ndipole_density = 1e4"),
    bad_key("gravity-negative", r"\bg\b", "g = 9.81", "g = -9.81"),
    bad_key("name-with-spaces", r"name", 'name = "thesis"', 'name = "a b"'),
    bad_key("order-odd", r"field\.order", "order = 2", "order = 3"),
    bad_key("order-negative", r"field\.order", "order = 2", "order = -2"),
    bad_key("order-a-string", r"field\.order", "order = 2", 'order = "two"'),
    bad_key("order-too-high", r"field\.order", "order = 2", "order = 14"),
    bad_key("needs-empty", r"model\.needs", NEEDS, "needs = []"),
    bad_key("needs-unknown", r"model\.needs", NEEDS, 'needs = ["everything"]'),
    bad_key("needs-linear-without-full", r"full", NEEDS, 'needs = ["reduced", "linear"]'),
    bad_key("coordinates-unknown", r"model\.coordinates", 'coordinates = "tait-bryan"',
            'coordinates = "polar"'),
    Case("ring-r_in-not-below-r_out", "info ring_magnet --set plate.r_in=0.07", r"r_in"),
    Case("expression-unknown-name", "info {scene}", r"bogus|phi0",
         toml=expression_scene("sqrt(z**2 + bogus**2)")),
    Case("expression-python-injection", "info {scene}", r"phi0",
         toml=expression_scene("__import__('os').getcwd()")),
    Case("expression-reserved-param-name", "info {scene}", r"params",
         toml=expression_scene("z", {"sin": 1.0})),
    Case("expression-abs", "equilibrium {scene}", r"abs", toml=expression_scene("abs(z)")),
    bad_key("compound-without-parts", r"parts",
            'kind = "annulus"\nradius = 0.10        # m\nhole = 0.03          # m\nmurho = -0.0026209383',
            'kind = "compound"'),
    # --- --set overrides
    Case("set-without-equals", "info thesis --set top.mass", r"="),
    Case("set-unknown-section", "info thesis --set nosection=1", r"nosection"),
    Case("set-malformed-key", "info thesis --set top.=1", r"malformed|top\."),
    Case("set-into-a-number", "info thesis --set top.mass.x=1", r"section|top\.mass"),
    Case("set-section-to-number", "info thesis --set top=1", r"top"),
    Case("set-mass-word", "info thesis --set top.mass=abc", r"top\.mass"),
    Case("set-mass-nan", "info thesis --set top.mass=nan", r"top\.mass"),
    Case("set-unknown-plate-kind", "info thesis --set plate.kind=pyramid", r"pyramid"),
    Case("set-huge-inertia", "stability thesis --set top.A=1e100", r"top\.A|\bA\b|inertia"),
    # --- options of the commands
    Case("no-command", "", r"command|required"),
    Case("unknown-command", "frobnicate thesis", r"frobnicate|invalid choice"),
    Case("unknown-option", "info thesis --frobnicate", r"frobnicate|unrecognized"),
    Case("field-no-point", "field thesis", r"--at"),
    Case("field-two-components", "field thesis --at 0.01,0.02", r"--at"),
    Case("field-words", "field thesis --at a,b,c", r"--at"),
    Case("field-nan", "field thesis --at nan,0,0.1", r"--at"),
    Case("stability-negative-height", "stability thesis --height -1", r"--height"),
    Case("stability-height-nan", "stability thesis --height nan", r"--height"),
    Case("stability-plot-option-unknown", "stability thesis --plot {tmp}/s.png", r"--plot|unrecognized"),
    Case("simulate-no-spin", "simulate thesis_stable", r"--spin"),
    Case("simulate-spin-word", "simulate thesis_stable --spin fast", r"--spin|invalid float"),
    Case("simulate-spin-nan", "simulate thesis_stable --spin nan", r"spin"),
    Case("simulate-spin-inf", "simulate thesis_stable --spin inf", r"spin"),
    Case("simulate-tilt-nan", "simulate thesis_stable --spin 1000 --tilt nan", r"tilt"),
    Case("simulate-t-end-negative", "simulate thesis_stable --spin 1000 --t-end -1", r"t-end"),
    Case("simulate-t-end-nan", "simulate thesis_stable --spin 1000 --t-end nan", r"t-end"),
    Case("simulate-unknown-integrator", "simulate thesis_stable --spin 1000 --integrator magic",
         r"integrator"),
    Case("simulate-tol-1", "simulate thesis_stable --spin 1000 --tol 1", r"tol"),
    Case("simulate-tol-negative", "simulate thesis_stable --spin 1000 --tol -1e-9", r"tol"),
    Case("simulate-step-1e-15", "simulate thesis_stable --spin 1000 --integrator rk4 --step 1e-15",
         r"step", sub=True),
    Case("simulate-n-out-zero", "simulate thesis_stable --spin 1000 --n-out 0", r"n.out"),
    Case("simulate-box-negative", "simulate thesis_stable --spin 1000 --box -1", r"box"),
    Case("simulate-full-of-reduced-only", "simulate reduced_only --spin 1000", r"full"),
    Case("simulate-too-heavy", "simulate thesis --set top.mass=1 --spin 1000", r"heavy|at most|top\.mass"),
    Case("simulate-plot-toml", "simulate thesis_stable --spin 1000 --t-end 0.01 --plot {tmp}/run.toml",
         r"\.png"),
    Case("scan-no-spin", "scan thesis_stable --tilt 0.01:0.1:3", r"--spin"),
    Case("scan-spin-two-parts", "scan thesis_stable --spin 100:200 --tilt 0.01:0.1:3", r"LO:HI:N"),
    Case("scan-spin-words", "scan thesis_stable --spin a:b:c --tilt 0.01:0.1:3", r"spin"),
    Case("scan-spin-zero-points", "scan thesis_stable --spin 100:200:0 --tilt 0.01:0.1:3", r"\bN\b"),
    Case("scan-spin-reversed", "scan thesis_stable --spin 200:100:3 --tilt 0.01:0.1:3", r"swap|above"),
    Case("scan-no-second-axis", "scan thesis_stable --spin 100:200:3", r"--tilt"),
    Case("scan-two-second-axes", "scan thesis_stable --spin 100:200:3 --tilt 0.01:0.1:3 --mass 0.05:0.06:3",
         r"exactly one"),
    Case("scan-workers-zero", "scan thesis_stable --spin 100:200:3 --tilt 0.01:0.1:3 --workers 0",
         r"workers"),
    Case("scan-unknown-integrator", "scan thesis_stable --spin 100:200:3 --tilt 0.01:0.1:3 --integrator x",
         r"integrator"),
    Case("scan-tol-1", "scan thesis_stable --spin 100:200:3 --tilt 0.01:0.1:3 --tol 1", r"tol", sub=True),
    Case("scan-out-toml", "scan thesis_stable --spin 100:200:3 --tilt 0.01:0.1:3 --out {tmp}/map.toml",
         r"\.png"),
    Case("optimize-unknown-param", OPT + " --param nosuch", r"nosuch"),
    Case("optimize-negative-height", "optimize thesis --fit-height -1", r"fit-height"),
    Case("optimize-nan-height", "optimize thesis --fit-height nan", r"fit-height"),
    Case("optimize-plate_a-no-solution", "optimize thesis --fit-height 0.3 --param plate_a", r"plate_a"),
    Case("optimize-mass-toward-negative", "optimize thesis --fit-height 0.05 --param m", r"\bm\b|mass"),
    Case("bench-no-stable-interval", "bench thesis --quick --out {tmp}/bench", r"stab"),
    Case("figures-out-is-a-file", "figures thesis --quick --out {tmp}/afile", r"afile", setup=a_file),
    # --- output paths
    Case("plot-suffix-toml", "equilibrium thesis --plot {tmp}/out.toml", r"\.png.*\.pdf.*\.svg"),
    Case("plot-no-suffix-folder", "equilibrium thesis --plot {tmp}/figs", r"folder|director|\.png",
         setup=a_folder),
    Case("plot-folder-named-png", "equilibrium thesis --plot {tmp}/figs.png", r"folder|director",
         setup=a_folder),
    Case("plot-below-a-file", "equilibrium thesis --plot {tmp}/afile/eq.png", r"afile", setup=a_file),
    Case("plot-unwritable-folder", "equilibrium thesis --plot {tmp}/locked/eq.png", r"locked",
         setup=locked_folder),
    # --- the cache
    Case("cache-is-a-file", "stability thesis", r"LEVITRON_CACHE", setup=cache_is_file),
    Case("cache-below-a-file", "stability thesis", r"LEVITRON_CACHE", setup=cache_below_file),
    Case("cache-read-only", "stability thesis", r"LEVITRON_CACHE", setup=cache_read_only),
    # --- damaged committed models (a copy of generated/thesis taken for the real one)
    Case("manifest-key-missing", "stability thesis", r"make derive", setup=manifest_key_missing),
    Case("manifest-parameters-swapped", "stability thesis", r"make derive", setup=manifest_params_swapped),
    Case("casadi-file-truncated", OPT, r"make derive", setup=casadi_truncated),
    Case("model-c-edited", "stability thesis", r"make derive", setup=model_c_edited),
    # --- hostile formulas and unbounded work (subprocesses with a time limit)
    Case("expression-pole", "simulate {scene} --part reduced --spin 100 --t-end 1 --json",
         r"pole|equilibri", toml=expression_scene("rho/(z - a)", {"rho": -1.0, "a": 0.05}),
         sub=True, timeout=60),
    Case("expression-nested-depth-15", "equilibrium {scene}", r"nest|deep|depth|phi0",
         toml=expression_scene(NESTED), sub=True, timeout=20),
    Case("simulate-n-out-1e9", "simulate thesis_stable --spin 1000 --t-end 0.01 --n-out 1000000000",
         r"n.out", sub=True),
    # (a z-x-z launch at tilt 1e-6 once ran into its step budget, the expanded energy's
    # cancellation; the cancellation-free form completes it: tests/runtime/simulate/test_near_vertical.py)
    Case("simulate-t-end-1e9", SIM + " --t-end 1e9", r"t.end|step|budget", sub=True, bounded=True),
    Case("simulate-spin-1e12", "simulate thesis_stable --spin 1e12 --tilt 0.01 --t-end 1 --json",
         r"spin|step|budget", sub=True, bounded=True),
    Case("simulate-step-1e-12", SIM + " --integrator rk4 --step 1e-12 --t-end 1", r"step|budget",
         sub=True, bounded=True),
    Case("scan-t-end-1e9", "scan thesis_stable --spin 1000:1000:1 --tilt 0.01:0.01:1 --t-end 1e9 --json "
         "--quiet", r"t.end|step|budget", sub=True, bounded=True),
]


def test_battery_size():
    assert len(BATTERY) >= 60
    assert len({c.id for c in BATTERY}) == len(BATTERY)


@pytest.mark.parametrize("case", BATTERY, ids=[c.id for c in BATTERY])
def test_bad_input_is_one_line_and_exit_2(case, tmp_path, warm_cache, capsys, monkeypatch, request):
    run_case(case, tmp_path, warm_cache, capsys, monkeypatch, request)


# ---------------------------------------------------------------- what must work

def _json_run(argv: list[str], capsys) -> dict:
    code, out, err = run_inprocess(argv, capsys)
    assert code == 0, err
    assert "Traceback" not in err
    return json.loads(out)


def test_ring_magnet_solid_cylinder_works_and_is_not_the_ring(tmp_path, warm_cache, capsys, monkeypatch):
    """`--set plate.r_in=0` (a solid cylinder: a structural change) works, and its model is not the
    ring's (once one cache key answered for both)."""
    for k, v in case_env(tmp_path, warm_cache).items():
        monkeypatch.setenv(k, v)
    monkeypatch.chdir(tmp_path)
    needs = ["--set", 'model.needs=["reduced"]', "--json"]
    solid = _json_run(["equilibrium", "ring_magnet", "--set", "plate.r_in=0", *needs], capsys)
    ring = _json_run(["equilibrium", "ring_magnet", *needs], capsys)
    assert solid["equilibria"] and ring["equilibria"]
    assert solid["max_mass"] != pytest.approx(ring["max_mass"], rel=1e-3)
    copy_artefacts(tmp_path / "cache", warm_cache)


def test_pole_is_no_equilibrium_and_hides_no_root(tmp_path, warm_cache, capsys, monkeypatch):
    """phi0 = rho/(z - a): the pole z = a is no equilibrium; the real one,
    m g + mu phi0''(z) = 0, i.e. z = a + (-2 mu rho / (m g))^(1/3), is found."""
    for k, v in case_env(tmp_path, warm_cache).items():
        monkeypatch.setenv(k, v)
    monkeypatch.chdir(tmp_path)
    rho, a, mu, m, g = 0.001, 0.05, -1.0, 0.02, 9.81
    scene = tmp_path / "pole.toml"
    scene.write_text(expression_scene("rho/(z - a)", {"rho": rho, "a": a}, name="pole"))
    res = _json_run(["equilibrium", str(scene), "--json"], capsys)
    zs = [e["z"] for e in res["equilibria"]]
    assert not any(abs(z - a) < 1e-3 * a for z in zs), zs
    assert [z for z in zs] == [pytest.approx(a + (-2 * mu * rho / (m * g)) ** (1 / 3), rel=1e-6)]
    copy_artefacts(tmp_path / "cache", warm_cache)


def test_closed_stdout_is_quiet(tmp_path):
    """A reader that went away (`levitron ... | head -1`) ends the command quietly, exit 0: here
    the pipe is closed before the command writes, so the write must fail."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), LEVITRON_CACHE=str(tmp_path / "cache"))
    proc = subprocess.Popen([sys.executable, "-m", "levitron.runtime.cli.main", "info", "thesis"], cwd=tmp_path,
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=60) == 0, err
    assert err == ""


def test_head_one_is_quiet(tmp_path, seed_cache):
    """The shell form of the same: `levitron field ... | head -1` (a long output)."""
    points = " ".join(f"--at 0,0,{0.05 + 0.001 * i:.3f}" for i in range(200))
    cmd = (f"{shlex.quote(sys.executable)} -m runtime.cli.main field thesis {points} | head -1; "
           "exit ${PIPESTATUS[0]}")
    env = dict(os.environ, PYTHONPATH=str(ROOT), LEVITRON_CACHE=str(seed_cache(tmp_path / "cache")))
    res = subprocess.run(["bash", "-c", cmd], check=False, cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert error_lines(res.stderr) == []      # at most the "levitron: compiling: ..." stage notes
    assert res.stdout.count("\n") == 1


def test_version(capsys):
    from importlib import metadata
    code, out, _ = run_inprocess(["--version"], capsys)
    assert code == 0
    try:
        expected = metadata.version("levitron")
    except metadata.PackageNotFoundError:
        import tomllib
        expected = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert out.strip() == f"levitron {expected}"


def test_python_m_runtime(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-m", "levitron.runtime", "--version"], check=False, cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 0 and res.stdout.startswith("levitron "), res.stderr
    res = subprocess.run([sys.executable, "-m", "levitron.runtime", "info", "nosuchscene"], check=False, cwd=tmp_path,
                         env=env, capture_output=True, text=True, timeout=60)
    assert res.returncode == 2 and res.stderr.count("\n") == 1, res.stderr


def test_internal_error_is_one_line_exit_3(capsys, monkeypatch):
    """A bug (any unexpected exception) is one line with its type, exit 3; LEVITRON_DEBUG=1 gives
    the traceback."""
    from levitron.runtime.cli.commands import info

    def broken(args):
        raise ZeroDivisionError("boom")
    monkeypatch.setattr(info, "run", broken)
    monkeypatch.delenv("LEVITRON_DEBUG", raising=False)
    code, out, err = run_inprocess(["info", "thesis"], capsys)
    assert code == 3 and out == ""
    assert err.splitlines() == [("levitron info: internal error: ZeroDivisionError: boom (set "
                                 "LEVITRON_DEBUG=1 for the traceback; please report it)")]
    monkeypatch.setenv("LEVITRON_DEBUG", "1")
    from levitron.runtime.cli.main import main
    with pytest.raises(ZeroDivisionError):
        main(["info", "thesis"])


def test_multi_line_message_is_cut_to_one_line(capsys, monkeypatch):
    from levitron.runtime.cli.commands import info
    from levitron.runtime.errors import UserError

    def wordy(args):
        raise UserError("first line\nsecond line\nthird line")
    monkeypatch.setattr(info, "run", wordy)
    monkeypatch.delenv("LEVITRON_DEBUG", raising=False)
    code, _, err = run_inprocess(["info", "thesis"], capsys)
    assert code == 2
    assert err.splitlines() == [("levitron info: error: first line [2 more lines: set "
                                 "LEVITRON_DEBUG=1 to see them]")]


def test_plot_path_is_checked_before_the_work(tmp_path):
    from levitron.runtime.errors import UserError
    from levitron.runtime.ui.plotting import check_plot_path
    for ok in ("a.png", "sub/dir/b.PDF", "c.svg"):
        assert check_plot_path(tmp_path / ok) == tmp_path / ok
    assert not (tmp_path / "sub").exists()           # checking creates nothing
    (tmp_path / "f").write_text("")
    for bad in ("out.toml", "noext", "f/x.png", ""):
        with pytest.raises(UserError):
            check_plot_path(tmp_path / bad)


def test_save_figure_makes_the_folder_and_leaves_no_temporary(tmp_path):
    from levitron.runtime.ui.plotting import pyplot, save_figure
    fig = pyplot().figure()
    path = save_figure(fig, tmp_path / "new" / "fig.svg")
    assert path.read_text().lstrip().startswith("<?xml")
    assert sorted(p.name for p in (tmp_path / "new").iterdir()) == ["fig.svg"]


def test_the_cli_does_not_import_sympy(tmp_path, seed_cache):
    """The runtime never imports sympy: importing the CLI and running a command leaves it out."""
    code = ("import sys, io, contextlib\n"
            "from levitron.runtime.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    rc = main(['equilibrium', 'thesis', '--json'])\n"
            "assert rc == 0, rc\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'sympy'))\n")
    env = dict(os.environ, PYTHONPATH=str(ROOT), LEVITRON_CACHE=str(seed_cache(tmp_path / "cache")))
    res = subprocess.run([sys.executable, "-c", code], check=False, cwd=tmp_path, env=env,
                         capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "[]"


def test_compile_error_is_one_line_exit_2(capsys, monkeypatch):
    """A compiler failure is one line with the compiler's first error (the whole output with
    LEVITRON_DEBUG=1), not the compiler's command line."""
    from levitron.runtime.model.cbuild import CompileError
    from levitron.runtime.cli.commands import info

    def fails(args):
        raise CompileError("C compilation failed (cc -Werror -o x.so model.c):\n"
                           "model.c:3:1: error: expected ';' before '}' token\n    3 | }\n")
    monkeypatch.setattr(info, "run", fails)
    monkeypatch.delenv("LEVITRON_DEBUG", raising=False)
    code, _, err = run_inprocess(["info", "thesis"], capsys)
    assert code == 2
    assert len(err.splitlines()) == 1
    assert "model.c:3:1: error: expected ';'" in err and "-Werror" not in err
