"""Progress for every slow step: a step of named stages (a derivation in its subprocess, a
compilation, the figures) shows "deriving: Hamilton's equations 4/7" with an ETA; off a terminal it
writes one line per stage on stderr, so a minute of deriving is not silent in a log."""
from __future__ import annotations

import re
import subprocess
import sys

from levitron.scene.paths import ROOT
from levitron.runtime.cli import main as cli
from levitron.runtime.ui import progress


def test_stage_lines_off_a_terminal(monkeypatch, capsys):
    monkeypatch.delenv("LEVITRON_PROGRESS", raising=False)
    progress.enable()
    with progress.stages("deriving", ["the plate", "Hamilton's equations", "C files"], [1, 1, 1]) as stage:
        stage(0)
        stage("Hamilton's equations")
        stage(2)
    err = capsys.readouterr().err.splitlines()
    assert [re.sub(r" \(.*\)$", "", e) for e in err] == [
        "levitron: deriving: the plate 1/3", "levitron: deriving: Hamilton's equations 2/3",
        "levitron: deriving: C files 3/3"]
    assert "eta" in err[1] and "elapsed" in err[0]


def test_no_stage_lines_when_progress_is_off(monkeypatch, capsys):
    progress.disable()
    try:
        with progress.stages("deriving", ["a", "b"]) as stage:
            stage(0)
            stage(1)
    finally:
        progress.enable()
    monkeypatch.setenv("LEVITRON_PROGRESS", "0")
    with progress.stages("deriving", ["a"]) as stage:
        stage(0)
    assert capsys.readouterr().err == ""


def test_derive_child_names_its_stages(tmp_path):
    """python -m levitron.derive --stages: one "stage k/7 NAME" line as each stage begins (a reduced-only
    scene skips the full model's stages)."""
    run = subprocess.run([sys.executable, "-m", "levitron.derive", "reduced_only", "--out", str(tmp_path),
                          "--force", "--stages"], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    stages = re.findall(r"^stage (\d)/7 (.+)$", run.stderr, re.M)
    assert [int(k) for k, _ in stages] == [1, 2, 3, 6, 7]
    assert stages[2][1] == "the reduced model"


def test_a_structural_set_shows_its_stages(tmp_path, monkeypatch, capsys, seed_cache):
    """A --set of a structural key derives in a subprocess and compiles: both show their stages
    on stderr off a terminal; stdout holds only the answer."""
    monkeypatch.setenv("LEVITRON_CACHE", str(seed_cache(tmp_path / "cache")))
    monkeypatch.delenv("LEVITRON_PROGRESS", raising=False)
    assert cli.main(["equilibrium", "reduced_only", "--set", "field.order=4"]) == 0
    out, err = capsys.readouterr()
    assert out.startswith("equilibria: ") and "deriving" not in out
    assert "levitron: deriving: the reduced model 3/7 (" in err
    assert re.search(r"deriving: C and CasADi files 7/7 \(\d+:\d\d elapsed, eta \d+:\d\d\)", err)
    assert "levitron: compiling: " in err


def test_a_long_count_writes_its_progress_off_a_terminal(monkeypatch, capsys):
    """A scan's points (runtime/scan/runners.py, log_every 10 s): off a terminal a line with the
    count and the ETA at most once per log_every, none for a step shorter than that."""
    monkeypatch.delenv("LEVITRON_PROGRESS", raising=False)
    progress.enable()
    with progress.task("scan", total=4, log_every=1e-9) as tick:
        tick(1)
        tick(2)
        tick(1)
    lines = capsys.readouterr().err.splitlines()
    assert [ln.split(" (")[0] for ln in lines] == ["levitron: scan: 1/4", "levitron: scan: 3/4"]
    assert all("eta" in ln for ln in lines)
    with progress.task("scan", total=4, log_every=60) as tick:
        tick(4)
    assert capsys.readouterr().err == ""
