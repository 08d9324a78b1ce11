"""The bad-input battery's machinery (tests/battery/): a Case, the scenes cases edit, and run_case, which
runs a case through the real entry point and asserts what every refusal must be:
  * exit code 2 (3 is the CLI's "internal error": a bug, not a message for bad input);
  * exactly one error line on stderr, mentioning what the case names (a regular expression).
    Besides it stderr may only hold progress notes of the "levitron: ..." logger (e.g. "deriving
    the model of scene ..."), never a second error line; stdout stays empty;
  * no "Traceback" anywhere, and no marker of runtime/words.py («t_end», ‹0.1|m›) left unworded;
  * generated/ unchanged (names, sizes and mtimes of every entry);
  * nothing half-written in the cache (a fresh LEVITRON_CACHE per case): no temporary names (a
    leading '.', 'tmp'), every derived folder complete (its manifest.json present).
BOUNDED cases (unbounded work once) must return within a time limit: either refused (the
checks above) or run to a "step_budget" status (exit 0, the --json result says so).
A case runs in-process (`runtime.cli.main.main(argv)`: fast) or, where the work could be unbounded
(a time limit) or a crash would take pytest down, as a `python -m levitron.runtime.cli.main` subprocess.
The session's warm cache that cases copy from is the fixture `warm_cache` (tests/battery/conftest.py).
"""
from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
GENERATED = ROOT / "generated"
THESIS = (ROOT / "scenes" / "thesis.toml").read_text()


def edit(text: str, old: str, new: str) -> str:
    """`text` with `old` replaced by `new`; `old` must occur (a case that edits nothing tests nothing)."""
    assert old in text, f"{old!r} is not in the base scene: the case would test nothing"
    return text.replace(old, new)


def thesis(old: str, new: str) -> str:
    return edit(THESIS, old, new)


def expression_scene(formula: str, params: dict | None = None, name: str = "expr") -> str:
    """A small expression-plate scene (the reduced model only: the cheapest derivation)."""
    lines = [f'name = "{name}"', "g = 9.81", "[top]", "mass = 0.02", "A = 2.2e-6", "C = 1.32e-6",
             "moment = -1.0", "[plate]", 'kind = "expression"', f'phi0 = "{formula}"']
    if params:
        lines.append("[plate.params]")
        lines += [f"{k} = {v!r}" for k, v in params.items()]
    lines += ["[field]", "order = 2", "[model]", 'needs = ["reduced"]']
    return "\n".join(lines) + "\n"



@dataclass
class Case:
    id: str
    argv: str
    mention: str                      # a regular expression the error line must match (case-blind)
    toml: str | None = None           # written to {tmp}/<name>.toml and passed as {scene}
    setup: Callable | None = None
    sub: bool = False                 # run as a subprocess (with a time limit)
    bounded: bool = False             # refusal, or exit 0 with status "step_budget"
    timeout: float = 30.0
    tags: tuple = field(default=())


# ---------------------------------------------------------------- checks

def snapshot(folder: Path) -> dict:
    """Every entry below `folder`: (size, mtime) by relative path."""
    out = {}
    for p in sorted(folder.rglob("*")):
        st = p.lstat()
        out[p.relative_to(folder).as_posix()] = (st.st_size if p.is_file() else None, st.st_mtime_ns)
    return out


def cache_leftovers(cache: Path) -> list[str]:
    """What a failed command must not leave in the cache: temporary names, half-written models."""
    if not cache.is_dir():
        return []
    bad = []
    for p in cache.rglob("*"):
        rel = p.relative_to(cache).as_posix()
        if p.name.startswith(".") or "tmp" in p.name.lower():
            bad.append(rel)
    derived = cache / "derived"
    if derived.is_dir():
        bad += [f"derived/{d.name} (no manifest.json)" for d in derived.iterdir()
                if d.is_dir() and not (d / "manifest.json").is_file()]
    return bad


def error_lines(err: str) -> list[str]:
    """The error lines of stderr: all but the "levitron: ..." progress notes."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    return [ln for ln in lines if not (ln.startswith("levitron: ") and ": error:" not in ln)]


# ---------------------------------------------------------------- a warm, shared cache
# Compiled libraries and derived models are copied into each case's fresh cache from a session
# cache (seeded from the developer's cache, never written back there), so that a case compiles or
# derives only what no earlier case made; what a case makes whole is kept for the next ones.

def place(src, dst) -> None:
    """A hard link where the file system allows one, else a copy: the cache's files are only ever
    replaced by a rename, never written in place, so a case cannot reach another's through a link
    (a copy per case of a 40 MB cache cost 0.2 s, some 50 s of the suite)."""
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)


def copy_artefacts(src: Path, dst: Path) -> None:
    """Copy finished artefacts (lev_* libraries, the objects they are linked from, their stamps;
    complete derived models), as hard links (_place)."""
    if not src.is_dir():
        return
    for f in [*src.glob("lev_*"), *src.glob("obj/[!.]*")]:
        if f.is_file() and not (dst / f.relative_to(src)).exists():
            (dst / f.relative_to(src)).parent.mkdir(exist_ok=True)
            place(f, dst / f.relative_to(src))
    for d in (src / "derived").glob("*") if (src / "derived").is_dir() else ():
        if d.is_dir() and not d.name.startswith(".") and (d / "manifest.json").is_file() \
                and not (dst / "derived" / d.name).exists():
            shutil.copytree(d, dst / "derived" / d.name, copy_function=place)


def case_env(tmp_path: Path, warm: Path) -> dict:
    cache = tmp_path / "cache"
    cache.mkdir()
    copy_artefacts(warm, cache)
    return {"LEVITRON_CACHE": str(cache)}


def run_inprocess(argv: list[str], capsys) -> tuple[int, str, str]:
    from levitron.runtime.cli.main import main
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
    out, err = capsys.readouterr()
    return code, out, err


def run_subprocess(argv: list[str], env: dict, cwd: Path, timeout: float) -> tuple[int, str, str]:
    full_env = dict(os.environ, PYTHONPATH=str(ROOT), **env)
    full_env.pop("LEVITRON_DEBUG", None)
    proc = subprocess.Popen([sys.executable, "-m", "levitron.runtime.cli.main", *argv], cwd=cwd, env=full_env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)      # the command and its derive subprocess
        proc.communicate()
        pytest.fail(f"`levitron {' '.join(argv)}` did not return within {timeout:g} s")
    return proc.returncode, out, err


def run_case(case: Case, tmp_path: Path, warm_cache: Path, capsys, monkeypatch, request) -> None:
    """Run one Case through the real entry point and assert the battery's checks (the module's
    docstring): exit 2 and one error line naming `case.mention`, or, for a BOUNDED case, exit 0 with
    status "step_budget"; no traceback, generated/ untouched, nothing half-written in the cache."""
    env = case_env(tmp_path, warm_cache)
    monkeypatch.delenv("LEVITRON_DEBUG", raising=False)
    monkeypatch.chdir(tmp_path)                   # relative default outputs (out/, reports/) land here
    subs = {"tmp": str(tmp_path)}
    if case.toml is not None:
        name = re.search(r'^name = "([^"]*)"', case.toml, re.MULTILINE)
        scene = tmp_path / f"{name.group(1) if name else 'scene'}.toml"
        scene.write_text(case.toml)
        subs["scene"] = str(scene)
    if case.setup is not None:
        case.setup(tmp_path, env, request)
    argv = [a.format(**subs) for a in shlex.split(case.argv)]
    cache = Path(env["LEVITRON_CACHE"])
    before = snapshot(GENERATED)

    if case.sub:
        code, out, err = run_subprocess(argv, env, tmp_path, case.timeout)
    else:
        for k, v in env.items():
            monkeypatch.setenv(k, v)
        code, out, err = run_inprocess(argv, capsys)

    assert "Traceback" not in out + err, err
    assert "«" not in out + err and "‹" not in out + err, \
        f"a runtime marker reached the user unworded: {(out + err)[-2000:]}"
    assert snapshot(GENERATED) == before, "generated/ changed"
    assert cache_leftovers(cache) == [], "left in the cache"
    if case.bounded and code == 0:
        status = json.loads(out).get("status")
        assert status == "step_budget", f"exit 0 with status {status!r}: neither refused nor bounded"
    else:
        assert code == 2, f"exit {code}\nstdout: {out[-2000:]}\nstderr: {err[-2000:]}"
        errors = error_lines(err)
        assert len(errors) == 1, err
        assert errors[0].startswith("levitron"), errors[0]
        assert re.search(case.mention, errors[0], re.IGNORECASE), f"{case.mention!r} not in: {errors[0]}"
        assert out.strip() == "", out
    if cache.is_dir() and cache.parent == tmp_path and os.access(cache, os.W_OK):
        copy_artefacts(cache, warm_cache)
