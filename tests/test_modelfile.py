"""Model files (TOML): exact round trips, units, errors that name file/element/field, hostile files."""

import dataclasses
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import rotorkit as rk
from rotorkit.errors import ParameterError
from rotorkit.modelfile import ModelFileError, dumps_model, element_types, loads_model

ROOT = Path(__file__).resolve().parent.parent
HEADER = 'format = "rotorkit-model"\nversion = 1\n'


def sink_model():
    """One model holding every element type (and both ways of giving shaft stiffness)."""
    return rk.Model([
        rk.Rotor(name="LP", stations=(1, 2, 3, 4, 5),
                 speed=rk.elements.SpeedProfile.table(times=[0.0, 0.5], speeds=[300.0, 1500.0]),
                 damping=rk.elements.Rayleigh(alpha=1.0, beta=1e-5)),
        rk.Rotor(name="HP", stations=("h",), speed_ratio=1.3, reference="LP",
                 damping=rk.elements.ModalDamping(ratios=(0.01, 0.02), remaining=0.001)),
        rk.LumpedMass(station=1, mass=2.0),
        rk.Disk(station=2, mass=10.0, radius=0.075, eccentricity=4.635e-5, phase=0.1, torsion=True),
        rk.Disk(station=3, mass=3.0, polar_inertia=0.02),
        rk.Disk(name="hpdisk", station="h", mass=8.0, radius=0.07, eccentricity=1e-5),
        rk.Disk.from_geometry(station=4, width=0.02, inner_diameter=0.01, outer_diameter=0.1,
                              material=rk.elements.Material.steel()),
        rk.ElasticSupport(station=1, stiffness=1e6, damping=300.0),
        rk.ElasticSupport(station="h", stiffness=2e6),
        rk.ShaftSegment(start=1, end=2, length=0.33, youngs_modulus=2e11, area_moment=1.178e-7,
                        end_condition="clamped-free", bending_damping=150.0, shear_modulus=7.7e10,
                        polar_area_moment=2.356e-7, torsional_damping=1.0),
        rk.ShaftSegment(start=2, end=3, bending_stiffness=3e5),
        rk.elements.BeamSegment(start=3, end=4, length=0.2, outer_diameter=0.04, inner_diameter=0.01,
                                material=rk.elements.Material.titanium_ti6al4v(), elements=2),
        rk.elements.TaperedBeamSegment(start=4, end=5, length=0.1, outer_diameter=0.04, outer_diameter_end=0.03,
                                       material=rk.elements.Material.steel(), axial_force=-500.0),
        rk.BallBearing(inner_station=3, outer_station="h", contact_stiffness=1.334e10, clearance=5e-6,
                       n_balls=8, inner_race_radius=0.0401, outer_race_radius=0.0639),
        rk.RubStator(station=2, clearance=1.34e-4, contact_stiffness=8e6, friction_coefficient=0.1),
        rk.Maneuver.barrel_roll(rate=np.pi, radius=3.0, start=0.2, end=0.4),
        rk.elements.LinearBearing.tabulated(station=2, speeds=[0.0, 1000.0], kxx=[1e6, 2e6], kyy=[1e6, 1.5e6],
                                            kxy=[0.0, 1e5], cxx=[10.0, 20.0],
                                            pedestal=rk.elements.Pedestal(mass=20.0, kxx=5e6, kyy=3e6, cyy=50.0)),
        rk.elements.LinearBearing(station=4, kxx=1e5, kyy=1e5, ktxx=2e3, ktyy=3e3, ktxy=100.0, ctyy=0.5),
        rk.elements.Seal.frequency_table(station=4, frequencies=[0.0, 500.0], kxx=[1e4, 2e4], kyy=[1e4, 2e4],
                                         cxy=[1.0, 2.0], whirl=100.0, interpolation="pchip"),
        rk.elements.LinearBearing(station=3, other_station="h", kxx=1e5, kyy=1e5, cxy=3.0, cyx=-3.0),
        rk.elements.BaseRotation(rate_y=0.5, center_x=-800.0, axial_positions={1: 0.1, 2: 0.4}),
        rk.SqueezeFilmDamper(station=4, radius=0.05, length=0.015, clearance=2e-4, viscosity=0.01,
                             centring_stiffness=1e6, centring_damping=10.0, offset_y=-1e-5),
        rk.JournalBearing(station=1, radius=0.025, length=0.02, clearance=5e-5, viscosity=0.02, cavitation="full"),
        rk.Rotor(name="IP", stations=("i",), speed=rk.Drive.motor(speeds=[0.0, 800.0], torques=[5.0, 1.0],
                                                                  initial_speed=400.0, polar_inertia=0.01)),
        rk.LumpedMass(station="i", mass=4.0),
        rk.ElasticSupport(station="i", stiffness=1e6),
        rk.IntershaftRub(inner_station=2, outer_station="i", clearance=2e-4, contact_stiffness=5e6,
                         friction_coefficient=0.1, contact_radius=0.05),
    ], name="sink")


def _types_in(value, out):
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        out.add(type(value).__name__)
        for f in dataclasses.fields(value):
            _types_in(getattr(value, f.name), out)
    elif isinstance(value, (tuple, list)):
        for v in value:
            _types_in(v, out)
    return out


def test_sink_model_covers_every_registered_type():
    covered = _types_in(list(sink_model().elements) + [rk.Maneuver.steady()], set())
    missing = set(element_types()) - covered
    assert not missing, f"add an instance of {sorted(missing)} to sink_model() so its round trip is tested"


@pytest.mark.parametrize("build", [sink_model, lambda: rk.preset("al31f"),
                                   lambda: rk.preset("al31f", rub=False, torsion=False, maneuver=False)],
                         ids=["every-element-type", "al31f", "al31f-reduced"])
def test_round_trip_is_exact(build, tmp_path):
    model = build()
    path = model.save(tmp_path / "m.toml")
    loaded = rk.load_model(path)
    assert loaded.name == model.name
    assert loaded.elements == model.elements  # every field, bit for bit (floats via repr)
    assert loaded.parameters == model.parameters
    assert loaded.structure_key == model.structure_key
    assert dumps_model(loaded) == dumps_model(model)


def test_round_trip_equations_and_rhs_identical(tmp_path):
    model = sink_model()
    with pytest.raises(ParameterError, match="ModalDamping: model 'sink' has forces that are not linear"):
        model.compile(backend="python")  # its rub and Hertzian bearings leave no undamped modes to damp

    def undamped(e):
        modal = isinstance(e, rk.Rotor) and isinstance(e.damping, rk.ModalDamping)
        return dataclasses.replace(e, damping=None) if modal else e

    model = rk.Model([undamped(e) for e in model.elements], name="sink")
    loaded = rk.load_model(model.save(tmp_path / "m.toml"))
    a, b = model.equations(), loaded.equations()
    assert a.mass_matrix == b.mass_matrix and a.forcing == b.forcing
    sa, sb = model.compile(backend="python"), loaded.compile(backend="python")
    y = np.random.default_rng(1).normal(scale=1e-5, size=sa.n_states)
    assert np.array_equal(sa.rhs(0.3, y), sb.rhs(0.3, y))


def test_units_in_any_unit_of_the_right_dimension():
    text = HEADER + """
[[element]]
type = "Rotor"
name = "R"
stations = [1]
speed = "12000 rpm"

[[element]]
type = "Disk"
station = 1
mass = "2000 g"
radius = "10 cm"
eccentricity = 1e-5

[[element]]
type = "ElasticSupport"
station = 1
stiffness = "20 kN/m"
"""
    model, run = loads_model(text, source="jeffcott.toml")
    p = model.parameters
    assert p["R_speed"] == pytest.approx(12000 * 2 * np.pi / 60, rel=1e-12)
    assert p["disk1_mass"] == pytest.approx(2.0) and p["disk1_radius"] == pytest.approx(0.1)
    assert p["disk1_eccentricity"] == 1e-5 and p["support1_stiffness"] == pytest.approx(2e4)
    assert run == {}


def _jeffcott(**disk):
    fields = {"station": "1", "mass": '"2 kg"', "radius": '"0.1 m"', **disk}
    lines = "\n".join(f"{k} = {v}" for k, v in fields.items())
    return (HEADER + '[[element]]\ntype = "Rotor"\nname = "R"\nstations = [1]\nspeed = "300 rad/s"\n\n'
            f'[[element]]\ntype = "Disk"\n{lines}\n\n'
            '[[element]]\ntype = "ElasticSupport"\nstation = 1\nstiffness = "2e4 N/m"\n')


@pytest.mark.parametrize("disk, match", [
    ({"mass": '"2 m"'}, r"rotor\.toml: element 2 \(Disk\).*mass.*'2 m'.*kg"),
    ({"mass": '"-2 kg"'}, r"rotor\.toml: element 2 \(Disk\).*mass.*must be > 0"),
    ({"mass": '"2 kilogramz"'}, r"rotor\.toml: .*element 2 \(Disk\) field 'mass'.*kilogramz"),
    ({"mass": "true"}, r"element 2 \(Disk\) field 'mass'.*expected a quantity"),
    ({"masss": '"2 kg"'}, r"element 2 \(Disk\): unknown field 'masss'; did you mean mass\?"),
    ({"eccentricity": '"1e999999 m"'}, r"element 2 \(Disk\).*eccentricity"),
    ({"eccentricity": "1e999"}, r"element 2 \(Disk\).*eccentricity.*not finite"),
    ({"radius": '"9**9**9 m"'}, r"element 2 \(Disk\).*radius"),
    ({"radius": '"1 m**999999"'}, r"element 2 \(Disk\).*radius"),
])
def test_bad_entries_name_file_element_field_and_value(disk, match):
    with pytest.raises(ParameterError, match=match):
        loads_model(_jeffcott(**disk), source="rotor.toml")


@pytest.mark.parametrize("text, match", [
    (HEADER + '[[element]]\ntype = "Dsik"\nstation = 1\n', r"element 1: unknown type 'Dsik'; did you mean Disk"),
    (HEADER + '[[element]]\ntype = "os.system"\n', r"unknown type 'os.system'"),
    (HEADER + '[[element]]\nstation = 1\n', r"element 1: type = None"),
    (HEADER + 'elements = []\n', r"unknown key 'elements'; did you mean element"),
    ('format = "rotorkit-model"\nversion = 99\n', r"version.*99"),
    ('version = 1\n', r"format.*expected format = \"rotorkit-model\""),
    ("format = [\n", r"not valid TOML"),
    (HEADER + "[run]\nt_ned = 1.0\n[[element]]\ntype='Rotor'\nname='R'\nstations=[1]\nspeed=1.0\n",
     r"unknown key 't_ned'; did you mean t_end"),
])
def test_bad_files(text, match):
    with pytest.raises(ModelFileError, match=match):
        loads_model(text, source="f.toml")


def _refused_quickly(text_or_path, match):
    """Refused with a clear error after little work: CPU time of this process (a loaded machine stretches wall
    time, not the work done), far above the milliseconds a bounded parser needs, far below what parsing a
    100 MB string or evaluating a huge exponent would cost."""
    start = time.process_time()
    with pytest.raises(ModelFileError, match=match):
        if isinstance(text_or_path, Path):
            rk.load_model(text_or_path)
        else:
            loads_model(text_or_path, source="hostile.toml")
    assert time.process_time() - start < 5.0


def test_hostile_files_are_refused_quickly(tmp_path):
    _refused_quickly(HEADER + "x = " + "[" * 100_000 + "]" * 100_000 + "\n", r"hostile\.toml")
    _refused_quickly(HEADER + "run = " + "{a = " * 2_000 + "1" + "}" * 2_000 + "\n", r"hostile\.toml")
    _refused_quickly(HEADER + '[[element]]\ntype = "Disk"\nstation = ' + "9" * 100_000 + "\n", r"hostile\.toml")
    nested = HEADER + '[[element]]\ntype = "Rotor"\nname = "R"\nstations = ' + "[" * 20 + "1" + "]" * 20 + "\n"
    _refused_quickly(nested, r"nested more than")
    big = tmp_path / "big.toml"
    with open(big, "w") as fh:
        fh.write(HEADER + 'name = "')
        fh.write("x" * (100 * 2**20))
        fh.write('"\n')
    _refused_quickly(big, r"big\.toml: \d+ bytes; a model file is at most")
    _refused_quickly(HEADER + 'name = "' + "x" * 20_000 + '"\n', r"a string of 20000 characters")


def test_python_functions_are_not_written():
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=1.0), rk.Disk(station=1, mass=1.0, radius=0.1),
                      rk.ElasticSupport(station=1, stiffness=1.0),
                      rk.Maneuver.profile(lambda t: sp.sin(t), lambda t: -9.81)])
    with pytest.raises(ModelFileError, match=r"Maneuver 'maneuver'\.accel_x is a Python function"):
        dumps_model(model)


def _cli(args, cwd):
    env = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}
    return subprocess.run([sys.executable, "-m", "rotorkit.cli", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=600)


def test_cli_runs_a_model_file_from_another_folder(tmp_path):
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=300.0),
                      rk.Disk(station=1, mass=2.0, radius=0.1, eccentricity=1e-4),
                      rk.ElasticSupport(station=1, stiffness=2e4, damping=4.0)], name="jeffcott")
    model.save(tmp_path / "models" / "rotor.toml", run={"t_end": 0.2, "orbit_station": 1, "bending": "x1"})
    work = tmp_path / "elsewhere"
    work.mkdir()
    proc = _cli(["run", "../models/rotor.toml", "--backend", "python", "--engine", "scipy",
                 "--set", "support1_stiffness=3e4 N/m"], work)
    assert proc.returncode == 0, proc.stderr
    out = work / "rotorkit-out" / "rotor"
    assert (out / "signals.npz").stat().st_size > 0 and (out / "orbit_station1.png").stat().st_size > 0
    result = rk.load_result(out / "signals.npz")
    assert result.parameters["support1_stiffness"] == 3e4 and result.t[-1] == pytest.approx(0.2)
    bad = _cli(["run", "../models/rotor.toml", "--set", "support1_stifness=3e4"], work)
    assert bad.returncode == 2 and "did you mean support1_stiffness" in bad.stderr


def test_cli_export_writes_the_preset(tmp_path):
    proc = _cli(["export", "al31f", "--set", "rub_stiffness=2e6"], tmp_path)
    assert proc.returncode == 0, proc.stderr
    model, run = loads_model(proc.stdout, source="al31f.toml")
    assert model.elements == rk.preset("al31f", rub_stiffness=2e6).elements
    assert run["t_end"] == 6.0 and run["orbit_station"] == 2


@pytest.mark.parametrize("argv", [["run", "al31f", "--t-end", "-1"], ["run", "al31f", "--rtol", "0"],
                                  ["stiffness", "al31f", "--t-end", "nan"], ["sweep", "al31f", "--param",
                                                                             "rub_stiffness=1:2:3", "--workers", "0"]])
def test_options_are_checked_before_any_derivation(argv, monkeypatch, capsys):
    from rotorkit.cli import main

    def forbidden(*args, **kwargs):
        raise AssertionError("derived or compiled before the options were checked")

    monkeypatch.setattr(rk.Model, "equations", forbidden)
    monkeypatch.setattr(rk.Model, "compile", forbidden)
    assert main(argv) == 2
    assert "expected" in capsys.readouterr().err


def test_sweep_and_set_give_the_same_did_you_mean(capsys):
    from rotorkit.cli import main

    assert main(["sweep", "al31f", "--param", "rub_stifness=1:2:3"]) == 2
    sweep = capsys.readouterr().err
    assert main(["equations", "al31f", "--set", "rub_stifness=1"]) == 2
    setting = capsys.readouterr().err
    hint = "'rub_stifness' is not a parameter of al31f; did you mean rub_stiffness"
    assert hint in sweep and hint in setting


def test_model_file_without_run_table_draws_the_first_disk(tmp_path):
    from types import SimpleNamespace

    from rotorkit.cli.common import load_scene

    model = rk.Model([rk.Rotor(name="R", stations=(0, 1), speed=300.0), rk.LumpedMass(station=0, mass=1.0),
                      rk.Disk(station=1, mass=2.0, radius=0.1), rk.ElasticSupport(station=0, stiffness=2e4),
                      rk.ShaftSegment(start=0, end=1, bending_stiffness=1e5)])
    args = SimpleNamespace(preset=str(model.save(tmp_path / "two.toml")), set=["R_speed=100 rad/s"])
    scene, loaded, overrides = load_scene(args)
    assert scene.OUTPUTS == {"orbit_station": 1, "bending": "x1"} and args.preset == "two"
    assert loaded.parameters["R_speed"] == 100.0 and set(overrides) == {"R_speed"}
