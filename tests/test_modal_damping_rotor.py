"""``Rotor(damping=ModalDamping(ratios=...))``: modal damping as a damping spec of the rotor.

Closed forms, on a disk of mass ``m`` on a linear bearing (no tilt, no
gyroscopics): the undamped modes are ``x`` and ``y`` with ``w = sqrt(k / m)``,
and modal damping ``zeta`` on a mode is the viscous ``c = 2 zeta m w``, so

- each mode's eigenvalue has damping ratio ``zeta`` exactly, at any speed
  (nothing couples the modes);
- the unbalance response at resonance (``W = w``) of an isotropic rotor is
  ``U W^2 / (c W) = U w^2 / (2 zeta k) = e / (2 zeta)`` (``U = m e``);
- the receptance at resonance is ``1 / (c w) = 1 / (2 zeta k)``;
- the static deflection ``-m g / k`` does not see the damping.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rotorkit as rk
from rotorkit import Disk, ElasticSupport, LinearBearing, ModalDamping, Model, Rotor
from rotorkit.errors import ParameterError, TopologyError
from rotorkit.linear.modes import natural_frequencies

M, KX, KY = 2.0, 2e4, 8e4  # kg, N/m: modes at 100 and 200 rad/s


def disk_on_bearing(damping, kxx=KX, kyy=KY, speed=0.0):
    return Model([Rotor(name="R", stations=(1,), speed=speed, damping=damping),
                  Disk(station=1, mass=M, radius=0.1),
                  LinearBearing(station=1, kxx=kxx, kyy=kyy)])


@pytest.mark.parametrize("spec, expected", [
    (ModalDamping(ratios=(0.01, 0.03)), (0.01, 0.03)),
    (ModalDamping(ratios=(0.02,), remaining=0.05), (0.02, 0.05)),
])
def test_each_mode_has_its_ratio(spec, expected):
    model = disk_on_bearing(spec)
    w = np.sqrt(np.array([KX, KY]) / M)
    linear = rk.linear_model(model).modes(0.0)
    np.testing.assert_allclose(linear.frequencies, w, rtol=1e-10)
    np.testing.assert_allclose(linear.damping_ratios, expected, rtol=1e-9)
    compiled = natural_frequencies(model.compile(backend="python"), equilibrium=False)
    np.testing.assert_allclose(compiled.frequencies, w, rtol=1e-6)
    np.testing.assert_allclose(compiled.damping_ratios, expected, rtol=1e-6)


def test_campbell_has_the_ratios_at_every_speed():
    model = disk_on_bearing(ModalDamping(ratios=(0.01, 0.03)), speed=50.0)
    result = rk.campbell(model, [0.0, 150.0, 300.0], n_modes=2)
    np.testing.assert_allclose(result.damping_ratios, [[0.01, 0.03]] * 3, rtol=1e-9)


def test_without_the_spec_there_is_no_damping():
    modes = rk.linear_model(disk_on_bearing(None)).modes(0.0)
    np.testing.assert_allclose(modes.damping_ratios, 0.0, atol=1e-12)


def test_unbalance_response_at_resonance():
    zeta, e = 0.02, 1e-4
    model = disk_on_bearing(ModalDamping(ratios=(zeta, zeta)), kxx=KX, kyy=KX)
    wn = math.sqrt(KX / M)
    result = rk.unbalance_response(rk.linear_model(model), [rk.Unbalance(station=1, magnitude=M * e)], [wn])
    expected = M * e * wn**2 / (2 * zeta * KX)  # = e / (2 zeta)
    assert result.amplitude("x1")[0] == pytest.approx(expected, rel=1e-9)
    assert result.amplitude("y1")[0] == pytest.approx(expected, rel=1e-9)


def test_receptance_at_resonance():
    zeta = 0.05
    model = disk_on_bearing(ModalDamping(ratios=(zeta, zeta)))
    w = math.sqrt(KX / M), math.sqrt(KY / M)
    frf = rk.frequency_response(rk.linear_model(model), list(w))
    values = frf.values  # (frequency, output, input)
    assert abs(values[0, 0, 0]) == pytest.approx(1 / (2 * zeta * KX), rel=1e-9)
    assert abs(values[1, 1, 1]) == pytest.approx(1 / (2 * zeta * KY), rel=1e-9)


def test_static_deflection_is_unaffected():
    model = Model([Rotor(name="R", stations=(1,), speed=0.0, damping=ModalDamping(ratios=(0.3, 0.3))),
                   Disk(station=1, mass=M, radius=0.1), ElasticSupport(station=1, stiffness=KX),
                   rk.Maneuver(gravity=9.81)])
    s = rk.static_deflection(model)
    assert s.deflection["y1"] == pytest.approx(-M * 9.81 / KX, rel=1e-9)


def test_ratios_are_not_parameters_and_changing_them_keeps_the_structure():
    a, b = disk_on_bearing(ModalDamping(ratios=(0.01,))), disk_on_bearing(ModalDamping(ratios=(0.2, 0.1)))
    assert a.structure_key == b.structure_key
    assert not any("damping" in name for name in a.parameters)
    np.testing.assert_allclose(rk.linear_model(b).modes(0.0).damping_ratios, (0.2, 0.1), rtol=1e-9)
    np.testing.assert_allclose(rk.linear_model(a).modes(0.0).damping_ratios, (0.01, 0.0), atol=1e-12, rtol=1e-9)


def test_model_file_round_trip(tmp_path):
    model = disk_on_bearing(ModalDamping(ratios=(0.01, 0.03), remaining=0.002))
    path = model.save(tmp_path / "m.toml")
    loaded = rk.load_model(path)
    assert loaded.rotors["R"].damping == ModalDamping(ratios=(0.01, 0.03), remaining=0.002)
    assert loaded.structure_key == model.structure_key
    np.testing.assert_allclose(rk.linear_model(loaded).modes(0.0).damping_ratios, (0.01, 0.03), rtol=1e-9)


def test_bad_ratio_in_a_model_file(tmp_path):
    path = disk_on_bearing(ModalDamping(ratios=(0.01,))).save(tmp_path / "m.toml")
    path.write_text(path.read_text().replace("ratios = [0.01]", "ratios = [1.5]"))
    with pytest.raises(ParameterError, match=r"ratios\[0\] = 1.5"):
        rk.load_model(path)


@pytest.mark.parametrize("kwargs, match", [
    (dict(ratios=()), r"ModalDamping.ratios = \(\): expected a non-empty sequence"),
    (dict(ratios="0.02"), r"ModalDamping.ratios = '0.02'"),
    (dict(ratios=(0.02, -0.1)), r"ModalDamping.ratios\[1\] = -0.1: expected a damping ratio in \[0, 1\)"),
    (dict(ratios=(0.02, 1.0)), r"ratios\[1\] = 1.0"),
    (dict(ratios=(float("nan"),)), r"ratios\[0\] = nan"),
    (dict(ratios=(float("inf"),)), r"ratios\[0\] = inf"),
    (dict(ratios=(True,)), r"ratios\[0\] = True"),
    (dict(ratios=("0.1",)), r"ratios\[0\] = '0.1'"),
    (dict(ratios=(0.1,), remaining=1.5), r"ModalDamping.remaining = 1.5"),
    (dict(ratios=(0.1,), remaining=None), r"ModalDamping.remaining = None"),
])
def test_bad_input(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        ModalDamping(**kwargs)


def test_rotor_refuses_other_damping_objects():
    with pytest.raises(ParameterError, match=r"damping = 0.02: expected Rayleigh\(alpha, beta\), ModalDamping"):
        Rotor(name="R", stations=(1,), speed=0.0, damping=0.02)


def test_one_rotor_only():
    spec = ModalDamping(ratios=(0.01,))
    with pytest.raises(TopologyError, match=r"Rotors \['A', 'B'\] each have ModalDamping"):
        Model([Rotor(name="A", stations=(1,), speed=0.0, damping=spec),
               Rotor(name="B", stations=(2,), speed=0.0, damping=spec),
               Disk(station=1, mass=1.0, radius=0.1), Disk(station=2, mass=1.0, radius=0.1),
               ElasticSupport(station=1, stiffness=1e4), ElasticSupport(station=2, stiffness=1e4)])


def test_simulate_runs_it():
    """Time runs carry ``-C q'`` (tests/test_modal_damping_time.py checks the decay); the x mode alone decays."""
    zeta, w = 0.05, math.sqrt(KX / M)
    system = disk_on_bearing(ModalDamping(ratios=(zeta, 0.0))).compile(backend="python")
    period = 2 * math.pi / (w * math.sqrt(1 - zeta**2))
    result = rk.simulate(system, (0.0, period), y0=system.initial_state(x1=1e-3, y1=1e-3), sample_times=[period],
                         rtol=1e-10, atol=1e-15, engine="scipy")
    # after one damped period: x1 = x0 exp(-zeta w T) exactly (starting at rest); y1 undamped is back to y0
    assert result.y[system.state_index("x1"), -1] == pytest.approx(1e-3 * math.exp(-zeta * w * period), rel=1e-6)
    assert result.y[system.state_index("y1"), -1] == pytest.approx(1e-3 * math.cos(math.sqrt(KY / M) * period),
                                                                    rel=1e-6)


def test_harmonic_balance_refuses_with_a_named_error():
    from rotorkit.periodic.hb import HarmonicBalance

    system = disk_on_bearing(ModalDamping(ratios=(0.01,))).compile(backend="python")
    with pytest.raises(ParameterError, match=r"HarmonicBalance: .*ModalDamping.*Use Rayleigh"):
        HarmonicBalance(system, speed_parameter="R_speed", harmonics=1)


@pytest.mark.slow  # ~20 s: derives and compiles a beam model
def test_compiled_and_linear_paths_agree_at_speed():
    """With gyroscopics (a beam at 300 rad/s) the ratios move off the given ones; both paths see the same C."""
    model = Model([Rotor(name="R", stations=(1, 2), speed=300.0,
                         damping=ModalDamping(ratios=(0.01, 0.02, 0.05, 0.03), remaining=0.004)),
                   rk.BeamSegment(start=1, end=2, length=0.8, outer_diameter=0.04, material=rk.Material.steel(),
                                  elements=3),
                   LinearBearing(station=1, kxx=2e7, kyy=5e7), LinearBearing(station=2, kxx=2e7, kyy=5e7)])
    linear = rk.linear_model(model).modes(300.0)
    compiled = natural_frequencies(model.compile(backend="python"), equilibrium=False)
    np.testing.assert_allclose(compiled.frequencies[:6], linear.frequencies[:6], rtol=1e-6)
    np.testing.assert_allclose(compiled.damping_ratios[:6], linear.damping_ratios[:6], rtol=1e-5)
    assert abs(linear.damping_ratios[0] - 0.01) > 1e-7  # the speed did mix the modes
