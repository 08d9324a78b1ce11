"""Scans never hang and never lose a map (no hang, no unbounded work):

* `--scheduler` at something that is not a dask scheduler (an HTTP server on 127.0.0.1) or at a
  scheduler without workers is a one-line UserError within the timeout (before: waited forever);
* a local worker process killed mid-scan (SIGKILL at an injected point, runtime/faults.py) costs a
  rerun of its chunks, and the map equals the serial one (before: BrokenProcessPool, map lost);
* --workers above the usable cores is capped, with a note (before: 8 processes on 2 cores ran
  6.7x slower than serial).
"""
from __future__ import annotations

import http.server
import threading
import time

import numpy as np
import pytest

from levitron.runtime.scan import stability_map as sc
from levitron.runtime.errors import UserError
from levitron.runtime.scan.runners import usable_cores

SPINS, TILTS = np.array([300.0, 1000.0, 2000.0, 3200.0]), np.array([0.01, 0.06, 0.12])


def within(seconds: float, fn):
    """fn() in a daemon thread: its result or exception, or a test failure after `seconds`."""
    box = {}

    def run():
        try:
            box["value"] = fn()
        except Exception as exc:        # noqa: BLE001 (handed to the test thread, re-raised there)
            box["error"] = exc
    th = threading.Thread(target=run, daemon=True)
    th.start()
    th.join(seconds)
    if th.is_alive():
        pytest.fail(f"did not return within {seconds} s")
    if "error" in box:
        raise box["error"]
    return box["value"]


class _QuietHandler(http.server.BaseHTTPRequestHandler):
    def log_message(self, format, *args):       # noqa: A002 (the base class's signature)
        pass


@pytest.fixture()
def http_server():
    srv = http.server.ThreadingHTTPServer(("127.0.0.1", 0), _QuietHandler)
    threading.Thread(target=srv.serve_forever, daemon=True).start()
    yield f"tcp://127.0.0.1:{srv.server_address[1]}"
    srv.shutdown()


def test_an_http_server_is_no_scheduler(model, http_server):
    t0 = time.monotonic()
    with pytest.raises(UserError, match="no dask scheduler answered") as exc:
        within(30, lambda: sc.scan(model, SPINS[:1], "tilt", TILTS[:1], t_end=0.1,
                                   quiet=True, scheduler=http_server, scheduler_timeout=2))
    assert "\n" not in str(exc.value) and time.monotonic() - t0 < 15


def test_a_scheduler_without_workers_is_one_line(model):
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=0, processes=False, host="127.0.0.1", protocol="tcp",
                                  dashboard_address=None) as cluster:
        with pytest.raises(UserError, match="has no workers") as exc:
            within(30, lambda: sc.scan(model, SPINS[:1], "tilt", TILTS[:1], t_end=0.1,
                                       quiet=True, scheduler=cluster.scheduler_address,
                                       scheduler_timeout=2))
    assert "\n" not in str(exc.value)


def test_a_killed_worker_costs_a_rerun_not_the_map(model, tmp_path, monkeypatch, capfd):
    serial = sc.scan(model, SPINS, "tilt", TILTS, t_end=1.0, quiet=True)
    marker = tmp_path / "killed"
    monkeypatch.setenv("LEVITRON_FAULT", f"scan.worker_chunk:{marker}")
    par = within(300, lambda: sc.scan(model, SPINS, "tilt", TILTS, t_end=1.0,
                                      quiet=True, workers=2))
    assert marker.exists(), "no worker was killed: the test tested nothing"
    assert "scan worker process died" in capfd.readouterr().err
    assert par.runner["kind"] == "processes"
    assert par.status == serial.status
    np.testing.assert_array_equal(par.levitating, serial.levitating)
    np.testing.assert_array_equal(par.t_survived, serial.t_survived)
    assert par.rhs_evals == serial.rhs_evals


def test_workers_are_capped_at_the_usable_cores(model, capfd):
    many = usable_cores() + 6
    res = sc.scan(model, SPINS, "tilt", TILTS[:2], t_end=0.5, quiet=True, workers=many)
    assert res.runner["workers"] == min(usable_cores(), SPINS.size * 2)
    assert f"{many} worker processes capped" in capfd.readouterr().err


def test_losing_every_dask_worker_mid_scan_is_one_line(model):
    """Every worker of the cluster leaves while the scan's chunks run: the scheduler holds the
    tasks for a worker that never comes, and the scan waited for ever. Now it gives up once the
    cluster has had no worker for --scheduler-timeout seconds, in one line that says so."""
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  host="127.0.0.1", protocol="tcp",
                                  dashboard_address=None) as cluster:
        spins = np.linspace(300.0, 3200.0, 24)

        def leave():                # once the first chunk is done, the others still to run
            while not any(t.state == "memory" for t in list(cluster.scheduler.tasks.values())):
                time.sleep(0.02)
            cluster.scale(0)
        threading.Thread(target=leave, daemon=True).start()
        t0 = time.monotonic()
        with pytest.raises(UserError, match="lost every worker") as exc:
            within(60, lambda: sc.scan(model, spins, "tilt", TILTS, t_end=50.0,
                                       quiet=True, scheduler=cluster.scheduler_address,
                                       scheduler_timeout=2))
        assert "\n" not in str(exc.value) and time.monotonic() - t0 < 30


@pytest.mark.parametrize("where", ["wait", "result"])
def test_a_scheduler_that_dies_mid_run_is_one_line(monkeypatch, where):
    """kill -9 of the dask scheduler while futures run: dask raises FuturesCancelledError (a
    concurrent.futures.CancelledError), from `wait` or from a future's result; the run ends in one
    UserError naming the cluster and the count done (it was 'internal error: FuturesCancelledError',
    exit 3), and the cancel of the rest, on a dead scheduler, does not mask it."""
    distributed = pytest.importorskip("dask.distributed")
    from distributed.client import CancelledFuturesGroup, FutureCancelledError, FuturesCancelledError
    from levitron.runtime.scan import runners

    def cancelled():
        lost = FutureCancelledError("chunk-1", "scheduler-connection-lost")
        return FuturesCancelledError([CancelledFuturesGroup([lost], "scheduler-connection-lost")])

    class Future:
        def result(self, timeout=None):
            raise cancelled()

    class Client:
        scheduler = type("S", (), {"address": "tcp://127.0.0.1:9"})()

        def map(self, fn, items, pure=False):
            return [Future() for _ in items]

        def cancel(self, futures):
            raise OSError("the scheduler is gone")

    def wait(pending, timeout=None, return_when=None):
        if where == "wait":
            raise cancelled()
        return set(pending), set()
    monkeypatch.setattr(distributed, "wait", wait)
    with pytest.raises(UserError, match=r"the dask cluster at 'tcp://127.0.0.1:9' .*(cancelled|gave a chunk up)"
                                        r".*\(0 of 2 points done\)"):
        runners.run_dask(None, [[1], [2]], Client(), quiet=True, fn=lambda c, chunk: {"points": chunk})
