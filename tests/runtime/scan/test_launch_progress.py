"""Progress on every `launch`, serial included (issue 26: the serial bar stayed at 0/1000 for 22 s):
the serial Monte Carlo goes in chunks of about 20 launches and ticks after each, so the count and
its ETA move, on a terminal (the rich bar) and off one (the timed lines of runtime/ui/progress.py)."""
from __future__ import annotations

import os
import pty
import re
import shutil
import sys

import pytest

from levitron.runtime.cli.main import main
from levitron.runtime.scan import runners

N = 100
ARGS = ["launch", "thesis_air", "--n", str(N), "--t-end", "1", "--tilt", "0.01", "--workers", "1"]


def test_the_serial_launch_logs_its_count_and_eta_off_a_terminal(monkeypatch, capsys):
    monkeypatch.delenv("LEVITRON_PROGRESS", raising=False)
    monkeypatch.setattr(runners, "LOG_EVERY", 1e-9)        # a line at every tick, not every 10 s
    assert main(ARGS) == 0
    err = capsys.readouterr().err
    counts = [int(k) for k in re.findall(rf"levitron: launch: (\d+)/{N} \(\d+:\d\d elapsed, eta \d+:\d\d\)", err)]
    assert counts == list(range(20, N, 20)), err            # every chunk of 20, up to the last


def test_the_serial_launch_bar_moves_on_a_terminal(tmp_path):
    """The command on a pseudo-terminal: the rich bar shows counts between 0 and n, with an ETA."""
    exe = shutil.which("levitron", path=os.path.dirname(sys.executable))
    if exe is None:
        pytest.skip("the levitron script is not installed beside this Python")
    pid, fd = pty.fork()
    if pid == 0:                                   # the child: the command, its stderr the terminal
        env = {k: v for k, v in os.environ.items() if k != "LEVITRON_PROGRESS"}
        env.update(COLUMNS="120", TERM="xterm")
        os.execve(exe, [exe, "launch", "thesis_air", "--n", "200", "--t-end", "2", "--tilt", "0.01",
                        "--workers", "1"], env)
    out = b""
    while True:
        try:
            chunk = os.read(fd, 65536)
        except OSError:                            # the child closed the terminal
            break
        if not chunk:
            break
        out += chunk
    _, status = os.waitpid(pid, 0)
    text = out.decode(errors="replace")
    assert os.waitstatus_to_exitcode(status) == 0, text[-2000:]
    seen = {int(k) for k in re.findall(r"(\d+)/200, \d+:\d\d:\d\d elapsed", text)}
    assert seen & set(range(1, 200)), f"the bar showed only {sorted(seen)}"
    assert re.search(r"\d+/200, \d+:\d\d:\d\d elapsed, eta \d+:\d\d:\d\d", text)
