"""The single-rotor rub test rig (models/rig.py): topology, sensors, contact only during the roll,
and the paper's section-4 claims through `rotorkit validate rig`."""

import math

import numpy as np
import pytest

import rotorkit
from rotorkit import ParameterError
from rotorkit.presets import preset_module


def test_rig_builds_with_torsion_at_both_shaft_ends_and_is_listed():
    assert "rig" in rotorkit.list_presets() and "al31f" in rotorkit.list_presets()
    model = rotorkit.preset("rig")
    assert set(model.torsion_stations) == {1, 2, 3}  # encoder 1, disk, encoder 2; station 4 is the drive
    assert {"rub", "maneuver", "torsion", "gravity", "unbalance"} <= set(model.effects)
    p = model.parameters
    assert p["R_speed"] == pytest.approx(1200 * 2 * math.pi / 60)
    assert p["maneuver_roll_radius"] == 0.4 and p["maneuver_roll_rate"] == pytest.approx(math.pi)
    assert (p["maneuver_roll_start"], p["maneuver_roll_end"]) == (2.0, 4.0)
    module = preset_module("rig")
    for sensor in module.SENSORS:  # every sensor sits on a station the model has, with torsion where needed
        if hasattr(sensor, "check"):
            sensor.check(model)
    rates = {s.name: s.sample_rate for s in module.SENSORS if hasattr(s, "sample_rate")}
    assert rates == {"probe_h": 2000.0, "probe_v": 2000.0, "omega_1": 12800.0, "omega_2": 12800.0}


def test_rig_lumped_stiffness_is_the_simply_supported_shaft():
    module = preset_module("rig")
    d, span = module.SHAFT_DIAMETER, module.SPAN
    k_mid = 48 * module.E_STEEL * (math.pi * d**4 / 64) / span**3  # mid-span load on a simply supported shaft
    segs = [e for e in rotorkit.preset("rig").elements if type(e).__name__ == "ShaftSegment" and e.has_bending()]
    assert sum(s.bending_stiffness_value() for s in segs) == pytest.approx(k_mid)


@pytest.mark.parametrize("overrides, match", [
    ({"rub_clearance": 6e-3}, r"rub_clearance=0.006 m: the rig's stator adjusts from 0 to 5 mm"),
    ({"clearance": 1e-4}, r"unknown override 'clearance'; did you mean rub_clearance"),
    ({"rub": "yes"}, r"rub='yes' must be True or False"),
])
def test_rig_bad_overrides_are_named(overrides, match):
    with pytest.raises(ParameterError, match=match):
        rotorkit.preset("rig", **overrides)


@pytest.fixture(scope="module")
def study():
    from rotorkit.validation import Study

    module = preset_module("rig")
    options = dict(module.STUDY)
    return Study("rig", options.pop("signals"), t_end=module.OUTPUTS["t_end"], **options)


@pytest.mark.slow
def test_rig_runs_0_6_s_without_rub_before_the_roll_and_with_rub_during_it(study):
    run = study.run()
    assert run.status == "ok", run.detail
    r = run.measurement.result
    assert r.t[0] == 0.0 and r.t[-1] == pytest.approx(6.0)
    radius = np.hypot(r["x2"], r["y2"])
    clearance = r.parameters["rub2_clearance"]
    assert radius[r.t < 2.0].max() < clearance  # steady: no contact
    assert (radius[(r.t >= 2.0) & (r.t < 4.0)] > clearance).any()  # the roll: contact
    omega_1 = run.measurement["omega_1"]
    assert omega_1.sample_rate == 12800.0 and omega_1.t.size == 6 * 12800 + 1
    assert np.allclose(omega_1.values, 1200 * 2 * math.pi / 60, rtol=1e-3)  # the encoders read the shaft speed


@pytest.mark.slow
def test_validate_rig_reproduces_its_claims(study):
    module = preset_module("rig")
    results = [claim(study) for claim in module.CLAIMS]
    bad = [(r.claim, r.verdict, r.measured) for r in results if r.verdict != "reproduced"]
    assert not bad, bad
    assert study.runs_done == 1  # every claim reads the one default run


def test_validate_cli_rig_with_the_claims_of_the_preset(monkeypatch, capsys, tmp_path):
    """The CLI passes the preset's STUDY settings (sensors, band, high-pass) to the Study."""
    from rotorkit.cli import main
    from rotorkit.validation import ClaimResult

    module = preset_module("rig")
    seen = {}

    def claim(study):
        seen.update(band=study.band, sensors=study.sensors, highpass=study.highpass_hz, signals=study.signals)
        return ClaimResult("stub claim", "reproduced", "nothing run")

    monkeypatch.setattr(module, "CLAIMS", (claim,))
    assert main(["validate", "rig", "--out", str(tmp_path)]) == 0
    assert seen["band"] == module.STUDY["band"] and seen["highpass"] == 2.0
    assert seen["signals"] == {"bending": "probe_v", "torsion": "delta_omega"}
    assert [s.name for s in seen["sensors"]] == [s.name for s in module.SENSORS]
    assert "stub claim" in (tmp_path / "claims.txt").read_text()


def test_run_and_list_cli_write_the_rig_outputs(tmp_path, capsys):
    from rotorkit.cli import main

    assert main(["list"]) == 0
    listed = capsys.readouterr().out
    assert "al31f:" in listed and "rig:" in listed
    out = tmp_path / "rig"
    assert main(["run", "rig", "--t-end", "0.5", "--sample-rate", "2000", "--out", str(out)]) == 0
    for name in ("signals.npz", "sensors.npz", "probe_orbit.png", "probe_h.png", "probe_v.png", "delta_omega.png",
                 "waterfall_probe_v.png", "waterfall_delta_omega.png", "spectrogram_delta_omega.png"):
        assert (out / name).stat().st_size > 1000, name
    with np.load(out / "sensors.npz") as data:
        assert data["delta_omega"].size == data["delta_omega_t"].size == int(0.5 * 12800) + 1
        assert data["probe_v"].size == int(0.5 * 2000) + 1
        assert "probe_v=m" in list(data["units"]) and "delta_omega=rad/s" in list(data["units"])
