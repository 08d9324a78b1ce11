"""The trajectory is data: simulate's samples (t, states, energy, L_z, L_n, tilt) through the API,
and --save FILE.csv / FILE.npz round-trips them to the last bit."""
from __future__ import annotations

import json

import numpy as np
import pytest

import levitron as lev
from levitron.runtime.simulate import trajectory_file
from levitron.runtime.cli.main import main


@pytest.fixture(scope="module")
def run():
    return lev.load("thesis_stable").simulate(spin=1000.0, tilt=0.01, t_end=0.2, n_out=300)


def test_the_api_returns_the_samples(run):
    tr = run.trajectory
    assert list(tr)[:4] == ["t", "x", "y", "z"] and list(tr)[-5:] == ["energy", "L_z", "L_n", "tilt", "spin"]
    assert tr["t"][0] == 0.0 and tr["t"][-1] == pytest.approx(0.2)
    assert len(tr["t"]) == 301                   # n_out intervals and the start
    assert tr["tilt"][0] == pytest.approx(0.01, rel=1e-12)
    # the summary is the samples': its largest L_z deviation and tilt come from these columns
    dev = np.abs(tr["L_z"] - tr["L_z"][0]).max() / max(abs(tr["L_z"][0]), 1.32e-6 * 1000.0)
    assert dev == pytest.approx(run.details["conserved_max_deviation"]["L_z"], rel=1e-12, abs=1e-18)
    assert tr["tilt"].max() == pytest.approx(run.details["max_tilt"], rel=1e-12)


@pytest.mark.parametrize("suffix", [".csv", ".npz"])
def test_save_round_trips(run, tmp_path, suffix):
    path = run.save(tmp_path / f"run{suffix}")
    names, table = trajectory_file.read(path)
    assert names == list(run.trajectory)
    np.testing.assert_array_equal(table, np.column_stack([run.trajectory[n] for n in names]))


def test_cli_save(tmp_path, capsys):
    out = tmp_path / "run.csv"
    assert main(["simulate", "thesis_stable", "--spin", "1000", "--t-end", "0.2", "--n-out", "300",
                 "--save", str(out), "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["saved"] == str(out) and "trajectory" not in r
    names, table = trajectory_file.read(out)
    assert table.shape == (301, len(names)) and names[0] == "t"
    assert table[-1, names.index("z")] == pytest.approx(r["final_state"]["z"], rel=1e-15)


@pytest.mark.parametrize("bad,needle", [("run.txt", ".csv, .npz or .parquet"), ("afile/run.csv", "is a file")])
def test_cli_save_bad_path_is_one_line(tmp_path, capsys, bad, needle):
    (tmp_path / "afile").write_text("a file\n")
    assert main(["simulate", "thesis_stable", "--spin", "1000", "--t-end", "0.1",
                 "--save", str(tmp_path / bad)]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and "\n" not in err


def test_cli_save_makes_a_missing_folder_as_every_writer_does(tmp_path, capsys):
    """--save, --out, --plot and report --out treat a missing folder alike: they make it
    (runtime/ui/atomic.py check_target)."""
    out = tmp_path / "new" / "deeper" / "run.csv"
    assert main(["simulate", "thesis_stable", "--spin", "1000", "--t-end", "0.1", "--save", str(out)]) == 0
    assert out.stat().st_size > 0
