"""Reading a model loads the element modules it uses, not those of companions it does not hold.

A rotor at a constant speed without damping needs no ``SpeedProfile``, ``Drive`` or damping class; a beam
without a turning base no ``BaseRotation``; a bearing without a pedestal no ``Pedestal``; a model that is
read and solved from a warm cache never derives, so it needs no ``Terms`` (:mod:`rotorkit.elements.terms`).
Those modules are looked up with :func:`rotorkit.elements.base.loaded_types` (no instance exists before its
module is imported), so every fresh process reading ``examples/compressor.toml`` skips them and their
dataclasses (each costs about a millisecond to create). Each probe runs in a fresh interpreter.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import rotorkit as rk
from rotorkit.elements.base import loaded_types

ROOT = Path(__file__).resolve().parents[1]
#: the element modules a model of beams, disks and linear bearings under gravity does not need
COMPANIONS = ("damping", "drive", "speed", "base_motion", "pedestal", "terms")
HEAVY = ("sympy", "pint", "matplotlib", "scipy", "numba")

_PROBE = """
import json, sys
import rotorkit as rk
model, run = rk.modelfile.read_model_file({path!r})
print(json.dumps({{"elements": sorted(m.rsplit(".", 1)[1] for m in sys.modules if m.startswith("rotorkit.elements.")),
                   "heavy": sorted({{m.split(".")[0] for m in sys.modules}} & set({heavy!r})),
                   "parameters": sorted(model.parameters)}}))
"""


def probe(path, tmp_path):
    """Element modules, heavy libraries and parameters after a fresh process reads the model file ``path``."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), ROTORKIT_CACHE_DIR=str(tmp_path / "cache"))
    out = subprocess.run([sys.executable, "-c", _PROBE.format(path=str(path), heavy=HEAVY)], env=env, cwd=ROOT,
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_reading_the_compressor_loads_no_companion_module(tmp_path):
    seen = probe(ROOT / "examples" / "compressor.toml", tmp_path)
    assert {"rotor", "beam", "masses", "linear_bearing", "maneuver", "material"} <= set(seen["elements"])
    assert not set(COMPANIONS) & set(seen["elements"]), seen["elements"]
    assert seen["heavy"] == []  # numpy alone: no sympy (nothing derived), pint (common units), matplotlib, scipy


def test_a_model_holding_the_companions_loads_and_uses_them(tmp_path):
    """The control: the same probe sees the companion modules when the file holds them, and the elements see
    their companions (the rotor's speed table and damping, the bearing's pedestal become parameters)."""
    model = rk.Model([
        rk.Rotor(name="R", stations=(1, 2), speed=rk.SpeedProfile.table(times=[0.0, 1.0], speeds=[0.0, 100.0]),
                 damping=rk.Rayleigh(alpha=0.5, beta=1e-5)),
        rk.BeamSegment(start=1, end=2, length=0.5, outer_diameter=0.05, material=rk.Material.steel()),
        rk.Disk(station=2, mass=5.0, radius=0.1),
        rk.LinearBearing(station=1, kxx=1e7, kyy=1e7, pedestal=rk.Pedestal(mass=10.0, kxx=5e7, kyy=5e7)),
        rk.LinearBearing(station=2, kxx=1e7, kyy=1e7),
    ], name="companions")
    seen = probe(model.save(tmp_path / "companions.toml"), tmp_path)
    assert {"damping", "speed", "pedestal"} <= set(seen["elements"])
    assert seen["parameters"] == sorted(model.parameters)
    assert {"R_damping_alpha", "R_speed_w1", "linearbearing1_pedestal_mass"} <= set(seen["parameters"])


def test_loaded_types_gives_the_classes_of_imported_modules_only():
    from rotorkit.elements.pedestal import Pedestal

    assert loaded_types("pedestal.Pedestal") == (Pedestal,)
    assert loaded_types("no_such_module.Thing", "pedestal.Pedestal", "pedestal.NoSuchClass") == (Pedestal,)
    assert loaded_types() == ()
    assert not isinstance(Pedestal(mass=1.0, kxx=1.0, kyy=1.0), loaded_types("no_such_module.Thing"))
