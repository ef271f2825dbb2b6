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
