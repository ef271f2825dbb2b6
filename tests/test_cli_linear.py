"""Linear-analysis commands: modes, static, campbell, unbalance write their tables, CSV and figures."""

import pytest

from rotorkit.cli import main

RIGID = ["--set", "rub=false", "--set", "maneuver=false", "--backend", "python"]


def test_modes_and_static_commands(tmp_path, capsys):
    assert main(["modes", "al31f", "--out", str(tmp_path), "--units", "Hz", "--shapes", "1",
                 "--cage-samples", "1", "--backend", "python"]) == 0
    out = capsys.readouterr().out
    assert "natural (Hz)" in out and "log dec" in out and "whirl" in out
    header, first = (tmp_path / "modes.csv").read_text().splitlines()[:2]
    assert header.startswith("mode,natural_frequency_Hz") and first.startswith("1,")
    assert 40.0 < float(first.split(",")[1]) < 72.0  # MODEL_NOTES: lowest bending ~336 rad/s = 53 Hz
    assert (tmp_path / "mode1.png").stat().st_size > 0 and (tmp_path / "mode1_orbits.png").stat().st_size > 0
    assert main(["static", "al31f", "--out", str(tmp_path), "--backend", "python"]) == 0
    out = capsys.readouterr().out
    assert "support1" in out and "force on rotor (N)" in out
    assert (tmp_path / "static.png").stat().st_size > 0 and "support1,y1," in (tmp_path / "static.csv").read_text()


@pytest.mark.slow
def test_campbell_and_unbalance_commands(tmp_path, capsys):
    assert main(["campbell", "al31f", *RIGID, "--out", str(tmp_path), "--speeds", "250:450:5", "--modes", "2",
                 "--cage-samples", "1", "--units", "rpm"]) == 0
    out = capsys.readouterr().out
    assert "critical speeds" in out and "LP" in out
    for name in ("campbell.csv", "campbell.png", "stability.png"):
        assert (tmp_path / name).stat().st_size > 0
    assert main(["unbalance", "al31f", *RIGID, "--out", str(tmp_path), "--speeds", "100:600:50",
                 "--unbalance", "2:1e-5:0", "--station", "2"]) == 0
    out = capsys.readouterr().out
    assert "peak major semi-axis" in out
    assert (tmp_path / "unbalance_LP_2.csv").read_text().count("\n") == 51
    assert (tmp_path / "bode_LP_x2.png").stat().st_size > 0


@pytest.mark.parametrize("args, match", [
    (["campbell", "al31f", "--speeds", "3:2:1"], "--speeds '3:2:1'"),
    (["unbalance", "al31f", "--unbalance", "2"], "STATION:KG_M"),
    (["modes", "al31f", "--speed-parameter", "XX_speed"], "--speed-parameter 'XX_speed'"),
])
def test_bad_arguments_exit_2(args, match, capsys):
    assert main([*args, "--backend", "python"]) == 2
    assert match in capsys.readouterr().err
