"""The figures of ``rotorkit run`` drawn by a helper process: the same files, its errors raised in the run,
Ctrl-C stopping both, --no-figures."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from rotorkit.cli import figures as figures_module
from rotorkit.cli import main
from rotorkit.cli.figures import FigureProcess, figure_signals, write_figures
from rotorkit.errors import ParameterError
from rotorkit.result import Result

ROOT = Path(__file__).resolve().parents[1]
OUTPUTS = {"orbit_station": 2, "clearance_parameter": "rub2_clearance", "bending": "x2", "torsion": "alpha2-alpha5"}
FILES = ["orbit_station2.png", "x2.png", "alpha2_minus_alpha5.png"]
needs_fork = pytest.mark.skipif(not hasattr(os, "fork"), reason="the helper is forked")


def a_result():
    t = np.linspace(0.0, 1.0, 2001)
    names = ("x1", "x2", "y2", "alpha2", "alpha5", "x2_dot")
    y = np.array([np.sin(2 * np.pi * (k + 3) * t + k) * 1e-4 for k in range(len(names))])
    return Result(t=t, y=y, state_names=names, parameters={"rub2_clearance": 1.34e-4}, name="probe")


@pytest.fixture
def helper(monkeypatch):
    monkeypatch.delenv(figures_module.PROCESS_VARIABLE, raising=False)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    import threading

    for thread in threading.enumerate():  # a C loop still being built by an earlier run: not forked mid-build
        if thread.name.startswith("rotorkit"):
            thread.join(timeout=120)
    monkeypatch.setattr("threading.active_count", lambda: 1)  # threads other tests left idle do not matter here
    started = []

    def start():
        process = FigureProcess.start()
        assert process is not None
        started.append(process)
        return process

    yield start
    for process in started:
        process.close()


def test_the_helper_gets_only_the_signals_the_figures_show():
    assert figure_signals(OUTPUTS) == ["x2", "y2", "alpha2", "alpha5"]
    slim = figures_module._slim(a_result(), OUTPUTS)
    assert slim.state_names == ("x2", "y2", "alpha2", "alpha5")
    np.testing.assert_array_equal(slim["alpha2-alpha5"], a_result()["alpha2-alpha5"])


@needs_fork
def test_the_helper_draws_the_same_files_as_the_run_itself(helper, tmp_path):
    here, there = tmp_path / "here", tmp_path / "there"
    here.mkdir(), there.mkdir()
    assert [p.name for p in write_figures(a_result(), OUTPUTS, here)] == FILES
    process = helper()
    assert process.submit(a_result(), OUTPUTS, there)
    assert process.collect() == [there / name for name in FILES]
    for name in FILES:  # the same figure, pixel for pixel
        assert (there / name).read_bytes() == (here / name).read_bytes()
    process.close()
    assert not process._process.is_alive()


@needs_fork
def test_an_error_in_the_helper_is_raised_in_the_run(helper, tmp_path, monkeypatch):
    def broken(result, outputs, out, measurement=None):
        raise ParameterError("units='furlong' is unknown")

    monkeypatch.setattr(figures_module, "write_figures", broken)  # before the fork: the helper has it
    process = helper()
    assert process.submit(a_result(), OUTPUTS, tmp_path)
    with pytest.raises(ParameterError, match="furlong") as caught:
        process.collect()
    assert any("figure process" in note and "broken" in note for note in caught.value.__notes__)


@needs_fork
def test_a_helper_that_dies_is_an_error_naming_its_exit_code(helper, tmp_path, monkeypatch):
    monkeypatch.setattr(figures_module, "write_figures", lambda *args: os._exit(3))
    process = helper()
    assert process.submit(a_result(), OUTPUTS, tmp_path)
    with pytest.raises(RuntimeError, match=r"figure process ended .*exit code 3.*ROTORKIT_FIGURE_PROCESS=0"):
        process.collect()


@needs_fork
def test_a_job_that_does_not_pickle_is_drawn_in_the_run(helper, tmp_path):
    process = helper()
    assert not process.submit(a_result(), {**OUTPUTS, "extra": lambda: None}, tmp_path)


def test_no_helper_when_switched_off_or_threads_run(monkeypatch):
    import threading

    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    monkeypatch.setenv(figures_module.PROCESS_VARIABLE, "0")
    assert FigureProcess.start() is None
    monkeypatch.delenv(figures_module.PROCESS_VARIABLE)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0}, raising=False)
    assert FigureProcess.start() is None  # one core: nothing to overlap with
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:
        assert FigureProcess.start() is None
    finally:
        stop.set()
        thread.join()


def test_no_figures(tmp_path, capsys):
    assert main(["run", "al31f", "--t-end", "0.01", "--no-figures", "--out", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["manifest.json", "signals.npz", "summary.json"]


def children(pid):
    """Pids of the processes ``pid`` started (Linux)."""
    path = Path(f"/proc/{pid}/task/{pid}/children")
    return [int(p) for p in path.read_text().split()] if path.exists() else []


def gone(pid, timeout=10.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return True
        time.sleep(0.05)
    return False


@needs_fork
@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="reads a process's children from /proc")
@pytest.mark.parametrize("to", ["terminal", "run only"])
def test_ctrl_c_stops_the_run_and_its_helper(tmp_path, to):
    """Ctrl-C reaches the run and its helper (the terminal's process group); a SIGINT to the run alone stops
    the helper too. Interrupted early: while the model is derived (an empty cache: seconds), or just after."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), ROTORKIT_CACHE_DIR=str(tmp_path / "cache"), MPLBACKEND="Agg")
    env.pop(figures_module.PROCESS_VARIABLE, None)
    run = subprocess.Popen([sys.executable, "-m", "rotorkit.cli", "run", "al31f", "--backend", "python",
                            "--engine", "scipy", "--out", str(tmp_path / "out")], cwd=ROOT, env=env,
                           stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        deadline = time.monotonic() + 60
        while not children(run.pid) and time.monotonic() < deadline:
            time.sleep(0.05)
        helpers = children(run.pid)
        if os.cpu_count() < 2 and not helpers:
            pytest.skip("one core: no helper")
        assert len(helpers) == 1
        time.sleep(0.5)  # the helper imports matplotlib, the run derives
        if to == "terminal":
            os.killpg(run.pid, signal.SIGINT)
        else:
            os.kill(run.pid, signal.SIGINT)
        _, err = run.communicate(timeout=60)
        # stopped in whichever phase the signal lands: before the integration (exit 130; or killed by SIGINT, which
        # a shell also shows as 130: under ``python -m`` CPython exits so after a KeyboardInterrupt went through
        # exec'd code, such as a dataclass's generated methods being imported), or in it (exit 2, partial kept)
        if "interrupted (Ctrl-C) at t = " in err:
            assert run.returncode == 2, err
        else:
            assert run.returncode in (130, -signal.SIGINT) and "rotorkit: interrupted" in err, err
        assert "Traceback" not in err
        assert gone(helpers[0])
        assert not (tmp_path / "out" / "manifest.json").exists()  # no finished output folder
    finally:
        if run.poll() is None:
            os.killpg(run.pid, signal.SIGKILL)
            run.wait()
