"""Portable where it claims to be: the compile cache is keyed on the CPU the code targets (not the flag
string), LEVITRON_CFLAGS_PORTABLE=1 builds for the architecture's baseline with the same answers, the
default cache folder comes from platformdirs (XDG on Linux) with LEVITRON_CACHE winning, the runtime
imports and locks without fcntl, and constraints.txt pins versions inside pyproject.toml's ranges."""
from __future__ import annotations

import ctypes
import os
import platform
import subprocess
import sys
import textwrap
import threading
import time
import tomllib
from pathlib import Path

import pytest
from packaging.requirements import Requirement

from levitron.runtime.errors import UserError
from levitron.runtime.model import cbuild, cpu_target, folder_lock

ROOT = Path(__file__).resolve().parents[3]
FMA_C = "#include <math.h>\ndouble f(double a, double b, double c) { return fma(a, b, c) + sqrt(a * b); }\n"


def _source(tmp_path: Path) -> Path:
    src = tmp_path / "f.c"
    src.write_text(FMA_C)
    return src


def test_the_cache_key_holds_the_probed_cpu(tmp_path, monkeypatch):
    """Two CPUs with the same flag string: two libraries and two objects, never one for both."""
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    src = _source(tmp_path)
    keys, libs, objs = [], [], []
    for cpu in ("x86_64 -march=native 1111", "x86_64 -march=native 2222"):
        monkeypatch.setattr(cbuild, "cpu_target", lambda cc, flags, cpu=cpu: cpu)
        keys.append(cbuild.source_hash([src], cbuild.DEFAULT_FLAGS))
        libs.append(cbuild.compile_shared([src]))
        objs.append(cbuild.compile_object(src))
    assert keys[0] != keys[1] and libs[0] != libs[1] and objs[0] != objs[1]
    assert libs[0].name == f"lev_{keys[0]}.so"


def test_native_is_resolved_once_per_process_and_is_not_the_flag_string(monkeypatch):
    """The probe is the compiler's ISA macros under the flags: two CPUs whose compiler defines other
    macros under the same -march=native give two strings; it runs once per process and compiler."""
    cc = cbuild.compiler()
    native = cpu_target.cpu_target(cc, cbuild.DEFAULT_FLAGS)
    assert native.startswith(platform.machine() + " -march=native ")
    seen, outputs = [], ["#define __SSE2__ 1\n", "#define __AVX2__ 1\n#define __FMA__ 1\n"]

    def fake_cc(cmd, **kw):
        seen.append(cmd)
        return subprocess.CompletedProcess(cmd, 0, stdout=outputs[len(seen) - 1], stderr="")

    monkeypatch.setattr(cpu_target.subprocess, "run", fake_cc)
    probes = [cpu_target.cpu_target.__wrapped__(cc, cbuild.DEFAULT_FLAGS) for _ in outputs]
    assert probes[0] != probes[1] and all(p.startswith(platform.machine() + " -march=native ") for p in probes)
    assert seen[0] == [cc, "-march=native", "-E", "-dM", "-x", "c", "-"]
    monkeypatch.undo()
    before = cpu_target.cpu_target.cache_info().hits
    assert cpu_target.cpu_target(cc, cbuild.DEFAULT_FLAGS) == native
    assert cpu_target.cpu_target.cache_info().hits == before + 1


@pytest.mark.skipif(platform.machine().lower() not in ("x86_64", "amd64"), reason="the x86-64 baseline")
def test_portable_mode_builds_the_baseline_with_the_same_answers(tmp_path, monkeypatch):
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    src = _source(tmp_path)
    native = cbuild.compile_shared([src])
    monkeypatch.setenv("LEVITRON_CFLAGS_PORTABLE", "1")
    flags = cpu_target.target_flags(cbuild.DEFAULT_FLAGS)
    assert "-march=native" not in flags and "-march=x86-64-v2" in flags
    portable = cbuild.compile_shared([src])
    assert portable != native
    assert cbuild.source_hash([src], cbuild.DEFAULT_FLAGS) == portable.name[4:-3]
    args = [(0.1, 0.7, -0.3), (1e16, 1 + 2 ** -52, -1e16), (3.0, 1 / 3, -1.0)]
    got = []
    for lib in (native, portable):
        f = ctypes.CDLL(str(lib)).f
        f.restype, f.argtypes = ctypes.c_double, [ctypes.c_double] * 3
        got.append([f(*a).hex() for a in args])
    assert got[0] == got[1]


@pytest.mark.parametrize("value", ["yes", "2", "native"])
def test_a_portable_setting_other_than_0_or_1_is_one_line(monkeypatch, value):
    monkeypatch.setenv("LEVITRON_CFLAGS_PORTABLE", value)
    with pytest.raises(UserError) as info:
        cpu_target.target_flags(cbuild.DEFAULT_FLAGS)
    msg = str(info.value)
    assert "\n" not in msg and "LEVITRON_CFLAGS_PORTABLE" in msg and "set it to 1" in msg
    monkeypatch.setenv("LEVITRON_CFLAGS_PORTABLE", "0")
    assert cpu_target.target_flags(cbuild.DEFAULT_FLAGS) == cbuild.DEFAULT_FLAGS


def _python(code: str, env: dict[str, str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], cwd=cwd, env=env, capture_output=True,
                          text=True, check=False)


def test_the_default_cache_folder_honours_xdg_and_levitron_cache_wins(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "LEVITRON_CACHE"}
    env.update(XDG_CACHE_HOME=str(tmp_path / "xdg"), PYTHONPATH=str(ROOT))
    res = _python("""
        import os
        from levitron.runtime.model.cbuild import cache_dir
        print(cache_dir())
        os.environ["LEVITRON_CACHE"] = "mine"
        print(cache_dir())
        """, env, tmp_path)
    assert res.returncode == 0, res.stderr
    default, mine = res.stdout.split()
    if sys.platform.startswith("linux"):
        assert default == str(tmp_path / "xdg" / "levitron")
    assert Path(default).is_dir() and mine == str(tmp_path / "mine")


def test_the_runtime_imports_builds_and_locks_without_fcntl(tmp_path):
    """A Python without fcntl (Windows): the runtime imports, links two sources through the object
    cache (whose lock is then a lock file) and leaves no lock file behind."""
    (tmp_path / "a.c").write_text("double g(double x);\ndouble f(double x) { return g(x) + 1.0; }\n")
    (tmp_path / "b.c").write_text("double g(double x) { return 2.0 * x; }\n")
    env = dict(os.environ, LEVITRON_CACHE=str(tmp_path / "cache"), PYTHONPATH=str(ROOT))
    res = _python("""
        import ctypes, sys
        from pathlib import Path
        sys.modules["fcntl"] = None
        from levitron.runtime.model import cbuild, locate
        from levitron.runtime.model.folder_lock import LOCK_NAME, flock_module, locked
        assert flock_module() is None
        lib = cbuild.compile_shared([Path("a.c"), Path("b.c")])
        f = ctypes.CDLL(str(lib)).f
        f.restype, f.argtypes = ctypes.c_double, [ctypes.c_double]
        with locked(Path(".")):
            held = Path(LOCK_NAME).exists()
        print(f(3.0), held, Path(LOCK_NAME).exists(), sorted(p.name for p in (lib.parent / "obj").iterdir()
                                                            if p.name.startswith(".")))
        """, env, tmp_path)
    assert res.returncode == 0, res.stderr
    assert res.stdout.split() == ["7.0", "True", "False", "[]"]


def test_the_lock_file_excludes_a_second_holder_and_breaks_a_stale_one(tmp_path):
    got = threading.Event()

    def second():
        with folder_lock.lock_file(tmp_path):
            got.set()

    with folder_lock.lock_file(tmp_path):
        t = threading.Thread(target=second)
        t.start()
        assert not got.wait(0.3)            # held: the second holder waits
    assert got.wait(30)
    t.join()
    assert not (tmp_path / folder_lock.LOCK_NAME).exists()
    stale = tmp_path / folder_lock.LOCK_NAME         # a killed holder's
    stale.write_text("12345\n")
    old = time.time() - folder_lock.STALE_S - 1
    os.utime(stale, (old, old))
    start = time.monotonic()
    with folder_lock.lock_file(tmp_path):
        assert stale.read_text() == f"{os.getpid()}\n"
    assert time.monotonic() - start < 5 and not stale.exists()


def test_constraints_pin_every_dependency_inside_the_packages_ranges():
    """constraints.txt (what CI installs) names one exact version of every dependency and of the test
    extra (but where the extra pins one itself), each inside pyproject.toml's range; the package itself
    pins none of sympy, casadi, jinja2."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    reqs = [Requirement(r) for r in project["dependencies"] + project["optional-dependencies"]["test"]]
    pins = {}
    for line in (ROOT / "constraints.txt").read_text().splitlines():
        line = line.split("#")[0].strip()
        if line:
            name, version = line.split("==")
            pins[name.lower().replace("_", "-")] = version
    for req in reqs:
        name = req.name.lower().replace("_", "-")
        if name not in pins and any(spec.operator == "==" for spec in req.specifier):
            continue
        assert name in pins, f"constraints.txt has no pin for {req.name}"
        assert req.specifier.contains(pins[name], prereleases=True), f"{name}=={pins[name]} outside {req}"
    ranged = {r.name.lower(): str(r.specifier) for r in reqs}
    assert all("==" not in ranged[n] for n in ("sympy", "casadi", "jinja2"))
