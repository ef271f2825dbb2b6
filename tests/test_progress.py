"""Slow one-off steps (derive, generate, compile) say so; quick ones stay silent."""

import io
import time

import rotorkit as rk
from rotorkit import progress


def test_a_slow_step_is_announced_with_its_duration():
    out = io.StringIO()
    with progress.announce_if_slow("compiling x", after=0.05, stream=out):
        time.sleep(0.3)
    lines = out.getvalue().splitlines()
    assert lines[0] == "rotorkit: compiling x ..."
    assert lines[1].startswith("rotorkit: compiling x: done in 0.")


def test_a_quick_step_prints_nothing_and_quiet_silences(monkeypatch):
    out = io.StringIO()
    with progress.announce_if_slow("quick", after=1.0, stream=out):
        pass
    time.sleep(0.05)
    monkeypatch.setenv("ROTORKIT_QUIET", "1")
    with progress.announce_if_slow("slow but quiet", after=0.0, stream=out):
        time.sleep(0.1)
    assert out.getvalue() == ""


def test_first_compile_of_a_new_structure_says_so(monkeypatch, tmp_path, capfd):
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(progress, "AFTER", 0.0)
    model = rk.Model([rk.Rotor(name="R", stations=("announce",), speed=10.0),
                      rk.LumpedMass(station="announce", mass=1.0),
                      rk.ElasticSupport(station="announce", stiffness=1e3)])
    model.compile(backend="python")
    err = capfd.readouterr().err
    assert "rotorkit: deriving the equations of model (2 coordinates, 3 elements) ..." in err
    assert "rotorkit: generating code for model" in err and "done in" in err
