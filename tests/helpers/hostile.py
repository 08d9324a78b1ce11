"""The hostile runner the battery tests share (tests/battery/test_hostile_conditions.py): the real command line in a
subprocess, under the limits an adversary sets (a file-size limit, a umask, an injected SIGKILL,
a time limit), and the checks every refusal must pass.

    res = cli(["simulate", ...], cwd=tmp_path, fsize=200)    # RLIMIT_FSIZE 200 bytes (memory=, umask=)
    refused(res, r"--save")          # exit 2, one error line naming the flag, no traceback
    aged(paths)                      # mtimes set back past the sweeps' one minute
    dead_pid()                       # a pid whose process has exited (a killed owner)
    children(pid), alive(pid)        # a process's live children (/proc), whether one still runs
    with http_imposter() as address: # a service that answers a dask client in HTTP
"""
from __future__ import annotations

import contextlib
import os
import re
import resource
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
ERROR = re.compile(r"^levitron[\w ]*: error: ", re.M)


def _limits(fsize: int | None, umask: int | None, memory: int | None):
    def apply():
        if memory is not None:
            resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        if fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
        if umask is not None:
            os.umask(umask)
    return apply


def cli(args, cwd: Path, env: dict | None = None, timeout: float = 300, fsize: int | None = None,
        umask: int | None = None, code: str | None = None, memory: int | None = None
        ) -> subprocess.CompletedProcess:
    """`levitron ARGS` (or `python -c CODE ARGS`) in a subprocess of its own session, with the
    session's LEVITRON_CACHE unless `env` names another; killed with its group after `timeout`;
    `fsize`, `memory`: RLIMIT_FSIZE and RLIMIT_AS in bytes; `umask`: the child's umask."""
    full = dict(os.environ, PYTHONPATH=str(ROOT), **(env or {}))
    full.pop("LEVITRON_DEBUG", None)
    head = [sys.executable, "-c", code] if code is not None else [sys.executable, "-m",
                                                                  "levitron.runtime.cli.main"]
    proc = subprocess.Popen([*head, *map(str, args)], cwd=cwd, env=full, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True,
                            preexec_fn=_limits(fsize, umask, memory))
    try:
        out, err = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        out, err = proc.communicate()
        raise AssertionError(f"`{' '.join(map(str, args))}` did not return within {timeout:g} s") from None
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err)


def error_lines(stderr: str) -> list[str]:
    """The error lines of stderr (not the "levitron: ..." progress notes)."""
    return [line for line in stderr.splitlines() if ERROR.match(line) or line.startswith("Traceback")
            or (line.strip() and not line.startswith("levitron"))]


def refused(res: subprocess.CompletedProcess, mention: str) -> str:
    """The one error line of a refusal (exit 2, no traceback) that matches `mention`."""
    assert "Traceback" not in res.stderr, res.stderr[-3000:]
    assert res.returncode == 2, f"exit {res.returncode}\n{res.stdout[-1500:]}\n{res.stderr[-1500:]}"
    errors = error_lines(res.stderr)
    assert len(errors) == 1, res.stderr
    assert re.search(mention, errors[0], re.I), f"{mention!r} not in: {errors[0]}"
    return errors[0]


def aged(paths, seconds: float = 120.0) -> None:
    """Set the mtime of every path back by `seconds` (as if the sweeps' minute had passed)."""
    t = time.time() - seconds
    for p in paths:
        os.utime(p, (t, t), follow_symlinks=False)


def dead_pid() -> int:
    """The pid of a process that has exited (the owner of a killed run's debris)."""
    proc = subprocess.Popen(["true"])
    proc.wait()
    return proc.pid


def _stat(pid: int) -> list[str] | None:
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text[text.rindex(")") + 2:].split()         # state, ppid, ... (the name may hold spaces)


def alive(pid: int) -> bool:
    """Whether `pid` runs (a zombie that no one reaped has ended)."""
    st = _stat(pid)
    return st is not None and st[0] not in ("Z", "X")


def children(pid: int) -> dict[int, str]:
    """The live child processes of `pid`: {pid: command line}."""
    out = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and (st := _stat(int(entry.name))) is not None and int(st[1]) == pid \
                and alive(int(entry.name)):
            try:
                out[int(entry.name)] = (entry / "cmdline").read_bytes().replace(b"\0", b" ").decode()
            except OSError:
                continue
    return out


@contextlib.contextmanager
def http_imposter():
    """A local service that answers every connection with an HTTP reply at once (what a dask client
    reads as a frame of an impossible length): yields its tcp:// address."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(8)
    server.settimeout(0.2)
    stop = threading.Event()

    def serve():
        conns = []
        while not stop.is_set():
            try:
                conn, _ = server.accept()
            except OSError:
                continue
            conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Type: text/html\r\nContent-Length: 20\r\n\r\n"
                         b"<html>bad req</html>")
            conns.append(conn)
        for conn in conns:
            conn.close()

    th = threading.Thread(target=serve, daemon=True)
    th.start()
    try:
        yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    finally:
        stop.set()
        th.join(5)
        server.close()
