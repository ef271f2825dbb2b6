"""Hostile outputs and names: what is not an output of ours is never replaced; a run lands whole or not at all.

Three classes, each with one mechanism:

- names from a model file never become paths: the ``[run]`` table is checked
  against the model's signals, stations and parameters when the file is read;
- an output path that exists and is not a regular file (or an empty folder /
  an earlier run's folder) is refused before any work, by every writer
  (``export``, ``run``, ``validate``, ``sweep``, ``Model.save``, ``Result.save``);
- a run moved into an existing folder replaces the old run atomically: killed
  at any step, the folder holds the complete old run or the complete new one,
  and nothing of the old run stays beside the new.
"""

import json
import os
import signal
import stat
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.cli import main
from rotorkit.errors import ParameterError
from rotorkit.files import MANIFEST, write_folder
from rotorkit.modelfile import ModelFileError, loads_model

JEFFCOTT = textwrap.dedent("""
    format = "rotorkit-model"
    version = 1
    name = "jeffcott"

    [[element]]
    type = "Rotor"
    name = "R"
    stations = [1]
    speed = 300.0

    [[element]]
    type = "Disk"
    station = 1
    mass = 2.0
    radius = 0.1

    [[element]]
    type = "ElasticSupport"
    station = 1
    stiffness = 2e4
""")


# -- names from a model file ---------------------------------------------------
@pytest.mark.parametrize("run, words", [
    ("bending = '../../../tmp/escape'", "not a signal of the model"),
    ("bending = 'x99'", "'x99' is not a signal"),
    ("bending = 'x1-../../a'", "not a signal"),
    ("orbit_station = 99", "orbit_station = 99: expected a station with x and y"),
    ("orbit_station = '../x'", "orbit_station"),
    ("torsion = 'x1'", "no torsion coordinates"),
    ("clearance_parameter = 'nope'", "clearance_parameter = 'nope': not a parameter"),
    ("bending = 3", "expected a signal name"),
])
def test_run_table_names_that_are_not_the_models_are_refused_when_the_file_is_read(run, words):
    with pytest.raises(ModelFileError, match=words):
        loads_model(JEFFCOTT + "\n[run]\n" + run + "\n")


def test_run_table_names_of_the_model_are_accepted():
    model, run = loads_model(JEFFCOTT + "\n[run]\nbending = 'x1-y1'\norbit_station = 1\n"
                             "clearance_parameter = 'disk1_mass'\n")
    assert run["bending"] == "x1-y1"


def test_figure_names_come_from_signals_only(tmp_path):
    from rotorkit.cli.figures import _figure_name

    result = rk.Result(t=np.zeros(2), y=np.zeros((2, 2)), state_names=("x1", "y1"))
    with pytest.raises(ParameterError, match="not a signal"):
        _figure_name(result, "../../escape", "../../escape")
    assert _figure_name(result, "x1_minus_y1", "x1-y1") == "x1_minus_y1.png"


# -- outputs that are not ours -------------------------------------------------
def device(tmp_path):
    """A character device to write onto: a private copy of /dev/full (root), else /dev/full itself."""
    if os.geteuid() == 0:
        path = tmp_path / "full"
        os.mknod(path, stat.S_IFCHR | 0o666, os.makedev(1, 7))
        return path
    return "/dev/full"  # a user cannot rename over /dev entries: nothing is at risk


def bad_outputs(tmp_path, want):
    """Output paths that must be refused; ``want`` is "file" or "folder"."""
    folder = tmp_path / "a_folder"
    folder.mkdir()
    (folder / "keep.txt").write_text("mine")
    a_file = tmp_path / "a_file"
    a_file.write_text("mine")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    link = tmp_path / "link_to_device"
    dev = device(tmp_path)
    os.symlink(dev, link)
    cases = {"empty": "", "device": dev, "fifo": fifo, "link to a device": link}
    if want == "file":
        cases["a folder"] = folder
    else:
        cases["a file"] = a_file
        cases["a folder of someone else's files"] = folder
    return cases


def untouched(tmp_path):
    assert stat.S_ISCHR(os.stat(device(tmp_path) if os.geteuid() != 0 else tmp_path / "full").st_mode)
    assert stat.S_ISFIFO(os.lstat(tmp_path / "fifo").st_mode)
    assert (tmp_path / "a_folder" / "keep.txt").read_text() == "mine"
    assert (tmp_path / "a_file").read_text() == "mine"


CASES = ["empty", "device", "fifo", "link to a device", "a folder", "a file", "a folder of someone else's files"]


@pytest.fixture
def no_work(monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("the output must be checked before any work")

    monkeypatch.setattr(rk.Model, "compile", forbidden)


@pytest.mark.parametrize("case", ["empty", "device", "fifo", "link to a device", "a folder"])
def test_file_writers_refuse_an_output_that_is_not_a_regular_file(tmp_path, capsys, case):
    path = bad_outputs(tmp_path, "file")[case]
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=300.0), rk.Disk(station=1, mass=2.0, radius=0.1),
                      rk.ElasticSupport(station=1, stiffness=2e4)])
    result = rk.Result(t=np.zeros(2), y=np.zeros((2, 2)), state_names=("x1", "y1"))
    for write in (lambda: model.save(path), lambda: result.save(path)):
        with pytest.raises(ParameterError):
            write()
    assert main(["export", "al31f", "--out", str(path)]) == 2
    assert "--out" in capsys.readouterr().err
    untouched(tmp_path)


@pytest.mark.parametrize("case", ["empty", "device", "fifo", "link to a device", "a file",
                                  "a folder of someone else's files"])
def test_run_refuses_an_output_folder_that_is_not_ours_before_any_work(tmp_path, capsys, no_work, case):
    path = bad_outputs(tmp_path, "folder")[case]
    assert main(["run", "al31f", "--t-end", "0.001", "--engine", "scipy", "--out", str(path)]) == 2
    assert "--out" in capsys.readouterr().err
    untouched(tmp_path)


@pytest.mark.parametrize("case", ["empty", "device", "fifo", "a file"])
def test_validate_and_sweep_refuse_a_bad_output_before_any_run(tmp_path, capsys, no_work, case):
    path = bad_outputs(tmp_path, "folder")[case]
    assert main(["validate", "al31f", "--out", str(path)]) == 2
    assert main(["sweep", "al31f", "--param", "rub_stiffness=1e6:2e6:2", "--out", str(path)]) == 2
    untouched(tmp_path)


# -- the move of a finished run into place ----------------------------------------
def write_run(names, tag):
    def write(folder):
        for name in names:
            (folder / name).write_text(f"{tag} {name}")
        return [folder / name for name in names]

    return write


def check_whole(out, names, tag):
    manifest = json.loads((out / MANIFEST).read_text())
    assert [f["name"] for f in manifest["files"]] == names
    assert sorted(p.name for p in out.iterdir()) == sorted(names + [MANIFEST])
    for name in names:
        assert (out / name).read_text() == f"{tag} {name}"


def test_a_rerun_leaves_no_file_of_the_old_run(tmp_path):
    out = tmp_path / "out"
    write_folder(out, write_run(["signals.npz", "orbit_station2.png", "x2.png"], "old"))
    write_folder(out, write_run(["signals.npz", "x3.png"], "new"))
    check_whole(out, ["signals.npz", "x3.png"], "new")
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no staging folder left


KILLED_MOVE = textwrap.dedent("""
    import os, sys
    from pathlib import Path
    from rotorkit import files

    def write(folder):
        for name in ("signals.npz", "x3.png"):
            (folder / name).write_text(f"new {name}")
        return [folder / "signals.npz", folder / "x3.png"]

    stage, exchange = sys.argv[2], sys.argv[3] == "exchange"
    if not exchange:
        files._exchange = lambda a, b: False
    files._stage = lambda name: os.kill(os.getpid(), 9) if name == stage else None
    files.write_folder(Path(sys.argv[1]), write)
""")


@pytest.mark.skipif(not hasattr(signal, "SIGKILL"), reason="POSIX signals")
@pytest.mark.parametrize("how, stage", [("exchange", "staged"), ("exchange", "exchanged"), ("exchange", "removed"),
                                        ("renames", "staged"), ("renames", "moved"), ("renames", "removed")])
def test_a_run_killed_at_any_step_of_the_move_leaves_the_old_or_the_new_run_whole(tmp_path, how, stage):
    out = tmp_path / "out"
    old = ["signals.npz", "orbit_station2.png", "x2.png"]
    write_folder(out, write_run(old, "old"))
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    child = subprocess.run([sys.executable, "-c", KILLED_MOVE, str(out), stage, how], env=env, timeout=60)
    assert child.returncode == -signal.SIGKILL
    if stage == "staged":
        check_whole(out, old, "old")
    else:
        check_whole(out, ["signals.npz", "x3.png"], "new")
    write_folder(out, write_run(["signals.npz"], "third"))  # the next run cleans what the killed one left
    check_whole(out, ["signals.npz"], "third")
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_the_killed_stage_between_two_renames_leaves_both_runs_whole_beside_the_folder(tmp_path):
    """Without an atomic exchange (not Linux), a kill between the two renames leaves no ``out`` for an instant;
    both runs are then whole in hidden folders beside it."""
    out = tmp_path / "out"
    write_folder(out, write_run(["a"], "old"))
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    child = subprocess.run([sys.executable, "-c", KILLED_MOVE, str(out), "old moved aside", "renames"], env=env,
                           timeout=60)
    assert child.returncode == -signal.SIGKILL
    hidden = sorted(p for p in tmp_path.iterdir() if p.name.startswith(".out.rotorkit-"))
    assert len(hidden) == 2
    runs = [p / "run" if (p / "run").exists() else p for p in hidden]
    for run in runs:
        assert (run / MANIFEST).exists()
