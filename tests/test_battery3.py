"""The third battery (issue 31), by class: each test stands for a class of defects, runs the real
command line under the hostile conditions of tests/hostile.py, and failed before its fix.

Outputs: every file the tool writes (simulate --save / Simulation.save, --plot, --animate, report
--out, optimize --write-scene) is written to a temporary beside it and renamed
(runtime/ui/atomic.py), so a file-size limit, a full disk or a kill leaves the old file whole,
concurrent writers leave one whole file, the mode is the umask's, and the debris of killed runs
(output temporaries, $CACHE/obj temporaries, report scratch folders, generated/.<scene>.new-*)
is swept by the next run.
"""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from hostile import aged, cli, dead_pid, refused

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
    env = dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parent.parent))
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
