"""General linear bearings against closed forms.

- Jeffcott rotor (mass m) on an anisotropic bearing: two natural frequencies
  ``sqrt(kxx/m)`` and ``sqrt(kyy/m)``.
- Cross-coupled stiffness ``kxy = q = -kyx`` with direct ``k`` and damping
  ``c``: with ``z = x + i y`` the equation is ``m z'' + c z' + (k - i q) z = 0``;
  a root crosses the imaginary axis at ``lambda = i wn`` exactly when
  ``q = c wn``: stable below, unstable above (eigenvalues and a time run).
- Two rotors each on a ground spring ``k1``, joined by an inter-shaft bearing
  ``kb``: in-phase ``sqrt(k1/m)`` and anti-phase ``sqrt((k1 + 2 kb)/m)``.
- Tabulated coefficients: linear between the table speeds, end values held.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, LumpedMass, Model, ParameterError, Rotor, TopologyError, simulate
from rotorkit.analysis.modes import linearize
from rotorkit.elements import LinearBearing, SpeedProfile

M = 2.0


def jeffcott(bearing, speed=0.0):
    return Model([Rotor(name="R", stations=(1,), speed=speed), LumpedMass(station=1, mass=M), bearing])


def eigenvalues(model, t=0.0):
    system = model.compile(backend="python")
    A = linearize(system, np.zeros(len(system.coordinate_names)), t=t, method="analytic")[0]
    return np.linalg.eigvals(A)


def test_anisotropic_bearing_two_natural_frequencies():
    lam = eigenvalues(jeffcott(LinearBearing(station=1, kxx=2e4, kyy=0.8e4)))
    np.testing.assert_allclose(np.sort(np.abs(lam.imag)), np.sort([100.0, 100.0, math.sqrt(0.4e4), math.sqrt(0.4e4)]),
                               rtol=1e-10)
    assert np.max(np.abs(lam.real)) < 1e-9


def test_symmetric_part_is_visible_in_K_and_C_and_skew_part_is_a_load():
    model = jeffcott(LinearBearing(station=1, kxx=2e4, kyy=1e4, kxy=3e3, kyx=-1e3, cxx=5.0, cyy=6.0, cxy=2.0))
    eom = model.equations()
    K = eom.stiffness.subs({s: model.parameters[s.name] for s in eom.parameters})
    np.testing.assert_allclose(np.array(K, dtype=float), [[2e4, 1e3], [1e3, 1e4]])
    C = eom.damping.subs({s: model.parameters[s.name] for s in eom.parameters})
    np.testing.assert_allclose(np.array(C, dtype=float), [[5.0, 1.0], [1.0, 6.0]])
    assert "linearbearing1" in eom.forces
    # the total force is -K d - C d' with the full (unsymmetric) matrices
    system = model.compile(backend="python")
    q, u = np.array([1e-4, -2e-4]), np.array([0.3, 0.1])
    acc = system.rhs(0.0, np.concatenate([q, u]))[2:]
    Kf, Cf = np.array([[2e4, 3e3], [-1e3, 1e4]]), np.array([[5.0, 2.0], [0.0, 6.0]])
    np.testing.assert_allclose(M * acc, -Kf @ q - Cf @ u, rtol=1e-12)


@pytest.mark.parametrize("factor, stable", [(0.8, True), (1.25, False)])
def test_cross_coupled_stability_threshold_q_equals_c_wn(factor, stable):
    k, c = 2e4, 8.0
    wn = math.sqrt(k / M)
    q = factor * c * wn
    bearing = LinearBearing(station=1, kxx=k, kyy=k, kxy=q, kyx=-q, cxx=c, cyy=c)
    lam = eigenvalues(jeffcott(bearing))
    # closed form: m s^2 + c s + k -/+ i q = 0
    exact = np.concatenate([np.roots([M, c, k - 1j * q]), np.roots([M, c, k + 1j * q])])
    np.testing.assert_allclose(np.sort_complex(lam), np.sort_complex(exact), rtol=1e-9)
    assert (np.max(lam.real) < 0) == stable
    # a free run grows or decays at the rate of the least stable root
    system = jeffcott(bearing).compile(backend="python")
    result = simulate(system, (0.0, 3.0), y0=system.initial_state(x1=1e-4), rtol=1e-10, atol=1e-16,
                      sample_rate=2000.0)
    r = np.hypot(result["x1"], result["y1"])
    # after 1.5 s the other root (real part -c/m minus this one) has died out
    early, late = np.max(r[(result.t > 1.5) & (result.t < 1.8)]), np.max(r[result.t > 2.7])
    rate = np.log(late / early) / 1.2
    assert rate == pytest.approx(np.max(lam.real), abs=0.05 * abs(np.max(lam.real)) + 0.02)
    assert (late < early) == stable


def test_cross_coupled_exactly_at_threshold_is_marginal():
    k, c = 2e4, 8.0
    q = c * math.sqrt(k / M)
    lam = eigenvalues(jeffcott(LinearBearing(station=1, kxx=k, kyy=k, kxy=q, kyx=-q, cxx=c, cyy=c)))
    assert abs(np.max(lam.real)) < 1e-8


def test_inter_shaft_bearing_in_phase_and_anti_phase_frequencies():
    k1, kb = 2e4, 1e4
    model = Model([
        Rotor(name="A", stations=(1,), speed=100.0), Rotor(name="B", stations=(2,), speed=150.0),
        LumpedMass(station=1, mass=M), LumpedMass(station=2, mass=M),
        ElasticSupport(station=1, stiffness=k1), ElasticSupport(station=2, stiffness=k1),
        LinearBearing(station=1, other_station=2, kxx=kb, kyy=kb),
    ])
    lam = eigenvalues(model)
    w = np.sort(np.abs(lam.imag))
    expected = np.sort(np.repeat([math.sqrt(k1 / M), math.sqrt((k1 + 2 * kb) / M)], 4))
    np.testing.assert_allclose(w, expected, rtol=1e-10)


def test_inter_shaft_bearing_alone_supports_a_rotor():
    model = Model([
        Rotor(name="A", stations=(1,), speed=100.0), Rotor(name="B", stations=(2,), speed=150.0),
        LumpedMass(station=1, mass=M), LumpedMass(station=2, mass=M),
        LinearBearing(station=1, kxx=1e4, kyy=1e4), LinearBearing(station=1, other_station=2, kxx=1e4, kyy=1e4),
    ])
    assert model.coordinate_names == ("x1", "x2", "y1", "y2")
    with pytest.raises(TopologyError, match="no support"):
        Model([Rotor(name="A", stations=(1,), speed=1.0), Rotor(name="B", stations=(2,), speed=1.0),
               LumpedMass(station=1, mass=M), LumpedMass(station=2, mass=M),
               LinearBearing(station=1, kxx=1e4, kyy=1e4)])


def test_tabulated_coefficients_interpolate_and_hold_end_values():
    speeds, kxx, kyy, kxy = [100.0, 200.0, 400.0], [1e4, 3e4, 2e4], [2e4, 2e4, 4e4], [0.0, 1e3, 4e3]
    bearing = LinearBearing.tabulated(station=1, speeds=speeds, kxx=kxx, kyy=kyy, kxy=kxy)

    def stiffness_at(speed):
        system = jeffcott(bearing, speed=speed).compile(backend="python")
        y = np.zeros(4)
        cols = []
        for j in range(2):
            y[:] = 0.0
            y[j] = 1e-3
            cols.append(-M * system.rhs(0.0, y)[2:] / 1e-3)
        return np.array(cols).T

    for speed in (0.0, 100.0, 150.0, 300.0, 400.0, 1000.0):
        expected = np.array([[np.interp(speed, speeds, kxx), np.interp(speed, speeds, kxy)],
                             [0.0, np.interp(speed, speeds, kyy)]])
        np.testing.assert_allclose(stiffness_at(speed), expected, rtol=1e-10, atol=1e-9)


def test_tabulated_coefficients_follow_a_speed_profile_in_time():
    bearing = LinearBearing.tabulated(station=1, speeds=[0.0, 100.0], kxx=[1e4, 3e4], kyy=[1e4, 3e4])
    model = jeffcott(bearing, speed=SpeedProfile.table(times=[0.0, 1.0], speeds=[0.0, 100.0]))
    system = model.compile(backend="python")
    y = np.array([1e-3, 0.0, 0.0, 0.0])
    assert -M * system.rhs(0.5, y)[2] / 1e-3 == pytest.approx(2e4, rel=1e-12)
    changed = system.with_parameters(linearbearing1_kxx1=5e4)
    assert -M * changed.rhs(0.5, y)[2] / 1e-3 == pytest.approx(3e4, rel=1e-12)


def test_bearing_on_a_spinning_rotor_keeps_unbalance_response():
    """Anisotropic bearing, unbalance at speed W: x and y steady amplitudes m e W^2 / |k - m W^2|."""
    kxx, kyy, e, W = 2e4, 0.8e4, 1e-4, 50.0
    model = Model([Rotor(name="R", stations=(1,), speed=W), Disk(station=1, mass=M, radius=0.1, eccentricity=e),
                   LinearBearing(station=1, kxx=kxx, kyy=kyy, cxx=4.0, cyy=4.0)])
    system = model.compile(backend="python")
    result = simulate(system, (0.0, 12.0), rtol=1e-9, atol=1e-14, sample_rate=1000.0)
    tail = result.t > 11.0
    for name, k in (("x1", kxx), ("y1", kyy)):
        c, w2 = 4.0, W * W
        amp = M * e * w2 / math.hypot(k - M * w2, c * W)
        assert np.max(np.abs(result[name][tail])) == pytest.approx(amp, rel=2e-3)


@pytest.mark.parametrize("kwargs, match", [
    (dict(station=1, kxx=-1.0, kyy=1.0), "kxx"),
    (dict(station=1, kxx=1.0, kyy=1.0, cyy=-2.0), "cyy"),
    (dict(station=1, kyy=1.0), "kxx is required"),
    (dict(station=1, other_station=1, kxx=1.0, kyy=1.0), "other_station"),
    (dict(station=1, speeds=[0.0, 1.0], kxx=[1.0, 2.0], kyy=[1.0]), "speeds has 2 entries but kyy has 1"),
    (dict(station=1, speeds=[0.0, 0.0], kxx=[1.0, 2.0], kyy=[1.0, 1.0]), "not strictly increasing"),
    (dict(station=1, speeds=[0.0, 1.0], kxx=[1.0, -2.0], kyy=[1.0, 1.0]), r"kxx\[1\] = -2.0 is negative"),
    (dict(station=1, speeds=[0.0, 1.0], kxx=[1.0, 2.0]), "kyy is required"),
])
def test_bad_input_raises_named_errors(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        LinearBearing(**kwargs)


def test_unknown_station_is_a_topology_error():
    with pytest.raises(TopologyError, match="station 5"):
        jeffcott(LinearBearing(station=1, other_station=5, kxx=1.0, kyy=1.0))


def test_pedestal_mass_two_dof_frequencies():
    """Journal m1 on a bearing k1 to a pedestal m2 on k2 to ground (the pedestal as a non-spinning rotor).

    det([[k1 - m1 w^2, -k1], [-k1, k1 + k2 - m2 w^2]]) = 0 gives
    w^2 = (b -/+ sqrt(b^2 - 4 m1 m2 k1 k2)) / (2 m1 m2), b = m1 (k1 + k2) + m2 k1, in x (kxx) and y (kyy).
    """
    m1, m2, k2 = 2.0, 5.0, 3e4
    kxx, kyy = 2e4, 1e4
    model = Model([
        Rotor(name="R", stations=(1,), speed=200.0), Rotor(name="pedestal", stations=("p",), speed=0.0),
        LumpedMass(station=1, mass=m1), LumpedMass(station="p", mass=m2),
        LinearBearing(station=1, other_station="p", kxx=kxx, kyy=kyy),
        ElasticSupport(station="p", stiffness=k2),
    ])
    expected = []
    for k1 in (kxx, kyy):
        b = m1 * (k1 + k2) + m2 * k1
        root = math.sqrt(b * b - 4 * m1 * m2 * k1 * k2)
        expected += [math.sqrt((b - root) / (2 * m1 * m2)), math.sqrt((b + root) / (2 * m1 * m2))]
    w = np.sort(np.abs(eigenvalues(model).imag))
    np.testing.assert_allclose(w, np.sort(np.repeat(expected, 2)), rtol=1e-10)
