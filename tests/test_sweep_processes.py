"""Sweep processes: a worker killed mid-point, the parent killed mid-sweep (its workers end), then a resume.

The points are Jeffcott rotor runs (tests/sweep_models.py); a point that
kills its worker is simulated with ``crash=1`` (SIGKILL, once per sweep, in a
worker only).
"""

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np

from rotorkit.sweep import point_path, run_sweep
from sweep_models import build_jeffcott  # noqa: E402

TESTS = Path(__file__).resolve().parent
ROOT = TESTS.parent


class Events:
    def __init__(self):
        self.events = []

    def __call__(self, event):
        self.events.append(event)

    def indices(self, status=None):
        return sorted(e.index for e in self.events if status is None or e.status == status)


def test_a_worker_killed_mid_point_is_retried_and_every_point_stored_once(tmp_path, monkeypatch):
    marker = tmp_path / "crashed"
    monkeypatch.setenv("RK_SWEEP_CRASH_MARKER", str(marker))
    monkeypatch.setenv("RK_SWEEP_DRIVER_PID", str(os.getpid()))
    events = Events()
    ds = run_sweep(build_jeffcott, {"rub_stiffness": [0.0, 1e4], "eccentricity": [1e-5, 2e-5]},
                   out_dir=tmp_path / "out", window=(0.2, 0.3), t_end=0.3, workers=2, progress=events,
                   overrides={"crash": 1.0}, signals=["x1"], start_method="fork")  # fork: no start-up imports
    assert marker.exists()  # a worker was killed
    killed = int(marker.read_text())
    assert events.indices() == [0, 1, 2, 3]  # each point reported (and stored) exactly once
    assert (ds.status == "ok").all()
    pids = set()
    for i in range(4):
        import json

        with np.load(point_path(tmp_path / "out", i), allow_pickle=False) as data:
            pids.add(json.loads(str(data["meta"]))["stats"]["pid"])
    assert killed not in pids and os.getpid() not in pids  # computed by the replacement workers


SCRIPT = textwrap.dedent("""
    import os
    import sys
    sys.path.insert(0, {tests!r})
    os.environ["RK_SWEEP_DRIVER_PID"] = str(os.getpid())  # the driver does not hold (sweep_models._hold)
    from rotorkit.sweep import run_sweep
    from sweep_models import build_jeffcott

    if __name__ == "__main__":
        run_sweep(build_jeffcott, "eccentricity", {values!r}, out_dir={out!r}, window=(0.2, 0.3), t_end={t_end!r},
                  workers=2, signals=["x1"], progress=lambda e: print(e, flush=True), start_method="fork")
""")


def _children(pid):
    out = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            fields = stat.rsplit(")", 1)[1].split()
            if int(fields[1]) == pid:
                out.append(int(entry.name))
    return out


def _alive(pid):
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] not in ("Z", "X")  # a zombie has ended


def test_killing_the_parent_ends_its_workers_and_a_rerun_computes_only_the_missing_points(tmp_path):
    values = [1e-5, 2e-5, 3e-5, 4e-5, 5e-5, 6e-5]
    out = tmp_path / "out"
    t_end = 0.5
    script = tmp_path / "sweep_script.py"
    script.write_text(SCRIPT.format(tests=str(TESTS), values=values, out=str(out), t_end=t_end))
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "RK_SWEEP_HOLD": "2.0"}  # every point holds its worker 2 s: the parent dies while the workers are busy
    proc = subprocess.Popen([sys.executable, str(script)], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        deadline = time.monotonic() + 240
        while not (out / "points").exists() or not any((out / "points").iterdir()):
            assert proc.poll() is None, proc.stderr.read()
            assert time.monotonic() < deadline, "no point finished in time"
            time.sleep(0.2)
        workers = [p for p in _children(proc.pid) if _alive(p)]
        assert workers, "the sweep has no worker processes"
        proc.kill()  # SIGKILL: no clean-up in the parent
        proc.wait()
        deadline = time.monotonic() + 10
        while any(_alive(p) for p in workers) and time.monotonic() < deadline:
            time.sleep(0.1)
        left = [p for p in workers if _alive(p)]
        assert not left, f"worker processes {left} outlived their parent"
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        proc.stdout.close()
        proc.stderr.close()
    done = sorted(int(p.stem[1:]) for p in (out / "points").glob("p*.npz"))
    assert 0 < len(done) < len(values)
    events = Events()
    ds = run_sweep(build_jeffcott, "eccentricity", values, out_dir=out, window=(0.2, 0.3), t_end=t_end, workers=2,
                   signals=["x1"], progress=events, start_method="fork")
    assert events.indices("cached") == done
    assert events.indices() == list(range(len(values)))  # each point once
    assert sorted(set(events.indices()) - set(done)) == events.indices("ok")  # only the missing ones ran
    assert (ds.status == "ok").all()
