"""Units at the boundary of every analysis: pint arrays, quantities and strings equal the SI call.

- A pint array in rpm gives the same result as the numbers converted by
  hand (``rpm * 2 pi / 60``) in rad/s: the unit is never stripped.
- Strings (``"3000 rpm"``, ``"100 g*mm"``) and scalar quantities are read
  the same way.
- A quantity of the wrong dimension raises UnitError naming the parameter.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Maneuver, Model, Rotor
from rotorkit.analysis.campbell import campbell
from rotorkit.analysis.critical_map import critical_speed_map
from rotorkit.analysis.frf import frequency_response
from rotorkit.analysis.linear_model import LinearModel
from rotorkit.analysis.modes import natural_frequencies
from rotorkit.analysis.static import static_deflection
from rotorkit.analysis.unbalance import Unbalance, unbalance_response
from rotorkit.analysis.whirl import orbit
from rotorkit.errors import UnitError
from rotorkit.units import registry, to_si_array

RPM = 2.0 * math.pi / 60.0


def Q_(value, unit):
    return registry().Quantity(value, unit)


def gyroscopic_rotor():
    """A rigid rotor on two isotropic supports with a gyroscopic disk: its Campbell lines split with speed."""
    m, Ip, Id, k, a = 10.0, 0.2, 0.12, 1e6, 0.2
    M = np.diag([m, m, Id, Id])
    K = np.diag([2 * k, 2 * k, 2 * k * a * a, 2 * k * a * a])
    G = np.zeros((4, 4))
    G[2, 3], G[3, 2] = Ip, -Ip
    return LinearModel(mass=M, damping=1.0 * np.eye(4), stiffness=K, gyroscopic=G,
                       coordinate_names=("x1", "y1", "thx1", "thy1"), rotor_speeds={"R": (0.0, 1.0)},
                       station_rotors={"1": "R"}, speed_parameter="R_speed")


@pytest.fixture(scope="module")
def small_system():
    model = Model([Rotor(name="R", stations=(1,), speed=0.0), Disk(station=1, mass=2.0, radius=0.1),
                   ElasticSupport(station=1, stiffness=2e4, damping=4.0), Maneuver.steady(gravity=9.81)])
    return model.compile(backend="python")


RPM_GRID = np.linspace(0.0, 15000.0, 7)


def test_to_si_array_never_strips_a_pint_array():
    np.testing.assert_allclose(to_si_array(Q_(RPM_GRID, "rpm"), "rad/s", "speeds"), RPM_GRID * RPM, rtol=1e-15)
    np.testing.assert_allclose(to_si_array(["0 rpm", "1000 rpm", Q_(2, "krad/s"), 5.0], "rad/s", "speeds"),
                               [0.0, 1000 * RPM, 2000.0, 5.0], rtol=1e-15)
    assert to_si_array("3000 rpm", "rad/s", "speed") == pytest.approx(3000 * RPM, rel=1e-15)


def test_campbell_in_rpm_equals_rad_per_s():
    model = gyroscopic_rotor()
    a = campbell(model, Q_(RPM_GRID, "rpm"), n_modes=4)
    b = campbell(model, RPM_GRID * RPM, n_modes=4)
    np.testing.assert_allclose(a.speeds, b.speeds, rtol=1e-15)
    np.testing.assert_allclose(a.frequencies, b.frequencies, rtol=1e-12)
    assert [c.speed for c in a.crossings] == pytest.approx([c.speed for c in b.crossings], rel=1e-10)
    strings = campbell(model, [f"{v:g} rpm" for v in RPM_GRID], n_modes=4)
    np.testing.assert_allclose(strings.frequencies, b.frequencies, rtol=1e-12)


def test_campbell_of_a_model_in_rpm(small_system):
    a = campbell(small_system.model, Q_([0.0, 500.0, 1500.0], "rpm"), n_modes=2, speed_parameter="R_speed",
                 backend="python")
    assert a.speeds.tolist() == pytest.approx([0.0, 500 * RPM, 1500 * RPM], rel=1e-15)
    damped = math.sqrt(2e4 / 2.0 - (4.0 / (2 * 2.0)) ** 2)  # sqrt(k/m - (c/2m)^2) rad/s, crossed by the 1x line
    assert a.critical_speeds()[0].speed == pytest.approx(damped, rel=1e-9)


def test_unbalance_response_in_rpm_and_g_mm():
    model = LinearModel(mass=2.0 * np.eye(2), damping=40.0 * np.eye(2), stiffness=2e4 * np.eye(2),
                        coordinate_names=("x1", "y1"), rotor_speeds={"R": (0.0, 1.0)})
    assert Unbalance(station=1, magnitude="100 g*mm").magnitude == pytest.approx(1e-4, rel=1e-14)
    assert Unbalance(station=1, magnitude=Q_(100, "g*mm"), angle="90 deg").angle == pytest.approx(math.pi / 2)
    rpm = np.linspace(0.0, 3000.0, 31)
    a = unbalance_response(model, [Unbalance(station=1, magnitude="100 g*mm", angle="40 deg")], Q_(rpm, "rpm"))
    b = unbalance_response(model, [Unbalance(station=1, magnitude=1e-4, angle=math.radians(40))], rpm * RPM)
    np.testing.assert_allclose(a.speeds, b.speeds, rtol=1e-15)
    np.testing.assert_allclose(a.response("x1"), b.response("x1"), rtol=1e-12, atol=1e-20)
    W = rpm * RPM  # the closed form of the Jeffcott rotor, from the converted speeds
    X = 1e-4 * W**2 * np.exp(1j * math.radians(40)) / (2e4 - 2.0 * W**2 + 40j * W)
    np.testing.assert_allclose(a.response("x1"), X, rtol=1e-12, atol=1e-20)


def test_frequency_response_in_rpm():
    model = gyroscopic_rotor()
    rpm = np.linspace(100.0, 6000.0, 13)
    a = frequency_response(model, Q_(rpm, "rpm"), speed="3000 rpm")
    b = frequency_response(model, rpm * RPM, speed=3000 * RPM)
    assert a.speed == pytest.approx(b.speed, rel=1e-15)
    np.testing.assert_allclose(a.frequencies, b.frequencies, rtol=1e-15)
    np.testing.assert_allclose(a.values, b.values, rtol=1e-12, atol=1e-20)


def test_critical_speed_map_in_rpm_and_n_per_mm():
    rotor = LinearModel(mass=2.0 * np.eye(2), damping=np.zeros((2, 2)), stiffness=np.zeros((2, 2)),
                        coordinate_names=("x1", "y1"), rotor_speeds={"R": (0.0, 1.0)}, station_rotors={"1": "R"})
    k = np.array([1e3, 1e4, 1e5])  # N/m: critical speed sqrt(k / m)
    a = critical_speed_map(rotor, [1], Q_(k / 1e3, "N/mm"), (Q_(0, "rpm"), Q_(4000, "rpm")), n_critical=1,
                           n_speeds=20)
    b = critical_speed_map(rotor, [1], k, (0.0, 4000 * RPM), n_critical=1, n_speeds=20)
    np.testing.assert_allclose(a.stiffnesses, k, rtol=1e-15)
    np.testing.assert_allclose(a.speeds, b.speeds, rtol=1e-12)
    np.testing.assert_allclose(a.speeds[:, 0], np.sqrt(k / 2.0), rtol=1e-8)
    c = critical_speed_map(rotor, [1], k, ("0 rpm", "4000 rpm"), n_critical=1, n_speeds=20)
    np.testing.assert_allclose(c.speeds, b.speeds, rtol=1e-12)


def test_static_deflection_and_modes_take_a_time_quantity(small_system):
    a = static_deflection(small_system, t=Q_(0.0, "ms"))
    assert a.deflection["y1"] == pytest.approx(-2.0 * 9.81 / 2e4, rel=1e-9)
    assert static_deflection(small_system, t="0 s").deflection == a.deflection
    modes = natural_frequencies(small_system, t="0 ms")
    assert modes.frequencies.tolist() == pytest.approx([100.0, 100.0], rel=1e-6)


def test_orbit_of_quantities_is_in_metres():
    X = Q_(np.array([3.0 + 0j, 1.0j]), "um")
    a = orbit(X, -1j * X)
    b = orbit(X.magnitude * 1e-6, -1j * X.magnitude * 1e-6)
    np.testing.assert_allclose(a.forward, b.forward, rtol=1e-15)
    np.testing.assert_allclose(a.forward, [3e-6, 1e-6], rtol=1e-15)


WRONG = [
    (lambda s: campbell(gyroscopic_rotor(), Q_([0.0, 10.0], "m")), "speeds"),
    (lambda s: campbell(gyroscopic_rotor(), ["0 rpm", "3 kg"]), "speeds"),
    (lambda s: campbell(gyroscopic_rotor(), Q_([0.0, 50.0], "Hz")), "Hz is ambiguous"),
    (lambda s: campbell(gyroscopic_rotor(), [0.0, 1.0], xtol="1 m"), "xtol"),
    (lambda s: campbell(gyroscopic_rotor(), [0.0, 1.0], t="1 m"), "t ="),
    (lambda s: unbalance_response(gyroscopic_rotor(), [(1, 1e-4, 0.0)], Q_([1.0, 2.0], "N")), "speeds"),
    (lambda s: Unbalance(station=1, magnitude="100 g"), "Unbalance magnitude"),
    (lambda s: Unbalance(station=1, magnitude=1e-4, angle="1 m"), "Unbalance angle"),
    (lambda s: frequency_response(gyroscopic_rotor(), Q_([1.0], "m/s")), "frequencies"),
    (lambda s: frequency_response(gyroscopic_rotor(), [1.0], speed="3000 N"), "speed"),
    (lambda s: critical_speed_map(gyroscopic_rotor(), [1], Q_([1e5], "N"), (0.0, 10.0)), "stiffnesses"),
    (lambda s: critical_speed_map(gyroscopic_rotor(), [1], [1e5], ("0 m", "1 m")), "speed_range"),
    (lambda s: static_deflection(s, t="1 m"), "t ="),
    (lambda s: natural_frequencies(s, t=Q_(1.0, "kg")), "t ="),
    (lambda s: orbit(Q_([1.0], "m"), Q_([1.0], "s")), "one dimension"),
]


@pytest.mark.parametrize("call, match", WRONG)
def test_wrong_dimension_raises_unit_error(call, match, small_system):
    with pytest.raises(UnitError, match=match):
        call(small_system)


def test_linear_model_speeds_take_units():
    """LinearModel.modes/matrices/state_matrix read '3000 rpm' and pint quantities as rad/s; a length is refused."""
    import numpy as np

    import rotorkit as rk
    from rotorkit.errors import UnitError
    from rotorkit.units import registry

    lin = rk.LinearModel(mass=np.eye(2), damping=0.1 * np.eye(2), stiffness=np.diag([4.0, 9.0]),
                         gyroscopic=np.array([[0.0, 1.0], [-1.0, 0.0]]), coordinate_names=("x1", "y1"))
    w = 3000 * np.pi / 30
    expected = lin.state_matrix(w)
    assert np.allclose(lin.state_matrix("3000 rpm"), expected, rtol=1e-14, atol=0)
    assert np.allclose(lin.state_matrix(registry().Quantity(3000.0, "rpm")), expected, rtol=1e-14, atol=0)
    assert np.allclose(lin.modes("3000 rpm").frequencies, lin.modes(w).frequencies, rtol=1e-12)
    with pytest.raises(UnitError):
        lin.matrices("3000 m")
