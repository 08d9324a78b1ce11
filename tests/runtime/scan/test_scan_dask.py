"""`levitron scan --scheduler ADDRESS` on a real dask.distributed cluster: a LocalCluster on the
loopback interface (TCP on 127.0.0.1, one in-process worker with two threads), and the map it
makes equals the serial one point for point (thesis 3.3, fig. 3.8)."""
from __future__ import annotations

import numpy as np
import pytest

from levitron.runtime.scan import stability_map as sc
from levitron.runtime.scan import runners as scan_runners
from levitron.runtime.errors import UserError

distributed = pytest.importorskip("dask.distributed", reason="the test extra installs dask[distributed]")

SPINS, TILTS = np.array([300.0, 1000.0, 2000.0, 3200.0]), np.array([0.01, 0.06, 0.12])


@pytest.fixture(scope="module")
def cluster():
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  host="127.0.0.1", protocol="tcp", dashboard_address=None) as c:
        yield c


def test_dask_map_equals_serial(model, cluster):
    address = cluster.scheduler_address
    assert address.startswith("tcp://127.0.0.1:")
    a = sc.scan(model, SPINS, "tilt", TILTS, t_end=1.0, quiet=True)
    b = sc.scan(model, SPINS, "tilt", TILTS, t_end=1.0, quiet=True, scheduler=address)
    assert b.runner["kind"] == "dask" and b.runner["threads"] == 2 and b.runner["engine"] == "c"
    assert b.runner["chunks"] == SPINS.size * TILTS.size     # 8 per thread asked, one per point here
    assert a.status == b.status
    np.testing.assert_array_equal(a.levitating, b.levitating)
    np.testing.assert_array_equal(a.t_survived, b.t_survived)
    assert a.rhs_evals == b.rhs_evals
    assert a.levitating.any() and not a.levitating.all()


def test_unreachable_scheduler_is_one_line(model, monkeypatch):
    monkeypatch.setattr(scan_runners, "CONNECT_TIMEOUT_S", 1)
    with pytest.raises(UserError, match="cannot reach the dask scheduler") as exc:
        sc.scan(model, SPINS[:1], "tilt", TILTS[:1], t_end=0.1, quiet=True,
                scheduler="tcp://127.0.0.1:9")
    assert "\n" not in str(exc.value)
