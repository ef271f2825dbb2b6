"""Outputs: the location checked before any work; a run's files land together; a late failure keeps the data."""

import json
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

import rotorkit as rk
from rotorkit.cli import main
from rotorkit.errors import ParameterError
from rotorkit.files import MANIFEST, check_output_folder, write_folder


@pytest.fixture
def no_work(monkeypatch):
    """Any compile fails the test: the output check must come first."""
    def forbidden(*args, **kwargs):
        raise AssertionError("the output location must be checked before any work")

    monkeypatch.setattr(rk.Model, "compile", forbidden)


def bad_locations(tmp_path):
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    cases = {"a file": (a_file, "is a file or device"),
             "/dev/null": ("/dev/null", "is a file or device"),
             "parent is a file": (a_file / "sub", "is a file, so the folder cannot be created"),
             "too long": (tmp_path / ("n" * 300), "255")}
    if os.geteuid() == 0:
        cases["read-only"] = ("/proc/rotorkit-test-out", "cannot write in")  # root ignores mode bits; /proc does not
    else:
        ro = tmp_path / "ro"
        ro.mkdir(mode=0o500)
        cases["read-only"] = (ro / "out", "cannot write in")
    return cases


@pytest.mark.parametrize("case", ["a file", "/dev/null", "parent is a file", "too long", "read-only"])
def test_bad_output_location_is_refused_before_any_work(tmp_path, capsys, no_work, case):
    path, match = bad_locations(tmp_path)[case]
    with pytest.raises(ParameterError, match=match):
        check_output_folder(path)
    assert main(["run", "al31f", "--t-end", "0.001", "--out", str(path)]) == 2
    assert match in capsys.readouterr().err


def test_a_new_folder_lands_complete_with_a_manifest(tmp_path):
    out = tmp_path / "new" / "run"

    def write(folder):
        (folder / "a.txt").write_text("a")
        (folder / "b.txt").write_text("bb")
        return [folder / "a.txt", folder / "b.txt"]

    written = write_folder(out, write)
    assert [p.name for p in written] == ["a.txt", "b.txt", MANIFEST]
    manifest = json.loads((out / MANIFEST).read_text())
    assert [(f["name"], f["bytes"]) for f in manifest["files"]] == [("a.txt", 1), ("b.txt", 2)]
    assert sorted(p.name for p in out.parent.iterdir()) == ["run"]  # no staging folder left


def test_a_late_write_failure_keeps_the_data(tmp_path, monkeypatch, capsys):
    import tempfile

    from rotorkit.cli import run as run_command

    def disk_full(result, outputs, folder, measurement=None, **figure_options):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(run_command, "write_outputs", disk_full)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    assert main(["run", "al31f", "--t-end", "0.002", "--out", str(tmp_path / "out"), "--backend", "python"]) == 1
    err = capsys.readouterr().err
    kept = err.rsplit("the signals are kept in ", 1)[1].strip()
    result = rk.load_result(kept)
    assert result.t[-1] == pytest.approx(0.002)


KILLED_WRITER = textwrap.dedent("""
    import sys, time
    from pathlib import Path
    from rotorkit.files import write_folder

    def write(folder):
        (folder / "signals.npz").write_text("new signals")
        print("half", flush=True)
        time.sleep(60)  # killed here, in the middle of writing
        (folder / "summary.json").write_text("new summary")
        return [folder / "signals.npz", folder / "summary.json"]

    write_folder(Path(sys.argv[1]), write)
""")


@pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="POSIX signals")
def test_a_run_killed_while_writing_leaves_the_previous_outputs_whole(tmp_path):
    out = tmp_path / "out"

    def first(folder):
        (folder / "signals.npz").write_text("old signals")
        (folder / "summary.json").write_text("old summary")
        return [folder / "signals.npz", folder / "summary.json"]

    write_folder(out, first)
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    child = subprocess.Popen([sys.executable, "-c", KILLED_WRITER, str(out)], stdout=subprocess.PIPE, env=env,
                             text=True)
    try:
        assert child.stdout.readline().strip() == "half"
        child.send_signal(signal.SIGKILL)
        child.wait(timeout=30)
    finally:
        child.kill()
        child.stdout.close()
    # the previous run is untouched and still matches its manifest; nothing new is mixed in
    assert (out / "signals.npz").read_text() == "old signals"
    assert (out / "summary.json").read_text() == "old summary"
    assert [f["name"] for f in json.loads((out / MANIFEST).read_text())["files"]] == ["signals.npz", "summary.json"]


@pytest.mark.skipif(not hasattr(signal, "SIGINT"), reason="POSIX signals")
@pytest.mark.parametrize("engine", ["scipy", "compiled"])
def test_ctrl_c_stops_a_run_keeps_the_partial_result_and_prints_no_traceback(tmp_path, engine):
    if engine == "compiled":
        pytest.importorskip("numba")
    out = tmp_path / "out"
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    child = subprocess.Popen([sys.executable, "-m", "rotorkit.cli", "run", "al31f", "--t-end", "300", "--engine",
                              engine, "--out", str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             env=env, text=True)
    try:
        for line in child.stderr:  # the progress lines: the simulation runs
            if "simulating" in line:
                break
        sent = time.perf_counter()
        child.send_signal(signal.SIGINT)
        stdout, stderr = child.communicate(timeout=60)
        stopped_after = time.perf_counter() - sent
    finally:
        child.kill()
    assert "Traceback" not in stderr, stderr
    assert child.returncode == 2, stderr
    assert "interrupted (Ctrl-C) at t = " in stderr
    assert stopped_after < 10  # about a second on an idle machine; the bound allows for a loaded one
    partial = rk.load_result(out / "signals-partial.npz")
    assert 0 < partial.t[-1] < 300
