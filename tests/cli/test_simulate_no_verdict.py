"""simulate's plain view: a run past its stable window (runtime/integrate/verdict.py past_window)
reads "no verdict" with the reason, never "untested" or "still floating"; a launch on the
invariant set, which tests nothing, stays "untested"."""
from __future__ import annotations

from levitron.runtime.cli import main as cli

AIR = ["simulate", "thesis_air", "--spin", "1000", "--t-end", "0.01"]


def _plain(capsys, *argv) -> list[str]:
    assert cli.main(list(argv)) == 0
    return capsys.readouterr().out.splitlines()


def test_a_run_past_its_window_is_no_verdict(capsys):
    out = _plain(capsys, *AIR, "--set", "top.spin_decay_time=2e-7")
    assert out[0].startswith("no verdict: up after") and "past the stable window" in out[0], out[0]
    line = next(x for x in out if x.startswith("levitating:"))
    assert line.startswith("levitating: no verdict (past its stable window): the spin at the run's end"), line
    assert "untested" not in "\n".join(out) and "still floating" not in "\n".join(out)


def test_a_launch_on_the_invariant_set_stays_untested(capsys):
    out = _plain(capsys, *AIR, "--tilt", "0")
    assert any(x.startswith("levitating: untested: the launch lies on the invariant set") for x in out), out
