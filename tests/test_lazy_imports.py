"""``import rotorkit`` is cheap: the heavy libraries load only when something needs them."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

import rotorkit

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("sympy", "numba", "matplotlib", "scipy", "pint")


def loaded_after(code):
    """The heavy modules in sys.modules after running ``code`` in a fresh interpreter."""
    probe = code + f"\nimport sys, json; print(json.dumps([m for m in {HEAVY!r} if m in sys.modules]))"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, cwd=ROOT,
                         env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"}, timeout=300)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_import_rotorkit_loads_no_heavy_library():
    assert loaded_after("import rotorkit") == []
    assert loaded_after("import rotorkit.errors; from rotorkit import ParameterError") == []


def test_using_a_name_loads_what_it_needs():
    """The probe can see an import: using the symbolic layer does load sympy (building a model does not)."""
    assert "sympy" not in loaded_after("import rotorkit; rotorkit.Model")
    assert "sympy" in loaded_after("import rotorkit; rotorkit.preset('al31f').equations()")


def test_every_public_name_resolves():
    for name in rotorkit.__all__:
        assert getattr(rotorkit, name) is not None
    assert set(rotorkit.__all__) <= set(dir(rotorkit))
    assert rotorkit.analysis.__name__ == "rotorkit.analysis"  # submodules as attributes, as before


def test_the_simulate_function_is_not_shadowed_by_its_module():
    import rotorkit.simulate  # noqa: F401  (an import of the submodule must not replace the function)

    assert callable(rotorkit.simulate) and rotorkit.simulate.__module__ == "rotorkit.simulate"


def test_unknown_attribute_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'Dsik'"):
        rotorkit.Dsik  # noqa: B018


#: what ``rotorkit run`` does with a scene before it compiles: read the preset, build the model (with a --set
#: override), ask it for its cache key and parameters, check the output folder
BEFORE_COMPILE = """
import argparse
from rotorkit.cli.common import load_preset
from rotorkit.files import check_output_folder

for preset in ("al31f", "rig"):
    args = argparse.Namespace(preset=preset, set=[])
    module, model, _ = load_preset(args)
    model.structure_key, model.parameters, model.parameter_units, model.effects, model.masses(), repr(model)
    model.time_event_parameters(), model.fixed_time_events(), model.coordinate_names
args = argparse.Namespace(preset="al31f", set=["rub_stiffness=9e6", "maneuver=false"])
module, model, _ = load_preset(args)
assert model.structure_key and model.parameters["rub2_contact_stiffness"] == 9e6
check_output_folder("{out}")
"""


def test_building_a_preset_loads_no_sympy(tmp_path):
    """A warm run (equations in the disk cache) derives nothing, so it must not pay for importing sympy."""
    assert "sympy" not in loaded_after(BEFORE_COMPILE.format(out=tmp_path / "out"))


def test_the_model_probe_sees_a_derivation(tmp_path):
    """The probe can fail: deriving the same model does load sympy."""
    code = BEFORE_COMPILE.format(out=tmp_path / "out") + "\nmodel.equations()"
    assert "sympy" in loaded_after(code)
