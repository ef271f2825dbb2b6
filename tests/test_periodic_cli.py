"""The ``rotorkit periodic`` command on a model file: files written, bifurcations printed, bad input refused."""

import numpy as np

from rotorkit.cli import main


def _model_file(tmp_path):
    from test_periodic import rub_model

    path = tmp_path / "jeffrub.toml"
    rub_model().save(path)
    return path


def test_periodic_command_writes_the_branch(tmp_path, capsys):
    from rotorkit.periodic.branch import load_branch

    path = _model_file(tmp_path)
    out = tmp_path / "out"
    code = main(["periodic", str(path), "--param", "R_speed=60:200", "--harmonics", "2", "--station", "1",
                 "--backend", "c", "--out", str(out)])
    printed = capsys.readouterr()
    assert code == 0, printed.err
    assert "grazing fold at R_speed" in printed.out and "fold at R_speed = 13" in printed.out
    branch = load_branch(out / "periodic_branch.nc")
    rows = np.loadtxt(out / "periodic_branch.csv", delimiter=",", skiprows=1)
    assert np.allclose(rows[:, 2], branch.max_radius(1), rtol=1e-9)
    assert (out / "periodic_response_1.png").stat().st_size > 1000


def test_periodic_command_refuses_bad_ranges(tmp_path, capsys):
    path = _model_file(tmp_path)
    assert main(["periodic", str(path), "--param", "R_speed=60"]) == 2
    assert "NAME=START:STOP" in capsys.readouterr().err
    assert main(["periodic", str(path), "--param", "R_sped=60:80", "--out", str(tmp_path)]) == 2
    assert "did you mean R_speed" in capsys.readouterr().err


def test_the_helper_process_writes_the_same_files(tmp_path, capsys, monkeypatch):
    """With two cores the files are written by a helper forked at the start (it imports matplotlib and xarray
    while the branch is followed): the same branch file, the same table, the figures, as written here."""
    import os
    import threading

    from rotorkit.cli import figures
    from rotorkit.periodic.branch import load_branch

    path = _model_file(tmp_path)
    args = ["periodic", str(path), "--param", "R_speed=60:200", "--harmonics", "2", "--station", "1",
            "--backend", "c", "--out"]
    monkeypatch.setenv(figures.PROCESS_VARIABLE, "0")
    assert main(args + [str(tmp_path / "here")]) == 0
    for thread in threading.enumerate():  # a C loop still being built by an earlier test: not forked mid-build
        if thread.name.startswith("rotorkit"):
            thread.join(timeout=120)
    monkeypatch.delenv(figures.PROCESS_VARIABLE)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1}, raising=False)
    monkeypatch.setattr(threading, "active_count", lambda: 1)  # threads other tests left idle do not matter here
    sent = []
    call = figures.FigureProcess.call
    monkeypatch.setattr(figures.FigureProcess, "call", lambda self, *job: sent.append(call(self, *job)) or sent[-1])
    assert main(args + [str(tmp_path / "helper")]) == 0, capsys.readouterr().err
    assert sent == [True]
    here, there = (load_branch(tmp_path / folder / "periodic_branch.nc") for folder in ("here", "helper"))
    assert np.array_equal(here.parameter, there.parameter) and np.array_equal(here.coefficients, there.coefficients)
    assert (tmp_path / "here" / "periodic_branch.csv").read_bytes() == \
        (tmp_path / "helper" / "periodic_branch.csv").read_bytes()
    assert (tmp_path / "helper" / "periodic_response_1.png").stat().st_size > 1000
