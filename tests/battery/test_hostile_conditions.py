"""The third battery (issue 31), by class: each test stands for a class of defects, runs the real
command line under the hostile conditions of tests/helpers/hostile.py, and failed before its fix.

Outputs: every file the tool writes (simulate --save / Simulation.save, --plot, --animate, report
--out, optimize --write-scene) is written to a temporary beside it and renamed
(runtime/ui/atomic.py), so a file-size limit, a full disk or a kill leaves the old file whole,
concurrent writers leave one whole file, the mode is the umask's, and the debris of killed runs
(output temporaries, $CACHE/obj temporaries, report scratch folders, generated/.<scene>.new-*)
is swept by the next run.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from tests.helpers.hostile import aged, cli, dead_pid, refused

SIM = ["simulate", "thesis_stable", "--spin", "1000", "--t-end", "0.05"]
API = ("import sys, levitron as lev\ntry:\n    {}\nexcept lev.UserError as exc:\n"
       "    print(f'levitron: error: {{exc}}', file=sys.stderr)\n    sys.exit(2)\n")
# ^ an API call: its UserError shown as the command line shows one
API_SAVE = API.format("lev.load('thesis_stable').simulate(spin=1000.0, t_end=0.05).save(sys.argv[1])")
# (id, argv with {out}, file name, the flag the error names, RLIMIT_FSIZE below the file, API code)
WRITERS = [
    ("save-csv", [*SIM, "--save", "{out}"], "t.csv", r"--save", 200, None),
    ("save-npz", [*SIM, "--save", "{out}"], "t.npz", r"--save", 200, None),
    ("api-save", ["{out}"], "t.csv", r"Simulation.save", 200, API_SAVE),
    ("plot", [*SIM, "--plot", "{out}"], "p.png", r"--plot", 200, None),
    ("animate", [*SIM, "--animate", "{out}"], "a.html", r"--animate", 200, None),
    ("report", ["report", "thesis_stable", "--out", "{out}"], "r.html", r"--out", 400_000, None),
    ("write-scene", ["optimize", "loop", "--maximize", "spin-ratio", "--vary", "top.mass=0.0197:0.0209",
                     "--constrain", "stiffness>=0.5", "--write-scene", "{out}"], "best.toml",
     r"--write-scene", 200, None),
]


def _run(case, folder: Path, **kw):
    _, argv, name, _, _, code = case
    return cli([a.format(out=folder / name) for a in argv], cwd=folder, code=code, **kw)


@pytest.mark.parametrize("case", WRITERS, ids=[c[0] for c in WRITERS])
def test_a_write_that_fails_leaves_the_old_file_whole(case, tmp_path):
    """Under a file-size limit (what a full disk does to a write) the old file stays, byte for
    byte, and the error names the flag; before: simulate --save and Simulation.save truncated it."""
    first = _run(case, tmp_path, umask=0o022)
    assert first.returncode == 0, first.stderr[-2000:]
    out = tmp_path / case[2]
    good = out.read_bytes()
    assert len(good) > case[4], "the file is smaller than the limit: the case tests nothing"
    assert out.stat().st_mode & 0o777 == 0o644, oct(out.stat().st_mode)   # before: 0600 (--write-scene)
    res = _run(case, tmp_path, fsize=case[4])
    refused(res, case[3] + r".*(too large|space)")
    assert out.read_bytes() == good
    assert sorted(p.name for p in tmp_path.iterdir()) == [case[2]], "a temporary was left"


def test_a_kill_mid_write_leaves_the_old_file_and_the_next_run_sweeps(tmp_path):
    """SIGKILL after the samples are written, before the rename (LEVITRON_FAULT): the old file is
    whole; the dead writer's temporary goes with the next save into that folder."""
    case = WRITERS[0]
    assert _run(case, tmp_path).returncode == 0
    out = tmp_path / case[2]
    good = out.read_bytes()
    marker = tmp_path.parent / f"{tmp_path.name}-marker"
    res = _run(case, tmp_path, env={"LEVITRON_FAULT": f"output.written:{marker}"})
    assert marker.exists() and res.returncode == -9, (res.returncode, res.stderr[-2000:])
    assert out.read_bytes() == good
    debris = [p for p in tmp_path.iterdir() if p != out]
    assert debris, "the kill left no temporary: the test tested nothing"
    aged(debris)
    assert _run(case, tmp_path).returncode == 0
    assert sorted(tmp_path.iterdir()) == [out]


def test_concurrent_saves_leave_one_whole_file(tmp_path):
    """Two runs saving to one file at once: the file is one of the two, whole (before: their
    rows interleaved into an unreadable CSV, and both said "saved")."""
    argv = [*SIM, "--n-out", "4000", "--save"]
    alone = {}
    for spin in ("1000", "1200"):
        a = argv[:3] + [spin] + argv[4:]
        assert cli([*a, tmp_path / f"alone-{spin}.csv"], cwd=tmp_path).returncode == 0
        alone[spin] = (tmp_path / f"alone-{spin}.csv").read_bytes()
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2]))
    for _ in range(3):
        procs = [subprocess.Popen([sys.executable, "-m", "levitron.runtime.cli.main", *argv[:3], spin,
                                   *argv[4:], str(tmp_path / "both.csv")], cwd=tmp_path, env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
                 for spin in alone]
        assert [p.wait(timeout=300) for p in procs] == [0, 0]
        assert (tmp_path / "both.csv").read_bytes() in alone.values()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["alone-1000.csv", "alone-1200.csv", "both.csv"]


def test_debris_of_killed_runs_is_swept_by_the_next_run(tmp_path, seed_cache):
    """What a kill -9 leaves, owned by a dead process and older than the sweeps' minute, is gone
    after the next run: $CACHE/obj temporaries (a compiler killed) and the report's scratch
    folders in $TMPDIR; a live owner's and a young one are kept. (Before: neither was swept.)"""
    cache = seed_cache(tmp_path / "cache")
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    dead = dead_pid()
    obj_debris = [cache / "obj" / f".{'ab' * 12}_{dead}_x1_y.o", cache / "obj" / f".{'ab' * 12}_{dead}_q.sha256"]
    report_debris = scratch / f"levitron-report-{dead}-abc"
    young = scratch / f"levitron-report-{dead}-young"
    live = scratch / f"levitron-report-{os.getpid()}-live"
    for p in obj_debris:
        p.write_bytes(b"half an object")
    for d in (report_debris, young, live):
        d.mkdir()
        (d / "fig.png").write_bytes(b"half a figure")
    aged([*obj_debris, report_debris, live])
    res = cli(["report", "thesis_stable", "--out", tmp_path / "r.html"], cwd=tmp_path,
              env={"LEVITRON_CACHE": str(cache), "TMPDIR": str(scratch)})
    assert res.returncode == 0, res.stderr[-2000:]
    assert not any(p.exists() for p in [*obj_debris, report_debris])
    assert young.exists() and live.exists()
    assert sorted(p.name for p in scratch.iterdir()) == sorted([young.name, live.name])


def test_generated_debris_is_swept(tmp_path):
    """generated/.<scene>.new-* of a killed `make derive` is swept by the next run's first use of
    the cache (runtime/model/cbuild.py cache_dir), even when that scene is current and never
    written again; a missing folder gets its old copy back first (derive/atomic_dir.py)."""
    from levitron.runtime.model.cache_sweep import sweep_generated
    gen = tmp_path / "generated"
    (gen / "thesis").mkdir(parents=True)
    dead = dead_pid()
    stale = [gen / f".thesis.new-{dead}-abc", gen / f".thesis.old-{dead}-def"]
    kept = [gen / f".thesis.new-{os.getpid()}-mine", gen / f".loop.new-{dead}-young"]
    old_copy = gen / f".square.old-{dead}-ghi"
    for d in (*stale, *kept, old_copy):
        d.mkdir()
        (d / "manifest.json").write_text("{}")
    aged([*stale, kept[0], old_copy])
    gone = sweep_generated(gen)
    assert sorted(gone) == sorted(stale)
    assert all(d.exists() for d in kept)
    assert (gen / "square" / "manifest.json").is_file() and not old_copy.exists()


def test_the_written_table_reads_back(tmp_path):
    """The atomic --save is the same table: CSV and .npz (an upper-case suffix too) read back equal."""
    from levitron.runtime.simulate import trajectory_file
    table = np.arange(12.0).reshape(4, 3) / 7
    for name in ("a.csv", "b.npz", "c.NPZ"):
        trajectory_file.write(tmp_path / name, ["t", "x", "y"], table)
        names, back = trajectory_file.read(tmp_path / name)
        assert names == ["t", "x", "y"] and np.array_equal(back, table)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv", "b.npz", "c.NPZ"]



# the writes of the runtime that are not on an output temporary, and why each is safe
NOT_ON_A_TEMPORARY = {
    ("runtime/model/locate.py", "snapshot"): "inside the derivation's own temporary folder (one rename)",
    ("runtime/simulate/animation_video.py", "str(path)"): "render() is handed animation.write's temporary",
    # an answer's save action (issue 29), not numpy's save: each writes through
    # trajectory_file.write_columns, on atomic.output's temporary (checked above, in its module)
    ("runtime/cli/commands/simulate.py", "args.save"): "Simulation.save: trajectory_file.write_columns",
    ("runtime/cli/commands/scan.py", "args.save"): "Scan.save: trajectory_file.write_columns",
    ("runtime/cli/commands/launch.py", "args.save"): "LaunchOdds.save: trajectory_file.write_columns",
    # a notebook table's figure, drawn into memory (io.StringIO / io.BytesIO), never a file
    ("runtime/ui/answer_view.py", "buf"): "an in-memory SVG for _repr_html_",
    ("runtime/ui/answer_view.py", "raw"): "an in-memory PNG for _repr_html_",
}


def test_every_write_of_the_runtime_goes_to_a_temporary():
    """No module of runtime/ writes a file in place: every open(..., 'w'), write_text, write_bytes,
    savefig, savetxt, savez or save is on a temporary (a name starting with tmp, or a handle on
    one), whose rename runtime/ui/atomic.py (or the cache's own protocol) does; each exception of
    NOT_ON_A_TEMPORARY says why (before: bench, report and figure files, --save and --write-scene were written in
    place or by private copies of the rename)."""
    import ast
    root = Path(__file__).resolve().parents[2]
    in_place = []
    for path in sorted((root / "runtime").rglob("*.py")):
        rel = str(path.relative_to(root))
        if rel == "runtime/ui/atomic.py":
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Call):
                continue
            f = node.func
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            mode = node.args[1].value if name == "open" and len(node.args) > 1 and isinstance(
                node.args[1], ast.Constant) else ""
            if name in ("write_text", "write_bytes") and isinstance(f, ast.Attribute):
                target = f.value
            elif (name in ("savefig", "savetxt", "savez", "save") and isinstance(f, ast.Attribute)) or (
                    name == "open" and any(m in str(mode) for m in "wax+")):
                target = node.args[0] if node.args else None
            else:
                continue
            text = ast.unparse(target) if target is not None else ""
            if text.startswith(("tmp", "Path(tmp")) or text == "fh" or (rel, text) in NOT_ON_A_TEMPORARY:
                continue
            in_place.append(f"{rel}:{node.lineno} {ast.unparse(node)[:70]}")
    assert in_place == [], "written in place:\n" + "\n".join(in_place)


# ---------------------------------------------------------------- one validation per quantity; no verdict, no odds

AIR = ["launch", "thesis_air", "--n", "4", "--t-end", "0.05"]
FACTOR = r"remanence factor .* is not positive"


def _api(call: str, folder: Path):
    return cli([], cwd=folder, code=API.format(call))


def test_a_temperature_spread_takes_the_check_of_the_temperature(tmp_path):
    """The launch spread's temperatures pass the one check of a temperature (scene/load.py
    temperature_factors, as --temperature does), at both ends of its range and from every source:
    the flag, the [launch] table, the API. Before: 'launch --temperature-spread 1353.33' said
    '100 % float' with the plate's remanence factor at -1.67; --temperature refused it."""
    single = refused(cli(["equilibrium", "thesis_air", "--temperature", "1353.33"], cwd=tmp_path), FACTOR)
    flag = refused(cli([*AIR, "--temperature-spread", "1353.33"], cwd=tmp_path), r"--temperature-spread 1353.33")
    assert flag.split("error: ", 1)[1].split(": ", 1)[1] == single.split("error: ", 1)[1], "not the same check"
    refused(cli([*AIR, "--temperature-spread", "uniform:20,1400"], cwd=tmp_path), FACTOR)
    refused(cli([*AIR, "--temperature-spread", "normal:600,100"], cwd=tmp_path), FACTOR + r"|8 sd")
    scene = tmp_path / "warm.toml"
    scene.write_text((Path(__file__).resolve().parents[2] / "scenes" / "thesis_air.toml").read_text()
                     + '\n[launch]\ntemperature = "uniform:20,1400"\n')
    refused(cli(["launch", scene, "--n", "4", "--t-end", "0.05"], cwd=tmp_path), FACTOR)
    refused(_api("lev.load('thesis_air').launch(n=4, t_end=0.05, inputs={'temperature': 'uniform:20,1400'})",
                 tmp_path), FACTOR)
    ok = cli([*AIR, "--temperature-spread", "uniform:10,30", "--json"], cwd=tmp_path)   # a sane spread runs
    assert ok.returncode == 0, ok.stderr[-2000:]


def test_runs_without_a_verdict_are_not_falls():
    """The odds count successes among the runs with a verdict: a run that stopped early (step
    budget) short of the success time is neither (before: a fall). Hand count: 10 runs, 3 reach
    the success time (one of them by a run that stopped after it), 4 fell (left_box, cannot_hover),
    3 stopped early before it: 3 / 7, Wilson of (3, 7)."""
    from levitron.runtime.scan import launch_odds as mc
    from levitron.runtime.scan import launch_inputs as li
    plan = mc.Plan("thesis_air", (), tuple((k, mc.Dist("normal", 1.0, 0.1)) for k in li.INPUTS), 10, 0,
                   2.0, "dop853", 1e-8)
    pts = [("completed", 2.0), ("completed", 2.0), ("step_budget", 1.5), ("left_box", 0.3),
           ("left_box", 0.0), ("cannot_hover", 0.0), ("left_box", 0.9), ("step_budget", 0.2),
           ("nonfinite", 0.4), ("step_underflow", 0.1)]
    points = [{"i": i, "t": t, "status": s, "m": 0.05, "mu": -0.6, "z_s": 0.1} for i, (s, t) in enumerate(pts)]
    r = mc.summarize(plan, [{"points": points}], 1.0, None, 0.1, None)
    assert (r["successes"], r["no_verdict"], r["n"]) == (3, 3, 10)
    assert r["probability"] == 3 / 7 and r["probability_ci95"] == list(mc.wilson(3, 7))
    assert r["verdicts"] == [True, True, True, False, False, False, False, None, None, None]


def test_a_run_that_stops_early_gives_no_verdict(tmp_path):
    """A step-budget run: simulate says 'no verdict', never 'still floating' (before: 'still
    floating after 6.38 ms (the whole run)'); a launch whose every run stopped early gives no
    odds (before: '0 % float')."""
    args = ["--t-end", "0.01", "--set", "top.spin_decay_time=1e-7"]
    res = cli(["simulate", "thesis_air", "--spin", "1122", *args], cwd=tmp_path)
    assert res.returncode == 0, res.stderr[-2000:]
    head = res.stdout.splitlines()[0]
    assert head.startswith("no verdict: the run stopped early (step_budget)"), head
    assert "still floating" not in res.stdout and "floats" not in res.stdout
    refused(cli(["launch", "thesis_air", "--n", "4", *args], cwd=tmp_path), r"stopped early without a verdict")


# ---------------------------------------------------------------- every size a user can ask for is bounded

DESIGN = ["optimize", "loop", "--maximize", "spin-ratio", "--vary", "top.mass=0.0197:0.0209",
          "--constrain", "stiffness>=0.5"]
THREE = ["--vary", "top.A=2e-6:2.4e-6", "--vary", "top.C=1.2e-6:1.4e-6"]
SIZES = [
    ("grid-1000000", [*DESIGN, "--grid", "1000000"], r"--grid 1000000 .*20000 .*--grid 20000 or fewer"),
    ("grid-200-three-keys", [*DESIGN, *THREE, "--grid", "200"], r"--grid 200 with 3 keys .*--grid 27 or fewer"),
    ("n-out-1e7", [*SIM, "--n-out", "10000000"], r"--n-out .*at most 1000000"),
    ("launch-n-1e7", ["launch", "thesis_air", "--n", "10000000"], r"--n 10000000 .*1000000"),
    ("fit-dev-zero", ["optimize", "thesis_stable", "--fit", "/dev/zero", "--vary", "plate.murho=-0.003:-0.0023"],
     r"--fit /dev/zero: longer than 16 MB"),
]


@pytest.mark.parametrize("argv,mention", [c[1:] for c in SIZES], ids=[c[0] for c in SIZES])
def test_every_size_has_a_bound_named_in_one_line(argv, mention, tmp_path):
    """Refused at once, naming the flag and its limit, within 2 GB of address space (before: --grid
    ran on past 120 s, --fit /dev/zero read until the memory ran out, --n-out named no flag)."""
    res = cli(argv, cwd=tmp_path, timeout=60, memory=2 * 2**30)
    refused(res, mention)


# ---------------------------------------------------------------- child processes

def test_workers_are_capped_and_die_with_their_parent(tmp_path):
    """`launch --workers 12` starts at most the usable cores' workers (D11), and after a kill -9
    of the command every child it started (the workers, multiprocessing's resource tracker) is
    gone within seconds (before: they lived on for minutes, D9)."""
    from tests.helpers.hostile import alive, children
    from levitron.runtime.scan.runners import usable_cores
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2]))
    proc = subprocess.Popen([sys.executable, "-m", "levitron.runtime.cli.main", "launch", "thesis_air",
                             "--n", "4000", "--t-end", "20", "--workers", "12"], cwd=tmp_path, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    seen: dict[int, str] = {}
    try:
        deadline, first = time.time() + 120, None
        while time.time() < deadline and proc.poll() is None:
            seen.update(children(proc.pid))
            if first is None and any("spawn_main" in cmd for cmd in seen.values()):
                first = time.time()            # the pool starts its workers at once: watch 3 s more
            if first is not None and time.time() > first + 3:
                break
            time.sleep(0.1)
        assert proc.poll() is None, "the launch ended before its workers were seen"
        workers = [p for p, cmd in seen.items() if "spawn_main" in cmd]
        assert 1 <= len(workers) <= usable_cores(), seen
        proc.kill()
        proc.wait()
        deadline = time.time() + 15
        while time.time() < deadline and any(alive(p) for p in seen):
            time.sleep(0.2)
        assert not [p for p in seen if alive(p)], f"left running after the kill: {seen}"
    finally:
        if proc.poll() is None:
            proc.kill()
        for p in seen:               # what this test started and a failure left behind
            if alive(p):
                os.kill(p, signal.SIGKILL)


def test_a_script_without_the_main_guard_is_told_so(tmp_path):
    """Worker processes import the user's script again: without `if __name__ == "__main__":` the
    API's launch(workers=2) is refused in one line naming the guard, before any worker starts
    (before: 299 traceback lines blaming memory); with the guard it runs (D10)."""
    call = "print(lev.load('thesis_air').launch(n=4, t_end=0.05, workers=2).probability)"
    bare = tmp_path / "bare.py"
    bare.write_text(f"import levitron as lev\n{call}\n")
    guarded = tmp_path / "guarded.py"
    guarded.write_text(f"import levitron as lev\n\nif __name__ == '__main__':\n    {call}\n")
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2]))
    res = subprocess.run([sys.executable, bare], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=120, check=False)
    assert res.returncode == 1 and len(res.stderr.splitlines()) < 40, res.stderr[-3000:]
    last = res.stderr.splitlines()[-1]
    assert "UserError: workers=2 starts worker processes" in last and '__name__ == "__main__"' in last, last
    assert "memory" not in res.stderr
    res = subprocess.run([sys.executable, guarded], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=120, check=False)
    assert res.returncode == 0 and 0 <= float(res.stdout) <= 1, res.stderr[-3000:]


API_MISTAKES = [
    ("lev.load('thesis_air', overides={'top.mass': 0.05})", r"'overides' is unknown: did you mean 'overrides'"),
    ("lev.load('thesis_air').stability(0.1, 2)", r"Study.stability: too many positional"),
    ("lev.load('thesis_air').equilibria(bands=True)", r"Study.equilibria: argument 'bands' is unknown"),
    ("lev.load('thesis_air').launch(n=4, inputs='spin=1000')", r"inputs = 'spin=1000' must map"),
    ("lev.load('thesis_air').launch(n=4, inputs=['spin'])", r"inputs = \['spin'\] must map"),
    ("lev.load('thesis_stable').gradient('sigma_hi', ['top.mass'], 3)", r"Study.gradient: too many"),
    ("lev.load('thesis_air').launch(n='4')", r"^n='4' must be a whole number"),             # D30: the quotes kept
    ("lev.load('thesis_air').launch(n=4, t_end=0.05, inputs={'temperature': 1400})",      # D17: the API's words
     r"^inputs\['temperature'\] 1400: .*not positive"),
]


@pytest.mark.parametrize("call,mention", API_MISTAKES, ids=[c[0].split(").")[-1][:30] for c in API_MISTAKES])
def test_api_mistakes_are_one_line_user_errors(call, mention):
    """A misspelt keyword or a wrong count of arguments is a levitron.UserError of one line, the
    valid names listed (before: Python's TypeError, D12); a text argument keeps its quotes (D30)
    and no message names a command-line flag (D17)."""
    import re

    import levitron as lev
    with pytest.raises(lev.UserError) as exc:
        eval(call, {"lev": lev})
    assert "\n" not in str(exc.value) and re.search(mention, str(exc.value)), str(exc.value)
    assert "--" not in str(exc.value) and not {"«", "‹"} & set(str(exc.value)), str(exc.value)


# ---------------------------------------------------------------- errors that name what to fix

MESSAGES = [
    ("report-out-empty", ["report", "thesis", "--out", ""], r"--out '': an empty value"),
    ("report-out-dot", ["report", "thesis", "--out", "."], r"--out \. is a folder"),
    ("figures-out-empty", ["figures", "thesis", "--out", ""], r"--out '': an empty value"),
    ("figures-out-equals", ["figures", "thesis", "--out="], r"--out '': an empty value"),
    ("scheduler-empty", ["launch", "thesis_air", "--n", "4", "--scheduler", ""], r"--scheduler ''"),
    ("scene-empty", ["info", ""], r"empty argument '' .*give the scene"),
    ("temperature-twice", ["equilibrium", "thesis", "--temperature", "30", "--set", "temperature=40"],
     r"--temperature 30 and --set 'temperature=40' both"),
]


@pytest.mark.parametrize("argv,mention", [c[1:] for c in MESSAGES], ids=[c[0] for c in MESSAGES])
def test_errors_name_what_to_fix(argv, mention, tmp_path):
    """Empty values never mean a default or the current folder (D26; before: figures --out ''
    wrote into the current folder, --scheduler '' ran serially, report --out '' and --out . exited 3,
    D8), and two settings of one number are refused, not resolved silently (D22)."""
    refused(cli(argv, cwd=tmp_path, timeout=120), mention)
    assert list(tmp_path.iterdir()) == [], "something was written"


def test_a_scheduler_that_answers_in_http_is_named(tmp_path):
    """Before: 'not enough memory ... ask for less' on the command line, a raw _ArrayMemoryError in
    the API (D7)."""
    from tests.helpers.hostile import http_imposter
    with http_imposter() as address:
        refused(cli([*AIR, "--scheduler", address], cwd=tmp_path, timeout=120), r"is not a dask scheduler")
        refused(_api(f"lev.load('thesis_air').launch(n=4, t_end=0.05, scheduler={address!r})", tmp_path),
                r"is not a dask scheduler")


def test_a_killed_derive_child_says_so(tmp_path):
    """`levitron derive` whose child is SIGKILLed says it was killed and that generated/ is as it
    was (before: 'derive failed', D20)."""
    marker = tmp_path / "marker"
    res = cli(["derive", "thesis", "--force"], cwd=tmp_path, env={"LEVITRON_FAULT": f"derive.child:{marker}"})
    assert marker.exists()
    refused(res, r"derive of thesis was killed \(signal 9\).*generated/ holds the models as they were")


def test_a_damaged_object_with_a_matching_stamp_is_rebuilt(tmp_path, seed_cache):
    """A cached object whose content and stamp were both replaced (the stamp matches the junk)
    fails the link: the objects are compiled again and the run works (before: every run failed
    with a bare linker error, D15)."""
    from levitron.runtime.model.cbuild import _stamp
    cache = seed_cache(tmp_path / "cache")
    obj = sorted((cache / "obj").glob("*.o"))[0]
    junk = b"not an object file\n" * 50
    obj.write_bytes(junk)
    obj.with_name(obj.name + ".sha256").write_text(_stamp(junk))
    res = cli(["equilibrium", "thesis", "--json"], cwd=tmp_path, env={"LEVITRON_CACHE": str(cache)})
    assert res.returncode == 0, res.stderr[-2000:]
    assert "linking the cached objects failed" in res.stderr
    assert obj.read_bytes() != junk


NUMBER_TEXTS = [
    ("spin-flag", [*SIM[:3], "{x}", *SIM[4:]], r"--spin: invalid float value"),
    ("launch-n", ["launch", "thesis_air", "--n", "{i}"], r"--n: invalid int value"),
    ("spread", [*AIR, "--spin", "normal:{x},100"], r"needs two numbers"),
    ("vary", [*DESIGN[:5], "top.mass=0.0197:{m}", *DESIGN[6:]], r"--vary .*write KEY=LO:HI with numbers"),
    ("at", ["field", "thesis", "--at", "0,0,{z}"], r"--at .* is not a point"),
]
SPELLINGS = {"underscore": {"x": "1_000", "i": "1_0", "m": "0.020_9", "z": "0.1_0"},
             "arabic-digits": {"x": "\u0661\u0660\u0660\u0660", "i": "\u0661\u0660", "m": "\u0660.\u0662",
                               "z": "\u0660.\u0661"}}


@pytest.mark.parametrize("spelling", SPELLINGS)
@pytest.mark.parametrize("argv,mention", [c[1:] for c in NUMBER_TEXTS], ids=[c[0] for c in NUMBER_TEXTS])
def test_a_number_is_read_one_way(argv, mention, spelling, tmp_path):
    """Every number typed as text is read as the fit's CSV cells are (runtime/ui/validate.py
    number_text): '1_000' or Arabic-Indic digits are refused everywhere (before: Python's float()
    took them in flags, spreads, --vary and --at, and the CSV reader refused them, D25)."""
    refused(cli([a.format(**SPELLINGS[spelling]) for a in argv], cwd=tmp_path, timeout=120), mention)


def test_a_scene_with_a_byte_order_mark_is_named(tmp_path):
    """A scene saved as UTF-8 with a BOM: the refusal names the BOM (before: 'not valid TOML (...
    at line 1, column 1)', D19), on the command line and in the API."""
    scene = tmp_path / "bom.toml"
    thesis = Path(__file__).resolve().parents[2] / "scenes" / "thesis.toml"
    scene.write_bytes(b"\xef\xbb\xbf" + thesis.read_bytes())
    refused(cli(["info", scene], cwd=tmp_path), r"byte-order mark .*without a BOM")
    refused(_api(f"lev.load({str(scene)!r})", tmp_path), r"byte-order mark")


def test_the_energy_balance_of_a_slow_decay_is_the_friction_free_drift(tmp_path):
    """With decay times of 1e12 s the run in air is the friction-free run (thesis_stable: the same
    top and plate) to round-off, and its energy balance is that run's energy drift (relative to
    the energy's terms when little is lost; before: 0.94, a ratio of two round-offs, D6)."""
    import json
    run = [*SIM[:3], "1122", "--t-end", "0.5", "--json"]
    ideal = json.loads(cli(run, cwd=tmp_path).stdout)
    slow = cli([run[0], "thesis_air", *run[2:], "--set", "top.spin_decay_time=1e12"], cwd=tmp_path)
    air = json.loads(slow.stdout)
    assert air["status"] == ideal["status"] == "completed"
    for k, v in ideal["final_state"].items():
        assert air["final_state"][k] == pytest.approx(v, rel=1e-9, abs=1e-12), k
    assert air["energy_drift"] == pytest.approx(ideal["energy_drift"], rel=1e-2)
    assert air["energy_drift"] < 1e-9


def test_a_formula_that_is_one_over_zero_is_named_not_judged(tmp_path):
    """phi0 = b z / (sin^2 z + cos^2 z - 1) is 1/0 at every height, its derivatives came out 0:
    refused naming the formula and the non-finite potential, not 'the field cannot hold a top'
    (a physics verdict; e17 of the second battery), and the API's functions() gives a UserError,
    not casadi's RuntimeError."""
    from tests.helpers.battery import expression_scene
    scene = tmp_path / "e17.toml"
    scene.write_text(expression_scene("b*z/(sin(z)**2+cos(z)**2-1)", {"b": 0.01}, name="e17"))
    for command in ("equilibrium", "stability"):
        refused(cli([command, scene], cwd=tmp_path), r"phi0 = .*Phi_0 is not finite .*divides by zero")
    refused(_api(f"lev.load({str(scene)!r}).functions()", tmp_path), r"z_s function cannot be built")
