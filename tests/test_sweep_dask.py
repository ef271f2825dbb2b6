"""Sweeps on a Dask cluster: a LocalCluster of 2 worker processes on loopback.

The results must equal the local executor's to the last bit (the same code
on the same machine); a worker killed mid-point has its point rerun
elsewhere; workers of another rotorkit version are refused.
"""

import os

import numpy as np
import pytest

distributed = pytest.importorskip("distributed")  # in the `test` extra: CI runs these

from rotorkit.errors import RotorkitError  # noqa: E402
from rotorkit.sweep import run_sweep  # noqa: E402
from rotorkit.sweep.executors import check_worker_versions  # noqa: E402
from sweep_models import build_jeffcott  # noqa: E402

SPACE = {"rub_stiffness": [0.0, 1e5], "eccentricity": [1e-5, 5e-5]}
KW = dict(window=(0.2, 0.4), t_end=0.4, signals=["x1"], orders=["1", "1/2"], poincare_revolutions=4)


@pytest.fixture(scope="module")
def client(tmp_path_factory):
    marker = tmp_path_factory.mktemp("dask") / "crashed"
    old = {k: os.environ.get(k) for k in ("RK_SWEEP_CRASH_MARKER", "RK_SWEEP_DRIVER_PID")}
    os.environ["RK_SWEEP_CRASH_MARKER"] = str(marker)  # workers inherit it
    os.environ["RK_SWEEP_DRIVER_PID"] = str(os.getpid())
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=None, silence_logs=40)
    client = distributed.Client(cluster, set_as_default=False)
    try:
        yield client, marker
    finally:
        client.close()
        cluster.close()
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def test_a_dask_sweep_equals_the_local_one(client, tmp_path):
    client, _ = client
    events = []
    remote = run_sweep(build_jeffcott, SPACE, out_dir=tmp_path / "dask", executor=client, progress=events.append,
                       **KW)
    local = run_sweep(build_jeffcott, SPACE, out_dir=tmp_path / "local", workers=1, **KW)
    assert sorted(e.index for e in events) == [0, 1, 2, 3] and events[-1].done == 4 == events[-1].total
    for name in ("amplitude", "order_amplitude", "poincare", "max_displacement", "status"):
        np.testing.assert_array_equal(remote[name].values, local[name].values)  # bit for bit
    assert (remote.status == "ok").all()
    pids = {int(p) for p in client.run(os.getpid).values()}
    import json

    from rotorkit.sweep import point_path

    computed_by = set()
    for i in range(4):
        with np.load(point_path(tmp_path / "dask", i), allow_pickle=False) as data:
            computed_by.add(json.loads(str(data["meta"]))["stats"]["pid"])
    assert computed_by <= pids  # on the Dask workers, not here


def test_a_dask_worker_killed_mid_point_is_replaced_and_no_point_is_lost(client, tmp_path):
    client, marker = client
    events = []
    ds = run_sweep(build_jeffcott, SPACE, out_dir=tmp_path / "crash", executor=client, progress=events.append,
                   overrides={"crash": 1.0}, **KW)
    assert marker.exists()  # a worker died in the middle of a point
    assert sorted(e.index for e in events) == [0, 1, 2, 3]  # every point exactly once
    assert (ds.status == "ok").all()


def test_workers_of_another_version_are_refused(client):
    from rotorkit.sweep.executors import worker_versions

    client, _ = client
    check_worker_versions(client)  # the same versions here: accepted
    other = {**worker_versions(), "rotorkit": "0.0.0-other"}  # as if this process ran another release
    with pytest.raises(RotorkitError, match=r"different version than this process \(here: python .*rotorkit 0.0.0-other; tcp://127.0.0.1:"
                                            r"\d+: python .*rotorkit 0.1.0.*install the same rotorkit"):
        check_worker_versions(client, local=other)
