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
    """The probe can see an import: using the symbolic layer does load sympy."""
    assert "sympy" in loaded_after("import rotorkit; rotorkit.Model")


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
