"""Hostile sweeps: bad arguments and damaged folders are named errors; a Dask worker killed with its nanny loses nothing.

Before: a lambda as the scene or unknown simulate options raised a bare
``TypeError``; a ``sweep.json`` that held JSON but not a manifest (``[]``,
``null``) was reported as "a different sweep" with a list of nulls. A Dask
worker process killed with ``kill -9`` together with its nanny (so nothing
restarts it) must neither lose a point nor store one twice, and a rerun
resumes without computing anything again.
"""

import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from rotorkit.errors import ArgumentTypeError, ParameterError, RotorkitError
from rotorkit.sweep import load_sweep, point_path, run_sweep
from sweep_models import build_jeffcott

KW = dict(window=(0.2, 0.4), t_end=0.4, signals=["x1"], orders=["1"], poincare_revolutions=4)


def _nested_build(rub_stiffness=0.0):
    return build_jeffcott(rub_stiffness=rub_stiffness)


@pytest.mark.parametrize("kwargs, error, words", [
    (dict(scheduler="not a url"), RotorkitError, r"cannot reach the Dask scheduler at 'not a url'"),
    (dict(scheduler=""), ParameterError, r"scheduler='': expected an address such as tcp://"),
    (dict(out_dir="/dev/null"), ParameterError, r"'/dev/null' is a file or device, not a folder"),
    (dict(out_dir="FILE"), ParameterError, r"is a file or device, not a folder"),
    (dict(scene=lambda rub_stiffness=0.0: build_jeffcott(rub_stiffness)), ArgumentTypeError,
     r"cannot import a lambda or a nested function; define the build function at module level"),
    (dict(simulate_options={"rtol": 1e-6, "bogus": 1}), ArgumentTypeError,
     r"simulate_options has unknown keys \['bogus'\]; allowed: method, rtol"),
    (dict(simulate_options="DOP853"), ArgumentTypeError, r"simulate_options='DOP853': expected a dict"),
    (dict(executor=object()), ArgumentTypeError, r"expected a concurrent.futures.Executor or a dask"),
    (dict(progress=3), ArgumentTypeError, r"progress=3: expected a callable"),
    (dict(overrides={"friction": [0.1]}), ArgumentTypeError, r"overrides\['friction'\] = \[0.1\] \(list\)"),
], ids=["scheduler not a url", "scheduler empty", "out /dev/null", "out a file", "lambda scene", "unknown options",
        "options not a dict", "executor", "progress", "override a list"])
def test_bad_sweep_arguments_are_named_errors_before_any_point_runs(tmp_path, monkeypatch, kwargs, error, words):
    import rotorkit.sweep.run as sweep_run

    monkeypatch.setattr(sweep_run, "run_point", lambda task: pytest.fail("a point ran"))
    (tmp_path / "FILE").write_text("not a folder")
    kwargs = {"scene": build_jeffcott, "out_dir": tmp_path / "out", "workers": 2, **kwargs}
    if kwargs["out_dir"] == "FILE":
        kwargs["out_dir"] = tmp_path / "FILE"
    with pytest.raises(error, match=words):
        run_sweep(kwargs.pop("scene"), "rub_stiffness", [0.0, 1e5], **KW, **kwargs)
    assert issubclass(error, RotorkitError)
    assert (tmp_path / "FILE").read_text() == "not a folder"


DAMAGED = {"not json": "{", "a list": "[]", "null": "null", "binary": "\x00\xff\xfe", "another format": '{"format": 99}',
           "a number": "3"}


@pytest.mark.parametrize("text", DAMAGED.values(), ids=DAMAGED.keys())
def test_a_damaged_sweep_json_is_a_named_error_on_resume_and_on_load(tmp_path, monkeypatch, text):
    import rotorkit.sweep.run as sweep_run

    monkeypatch.setattr(sweep_run, "run_point", lambda task: pytest.fail("a point ran"))
    out = tmp_path / "sweep"
    out.mkdir()
    (out / "sweep.json").write_text(text, encoding="latin-1")
    with pytest.raises(ParameterError, match=r"sweep.json is (unreadable|damaged).*delete it \(or the folder\) to "
                                             r"start the sweep over"):
        run_sweep(build_jeffcott, "rub_stiffness", [0.0, 1e5], out_dir=out, workers=1, **KW)
    with pytest.raises(ParameterError, match=r"(not a sweep folder|not a rotorkit sweep manifest)"):
        load_sweep(out)
    assert (out / "sweep.json").read_text(encoding="latin-1") == text  # left as it was, for the user to look at


# -- a Dask worker killed with kill -9 together with its nanny ----------------------------------------------------
SPACE = {"rub_stiffness": [0.0, 1e5], "eccentricity": [1e-5, 2e-5, 3e-5, 4e-5]}
FAST = {"backend": "python", "engine": "scipy"}  # no compiled code to load in each worker


def _ancestors(pid):
    """Process ids of ``pid``'s parent, grandparent, ... (from /proc)."""
    out = []
    while pid > 1:
        try:
            pid = int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):
            break
        out.append(pid)
    return out


@pytest.mark.slow
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_a_dask_worker_killed_with_its_nanny_loses_no_point_and_stores_none_twice(tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    here = Path(__file__).resolve().parent
    monkeypatch.setenv("RK_SWEEP_HOLD", "1.0")  # each point takes >= 1 s in a worker: the kill lands mid-sweep
    monkeypatch.setenv("RK_SWEEP_DRIVER_PID", str(os.getpid()))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(here.parent), str(here), os.environ.get("PYTHONPATH", "")]))
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=None, silence_logs=50)
    nanny = subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", cluster.scheduler_address,
                              "--nworkers", "1", "--nthreads", "1", "--no-dashboard", "--host", "127.0.0.1"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    client = distributed.Client(cluster, set_as_default=False)
    try:
        client.wait_for_workers(2, timeout=120)
        workers = {int(p) for p in client.run(os.getpid).values()}
        worker, = (p for p in workers if nanny.pid in _ancestors(p))  # the worker process the nanny started
        events, killed = [], threading.Event()

        def progress(event):
            events.append(event)
            if len(events) == 2 and not killed.is_set():  # both workers hold points now
                os.kill(worker, 9)
                os.kill(nanny.pid, 9)
                killed.set()

        ds = run_sweep(build_jeffcott, SPACE, out_dir=tmp_path / "sweep", executor=client, progress=progress,
                       simulate_options=FAST, **KW)
        assert killed.is_set() and nanny.wait(10) == -9
        assert sorted(e.index for e in events) == list(range(8))  # every point once: none lost, none twice
        assert (ds.status == "ok").all() and ds.sizes["rub_stiffness"] * ds.sizes["eccentricity"] == 8
        computed_by = [json.loads(str(np.load(point_path(tmp_path / "sweep", i))["meta"]))["stats"]["pid"]
                       for i in range(8)]
        assert os.getpid() not in computed_by
        assert sorted(p.name for p in (tmp_path / "sweep").iterdir() if p.name.startswith(".")) == []  # no temp left

        again = []  # a rerun resumes: every point is found on disk, none computed
        monkeypatch.setattr("rotorkit.sweep.run.run_point", lambda task: pytest.fail("a stored point ran again"))
        ds2 = run_sweep(build_jeffcott, SPACE, out_dir=tmp_path / "sweep", executor=client, progress=again.append,
                        simulate_options=FAST, **KW)
        assert sorted(e.index for e in again) == list(range(8)) and {e.status for e in again} == {"cached"}
        np.testing.assert_array_equal(ds2.amplitude.values, ds.amplitude.values)
    finally:
        client.close()
        cluster.close()
        if nanny.poll() is None:
            nanny.kill()
            nanny.wait()
