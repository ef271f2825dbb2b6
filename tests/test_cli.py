"""Command line: strict --set parsing, run writes its files, equations prints."""

import os
import subprocess
import sys

import pytest

from rotorkit.cli import main, parse_assignment
from rotorkit.errors import ParameterError


def test_parse_assignment():
    assert parse_assignment("rub_stiffness=2e6") == ("rub_stiffness", 2e6)
    name, q = parse_assignment("rub_stiffness=2e3 N/mm")
    assert name == "rub_stiffness" and q.to("N/m").magnitude == pytest.approx(2e6)
    assert parse_assignment("rub=false", {"rub": True}) == ("rub", False)


@pytest.mark.parametrize("text, match", [
    ("rub_stiffness", "expected name=value"),
    ("rub_stiffness=abc", "not a number or a quantity"),
    ("rub=maybe", "expected true or false"),
    ("1x=2", "not a parameter name"),
])
def test_parse_assignment_rejects(text, match):
    with pytest.raises(ParameterError, match=match):
        parse_assignment(text, {"rub": True})


def test_run_writes_plots_and_signals(tmp_path, capsys):
    code = main(["run", "al31f", "--t-end", "0.05", "--out", str(tmp_path), "--set", "rub_stiffness=2e6"])
    assert code == 0
    out = capsys.readouterr().out
    for name in ("signals.npz", "orbit_station2.png", "x2.png", "alpha2_minus_alpha5.png", "summary.json"):
        assert (tmp_path / name).stat().st_size > 0
        assert f"wrote {tmp_path / name}" in out
    import rotorkit as rk

    assert rk.load_result(tmp_path / "signals.npz").parameters["rub2_contact_stiffness"] == 2e6


@pytest.mark.parametrize("args, match", [
    (["run", "al31f", "--set", "rub_stifness=1"], "did you mean rub_stiffness"),
    (["run", "al31f", "--set", "rub_stiffness=2 kg"], "wrong unit"),
    (["run", "nosuch"], "unknown preset 'nosuch'"),
])
def test_errors_exit_2_with_a_message(args, match, capsys):
    assert main(args) == 2
    assert match in capsys.readouterr().err


def test_equations_prints_the_model(capsys):
    assert main(["equations", "al31f", "--set", "rub=false"]) == 0
    out = capsys.readouterr().out
    assert "16 coordinates" in out and "rub2" not in out and "M[x2, alpha2]" in out
    assert "disk2_mass" in out and "kg" in out  # the parameter table


@pytest.mark.parametrize("compiler", ["0", ""], ids=["no_compiler", "c"])
def test_paths_without_numba(compiler):
    """With numba unavailable, 'auto' takes the c back end (compiled engine) when a C compiler is found, else the
    pure-Python back end and the scipy engine; both run."""
    from rotorkit.codegen.cbuild import compiler as find_compiler

    if not compiler and find_compiler() is None:
        pytest.skip("no C compiler on this machine")
    expected = ("python",) if compiler == "0" else ("python", "c")
    code = (
        "import sys; sys.modules['numba'] = None\n"
        "import rotorkit as rk\n"
        f"assert rk.available_backends() == {expected!r}, rk.available_backends()\n"
        "s = rk.preset('al31f').compile()\n"
        "r = rk.simulate(s, (0.0, 0.01))\n"
        "print(s.backend, r.stats['engine'], r.stats['nfev'])\n"
    )
    env = dict(os.environ, ROTORKIT_C_COMPILER=compiler)
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stderr
    backend, engine, nfev = proc.stdout.split()
    assert (backend, engine) == (expected[-1], "scipy" if compiler == "0" else "compiled") and int(nfev) > 0


def test_accuracy_command_writes_table_and_figures(tmp_path, capsys):
    code = main(["accuracy", "al31f", "--t-end", "0.3", "--window", "0.1,0.3", "--cases", "scipy:RK45",
                 "--tolerances", "1e-3", "--reference-rtol", "1e-8", "--out", str(tmp_path)])
    assert code == 0
    out = capsys.readouterr().out
    assert "reference took" in out and "scipy        RK45" in out
    for name in ("accuracy.csv", "work_precision.png", "error_growth.png"):
        assert (tmp_path / name).stat().st_size > 0
    assert (tmp_path / "accuracy.csv").read_text().count("\n") == 2


@pytest.mark.parametrize("args, match", [
    (["accuracy", "al31f", "--cases", "gpu:DOP853"], "expected engine:method"),
    (["accuracy", "al31f", "--tolerances", "small"], "comma-separated numbers"),
])
def test_accuracy_argument_errors(args, match, capsys):
    assert main(args) == 2
    assert match in capsys.readouterr().err


def test_sweep_command_draws_cascades_and_resumes(tmp_path, capsys):
    args = ["sweep", "al31f", "--param", "rub_stiffness=2e6,8e6", "--workers", "1", "--out", str(tmp_path)]
    assert main(args) == 0
    first = capsys.readouterr()
    assert "2 points: 2 ok" in first.out and first.err.count(": ok") == 2
    for name in ("cascade_x2.png", "cascade_alpha2_minus_alpha5.png", "bifurcation_x2.png", "sweep.json",
                 "sweep.nc"):
        assert (tmp_path / name).stat().st_size > 0
    assert main(args) == 0  # resumes: nothing recomputed
    assert capsys.readouterr().err.count(": cached") == 2


def test_sweep_command_maps_a_grid(tmp_path, capsys):
    import xarray as xr

    args = ["sweep", "al31f", "--param", "rub_stiffness=2e6,8e6", "--param", "friction_coefficient=0,0.1",
            "--order", "1", "--order", "1/2", "--t-end", "0.3", "--window", "0.1", "0.3", "--workers", "1",
            "--out", str(tmp_path)]
    assert main(args) == 0
    out = capsys.readouterr()
    assert "4 points: 4 ok" in out.out and out.err.count("[4/4]") == 1
    for name in ("status_map.png", "map_x2_order_1.png", "map_x2_order_1_2.png"):
        assert (tmp_path / name).stat().st_size > 0
    with xr.open_dataset(tmp_path / "sweep.nc") as ds:
        assert ds.order_amplitude.dims == ("rub_stiffness", "friction_coefficient", "signal", "order")
        assert ds.rub_stiffness.attrs["units"] == "N/m" and ds.frequency.attrs["units"] == "rad/s"
        assert list(ds.order.values) == ["1", "1/2"]


@pytest.mark.parametrize("args, match", [
    (["--param", "rub_stiffness=1:2:3", "--param", "rub_stiffness=1,2"], "twice"),
    (["--param", "rub_stiffness=1:2:3", "--param", "friction_coefficient=0,0.1", "--zip"], "one length"),
    (["--param", "rub_stiffness=1:2:1000000"], "1,000,000 points"),
    (["--param", "rub_stiffness=1:2:1000", "--param", "lp_speed=1:2:1000"], "1,000,000 points"),
    (["--param", "rub_stiffness=1:2:3", "--scheduler", "tcp://127.0.0.1:9"], "cannot reach the Dask scheduler"),
])
def test_sweep_command_errors(args, match, tmp_path, capsys):
    assert main(["sweep", "al31f", *args, "--t-end", "0.3", "--window", "0.1", "0.3", "--out", str(tmp_path)]) == 2
    assert match in capsys.readouterr().err


def test_sweep_command_takes_a_model_file(tmp_path, capsys):
    import xarray as xr

    from sweep_models import build_jeffcott, unbalance_amplitude

    path = tmp_path / "jeffcott.toml"
    build_jeffcott(rub_stiffness=0.0).save(path)
    args = ["sweep", str(path), "--param", "disk1_eccentricity=1e-5,2e-5", "--t-end", "0.5", "--window", "0.2",
            "0.5", "--workers", "1", "--order", "1", "--out", str(tmp_path / "out")]
    assert main(args) == 0
    assert "2 points: 2 ok" in capsys.readouterr().out
    with xr.open_dataset(tmp_path / "out" / "sweep.nc") as ds:
        assert list(ds.signal.values) == ["x1"] and ds.disk1_eccentricity.attrs["units"] == "m"
        for e in (1e-5, 2e-5):
            got = float(ds.order_amplitude.sel(disk1_eccentricity=e, signal="x1", order="1"))
            assert got == pytest.approx(unbalance_amplitude(e), rel=2e-3)
    assert main(["sweep", str(path), "--param", "disk1_eccentricty=1,2"]) == 2
    assert "did you mean disk1_eccentricity" in capsys.readouterr().err


def test_sweep_rejects_an_unknown_parameter(capsys):
    assert main(["sweep", "al31f", "--param", "rub_stifness=1:2:3"]) == 2
    assert "did you mean rub_stiffness" in capsys.readouterr().err


def test_repeated_set_name_is_refused(capsys):
    code = main(["run", "al31f", "--t-end", "0.001", "--set", "rub_stiffness=2e6", "--set", "rub_stiffness=3e6",
                 "--out", "/nonexistent-never-written"])
    assert code == 2
    assert "rub_stiffness is given twice" in capsys.readouterr().err


def test_set_exponent_tower_in_any_spelling_is_refused():
    for text in ("x=9**9**9", "x=1 m^9^9^9", "x=1 m**(9**9)", "x=1 (((m^12)^12)^12)"):
        with pytest.raises(ParameterError, match="^--set"):
            parse_assignment(text)
