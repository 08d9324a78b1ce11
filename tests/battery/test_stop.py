"""Every command stops when asked: SIGINT or SIGTERM ends it within seconds, its worker processes
with it, and it exits 128 + the signal's number (runtime/model/processes.py stop_on_signals, the
pools' end in runtime/scan/runners.py).

Before: a parallel `launch` stopped 83 s after SIGINT (its pool waited for the chunks in flight), a
parallel `trim` 9 s after SIGTERM, and `stability ... --level-tolerance` with the magnet off its
axis ignored both (CasADi's CVODES turned the interruption into a RuntimeError, read as "no orbit
here", and the continuation went on).
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.helpers.hostile import ROOT, alive, children

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")

STOP_S = 5.0          # the promise: stopped within this after the signal
WAIT_S = 30.0         # how long a test waits before calling a stop a failure


def _handles_sigterm(pid: int) -> bool:
    """Whether the process has its SIGTERM handler (the CLI's main is running the command)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    caught = next((ln.split()[1] for ln in status.splitlines() if ln.startswith("SigCgt:")), "0")
    return bool(int(caught, 16) >> (signal.SIGTERM - 1) & 1)


def _workers(seen: dict[int, str]) -> list[int]:
    return [p for p, cmd in seen.items() if "spawn_main" in cmd]


def _stopped(args, sig: int, cache: Path, tmp_path: Path, workers: int = 0, settle: float = 3.0):
    """Run `levitron ARGS`; once it runs (its SIGTERM handler in place and, with `workers`, that
    many worker processes started) and `settle` seconds more, send `sig`. Returns (exit code,
    seconds from the signal to the exit, the children seen, stderr); fails if the command ended
    before the signal (it then tested nothing)."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), LEVITRON_CACHE=str(cache))
    env.pop("LEVITRON_DEBUG", None)
    proc = subprocess.Popen([sys.executable, "-m", "levitron.runtime.cli.main", *args], cwd=tmp_path,
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                            start_new_session=True)
    seen: dict[int, str] = {}
    try:
        deadline, ready = time.monotonic() + 120, None
        while time.monotonic() < deadline and proc.poll() is None:
            seen.update(children(proc.pid))
            if ready is None and _handles_sigterm(proc.pid) and len(_workers(seen)) >= workers:
                ready = time.monotonic()
            if ready is not None and time.monotonic() > ready + settle:
                break
            time.sleep(0.1)
        assert proc.poll() is None, f"the command ended before the signal: {proc.stderr.read()[-2000:]}"
        proc.send_signal(sig)
        sent = time.monotonic()
        try:
            _, err = proc.communicate(timeout=WAIT_S)
        except subprocess.TimeoutExpired:
            err = "(still running)"
        took = time.monotonic() - sent
        deadline = time.monotonic() + 1.0       # the resource tracker leaves as its pipe closes
        while time.monotonic() < deadline and any(alive(p) for p in seen):
            time.sleep(0.1)
        return proc.returncode, took, seen, err
    finally:
        if proc.poll() is None:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
        for p in seen:          # what this test started and a failure left behind
            if alive(p):
                os.kill(p, signal.SIGKILL)


def _assert_stopped(result, sig: int, workers: int = 0) -> None:
    code, took, seen, err = result
    assert len(_workers(seen)) >= workers, f"no worker was seen: the test tested nothing ({seen})"
    assert took <= STOP_S, f"stopped {took:.1f} s after {sig.name} (at most {STOP_S:g} s): {err[-1500:]}"
    assert code == 128 + sig, f"exit {code} after {sig.name}: {err[-1500:]}"
    assert "interrupted" in err and "Traceback" not in err, err[-1500:]
    assert not [p for p in seen if alive(p)], f"left running after the stop: {seen}"


LAUNCH = ["launch", "thesis_air", "--n", "30000", "--t-end", "30", "--workers", "2"]


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_parallel_launch_stops_with_its_workers(sig, tmp_path, warm_cache):
    """Chunks in flight (minutes of Monte Carlo) are not waited for: the workers are killed."""
    _assert_stopped(_stopped(LAUNCH, sig, warm_cache, tmp_path, workers=2), sig, workers=2)


SCAN = ["scan", "thesis", "--set", "top.mass=0.0515", "--spin", "300:3000:30", "--tilt", "0.01:0.1:30",
        "--t-end", "60", "--workers", "2"]


def test_a_parallel_scan_stops_with_its_workers(tmp_path, warm_cache):
    """A map's chunks in flight are not waited for either (a new case: held when first tried)."""
    _assert_stopped(_stopped(SCAN, signal.SIGTERM, warm_cache, tmp_path, workers=2), signal.SIGTERM, workers=2)


def test_a_parallel_trim_stops_with_its_workers(tmp_path, warm_cache):
    """The design's kept pool (runtime/scan/runners.py KeptPool) ends with the command."""
    result = _stopped(["trim", "thesis_air", "--workers", "2"], signal.SIGTERM, warm_cache, tmp_path,
                      workers=2)
    _assert_stopped(result, signal.SIGTERM, workers=2)


API_LAUNCH = """
import signal
import time
import levitron as lev
# Ctrl-C raises KeyboardInterrupt, as in every interactive Python; set here because a child inherits an
# ignored SIGINT from its parent (a test runner's worker may have one), and then Python installs no handler
signal.signal(signal.SIGINT, signal.default_int_handler)
study = lev.load("thesis_air")
try:
    study.launch(n=30000, t_end=30, workers=2)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    time.sleep(60)          # alive: its workers must be gone by now, not by dying with it
"""


def test_ctrl_c_in_the_apis_parallel_launch_ends_its_workers(tmp_path, warm_cache):
    """A KeyboardInterrupt in Study.launch(workers=2) kills the pool's workers before it leaves
    the call (before: the pool waited for its chunks in flight, a minute and more)."""
    import select
    env = dict(os.environ, PYTHONPATH=str(ROOT), LEVITRON_CACHE=str(warm_cache))
    proc = subprocess.Popen([sys.executable, "-c", API_LAUNCH], cwd=tmp_path, env=env, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, start_new_session=True)
    seen: dict[int, str] = {}
    try:
        deadline, ready = time.monotonic() + 120, None
        while time.monotonic() < deadline and proc.poll() is None:
            seen.update(children(proc.pid))
            if ready is None and len(_workers(seen)) >= 2:
                ready = time.monotonic()
            if ready is not None and time.monotonic() > ready + 3:
                break
            time.sleep(0.1)
        assert proc.poll() is None and len(_workers(seen)) >= 2, seen
        proc.send_signal(signal.SIGINT)
        sent = time.monotonic()
        assert select.select([proc.stdout], [], [], WAIT_S)[0], "the call did not return"
        assert proc.stdout.readline().strip() == "interrupted"
        took = time.monotonic() - sent
        assert took <= STOP_S, f"Study.launch returned {took:.1f} s after Ctrl-C"
        assert proc.poll() is None
        assert not [p for p in _workers(seen) if alive(p)], f"workers left running: {seen}"
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        for p in seen:
            if alive(p):
                os.kill(p, signal.SIGKILL)


@pytest.mark.parametrize("base", ["level", "tilted"])
def test_the_level_tolerance_of_a_tilted_magnet_stops(base, tmp_path, warm_cache):
    """The magnet's and the base's tolerances: periodic orbits shot by CasADi's CVODES (over a
    tilted base, minutes), whose interruption is not read as "no orbit here"."""
    args = ["stability", "thesis_stable", "--set", "top.moment_tilt=0.05", "--level-tolerance", "--json"]
    if base == "tilted":
        args[4:4] = ["--set", "plate.tilt=0.0005"]
    _assert_stopped(_stopped(args, signal.SIGTERM, warm_cache, tmp_path, settle=2.0), signal.SIGTERM)
