"""Modes and Campbell diagrams of finite-element rotors (BeamSegment, Disk, LinearBearing) against closed forms.

- Overhung disk (mass m, polar and diametral inertia Ip, Id) at the free end
  of a practically massless Euler-Bernoulli shaft on two stiff bearings: the
  shaft's stiffness condensed to the disk, ``[[K11, K12], [K12, K22]]``, is
  derived here from the textbook beam element and the bearing springs
  (static condensation, independent of rotorkit's beam). A mode whirling
  at ``w`` (forward ``w > 0``, backward ``w < 0``) solves
  ``(K11 - m w^2)(K22 - Id w^2 + Ip W w) = K12^2``; the critical speeds
  (``w = +-W``) solve it with ``Id -+ Ip``.
- Rigid rotor (a very stiff beam with a central disk) on two anisotropic
  bearings ``kxx != kyy`` at ``+-l`` from the centre: cylindrical modes
  ``sqrt(2 kxx / m)``, ``sqrt(2 kyy / m)`` (planar, speed-independent) and
  conical modes from ``(kt_x - Id w^2)(kt_y - Id w^2) = (Ip W w)^2`` with
  ``kt_x = 2 kyy l^2``, ``kt_y = 2 kxx l^2``; the rigid body's ``m``, ``Id``,
  ``Ip`` are those of a uniform cylinder plus the disk.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorkit import Model, Rotor
from rotorkit.analysis.campbell import campbell
from rotorkit.analysis.linear_matrices import linear_matrices, station_positions
from rotorkit.elements import BeamSegment, Disk, LinearBearing

E, D = 2.1e11, 0.03
EI = E * math.pi * D**4 / 64
A_, B_ = 0.3, 0.2  # bearing span, overhang (m)
KB = 1e9  # stiff bearings (N/m)
MD, ID = 5.0, 0.05


def overhung(ip, speed=0.0):
    beam = dict(outer_diameter=D, density=1e-3, youngs_modulus=E, shear_modulus=E / 2.6, theory="euler-bernoulli")
    return Model([Rotor(name="R", stations=(1, 2, 3), speed=speed),
                  BeamSegment(start=1, end=2, length=A_, **beam), BeamSegment(start=2, end=3, length=B_, **beam),
                  LinearBearing(station=1, kxx=KB, kyy=KB), LinearBearing(station=2, kxx=KB, kyy=KB),
                  Disk(station=3, mass=MD, polar_inertia=ip, diametral_inertia=ID)], name="overhung")


def _beam_element(length):
    l = length
    return EI / l**3 * np.array([[12, 6 * l, -12, 6 * l], [6 * l, 4 * l * l, -6 * l, 2 * l * l],
                                 [-12, -6 * l, 12, -6 * l], [6 * l, 2 * l * l, -6 * l, 4 * l * l]])


def _disk_stiffness():
    """One bending plane (w, beta) at the three nodes, bearings on w1 and w2, condensed to the disk."""
    K = np.zeros((6, 6))
    K[0:4, 0:4] += _beam_element(A_)
    K[2:6, 2:6] += _beam_element(B_)
    K[0, 0] += KB
    K[2, 2] += KB
    keep, drop = [4, 5], [0, 1, 2, 3]
    return K[np.ix_(keep, keep)] - K[np.ix_(keep, drop)] @ np.linalg.solve(K[np.ix_(drop, drop)],
                                                                          K[np.ix_(drop, keep)])


(K11, K12), (_, K22) = _disk_stiffness()


def overhung_whirl(speed, ip):
    """Whirl frequencies w: forward > 0, backward < 0."""
    a = np.polynomial.Polynomial([K11, 0.0, -MD])
    b = np.polynomial.Polynomial([K22, ip * speed, -ID])
    roots = (a * b - K12**2).roots()
    return np.sort(roots.real[np.abs(roots.imag) < 1e-9])


def overhung_critical(inertia):
    roots = np.roots([MD * inertia, -(K11 * inertia + MD * K22), K11 * K22 - K12**2])
    return np.sort(np.sqrt(roots[(roots.real > 0) & (np.abs(roots.imag) < 1e-9)].real))


@pytest.fixture(scope="module")
def overhung_campbell():
    return campbell(overhung(0.02), np.linspace(0.0, 2500.0, 26), n_modes=4, speed_parameter="R_speed")


def test_fe_overhung_disk_modes_and_whirl_against_the_closed_form():
    from rotorkit.analysis.linear_model import linear_model

    ip = 0.08
    linear = linear_model(overhung(ip).compile(backend="python"), speed=0.0)
    assert linear.station_positions == {"1": 0.0, "2": A_, "3": A_ + B_}
    for speed in (0.0, 500.0, 1500.0):
        modes = linear.modes(speed)
        w = overhung_whirl(speed, ip)
        kinds = np.array(modes.whirl[:4])
        np.testing.assert_allclose(modes.frequencies[:4], np.sort(np.abs(w)), rtol=1e-7)
        if speed > 0:
            np.testing.assert_allclose(np.sort(modes.frequencies[:4][kinds == "forward"]), w[w > 0], rtol=1e-7)
            np.testing.assert_allclose(np.sort(modes.frequencies[:4][kinds == "backward"]), np.sort(-w[w < 0]),
                                       rtol=1e-7)
            for mode in range(1, 5):
                # the stations at the stiff bearings barely move but tilt: their whirl is the slope's, the mode's
                stations = modes.station_whirl(mode)
                assert stations["1"] == stations["2"] == stations["3"] == kinds[mode - 1]
                assert modes.slope_orbits(mode)["2"].direction == kinds[mode - 1]


def test_fe_overhung_disk_campbell_critical_speeds(overhung_campbell):
    ip = 0.02
    diagram = overhung_campbell
    fwd = sorted(c.speed for c in diagram.critical_speeds() if c.whirl == "forward")
    bwd = sorted(c.speed for c in diagram.critical_speeds() if c.whirl == "backward")
    expected_fwd = overhung_critical(ID - ip)
    expected_bwd = overhung_critical(ID + ip)
    expected_fwd = expected_fwd[expected_fwd < 2500.0]
    expected_bwd = expected_bwd[expected_bwd < 2500.0]
    assert len(fwd) == len(expected_fwd) >= 1 and len(bwd) == len(expected_bwd) >= 2
    np.testing.assert_allclose(fwd, expected_fwd, rtol=1e-7)
    np.testing.assert_allclose(bwd, expected_bwd, rtol=1e-7)
    for i, speed in enumerate(diagram.speeds):
        w = np.abs(overhung_whirl(speed, ip))
        for k in range(diagram.n_modes):
            assert np.min(np.abs(w - diagram.frequencies[i, k])) < 1e-7 * np.max(w)


# ---------------------------------------------------------------------------
# Rigid rotor on anisotropic bearings
# ---------------------------------------------------------------------------

L_R, D_R, RHO = 0.5, 0.05, 7800.0
KXX, KYY = 2e6, 1e6
M_DISK, IP_DISK, ID_DISK = 10.0, 0.1, 0.05
_MB = RHO * math.pi * D_R**2 / 4 * L_R
MASS = M_DISK + _MB
IP_R = IP_DISK + _MB * D_R**2 / 8  # uniform cylinder: m r^2 / 2
ID_R = ID_DISK + _MB * L_R**2 / 12 + _MB * D_R**2 / 16  # m L^2 / 12 + m r^2 / 4


def rigid_rotor():
    beam = dict(outer_diameter=D_R, density=RHO, youngs_modulus=2.1e15, shear_modulus=2.1e15 / 2.6,
                theory="euler-bernoulli")
    return Model([Rotor(name="R", stations=(1, 2, 3), speed=0.0),
                  BeamSegment(start=1, end=2, length=L_R / 2, **beam),
                  BeamSegment(start=2, end=3, length=L_R / 2, **beam),
                  Disk(station=2, mass=M_DISK, polar_inertia=IP_DISK, diametral_inertia=ID_DISK),
                  LinearBearing(station=1, kxx=KXX, kyy=KYY), LinearBearing(station=3, kxx=KXX, kyy=KYY)],
                 name="rigid_rotor")


def conical(speed):
    """The two conical whirl frequencies (rad/s), lower (backward) first."""
    l = L_R / 2
    ktx, kty = 2 * KYY * l**2, 2 * KXX * l**2
    a, b, c = ID_R**2, -(ID_R * (ktx + kty) + (IP_R * speed) ** 2), ktx * kty
    return np.sqrt(np.sort(np.roots([a, b, c]).real))


def test_rigid_rotor_on_anisotropic_bearings_modes_and_campbell():
    model = rigid_rotor()
    cylindrical = np.sqrt([2 * KYY / MASS, 2 * KXX / MASS])
    diagram = campbell(model, np.linspace(0.0, 1500.0, 16), n_modes=4, speed_parameter="R_speed")
    for i, speed in enumerate(diagram.speeds):
        expected = np.sort(np.concatenate([cylindrical, conical(speed)]))
        # the beam is 1e5 times stiffer than the bearings, not rigid: frequencies ~1e-5 low
        np.testing.assert_allclose(np.sort(diagram.frequencies[i]), expected, rtol=2e-5)
    # the cylindrical modes are planar (one bearing direction each); the conical ones whirl backward, forward
    low, high = conical(1500.0)

    def whirl_at(frequency):
        return diagram.whirl[-1][int(np.argmin(np.abs(diagram.frequencies[-1] - frequency)))]

    assert [whirl_at(f) for f in (*cylindrical, low, high)] == ["linear", "linear", "backward", "forward"]
    # critical speeds: both cylindrical ones, and the backward conical one (W = w on the lower branch)
    located = sorted(c.speed for c in diagram.critical_speeds())
    l = L_R / 2
    ktx, kty = 2 * KYY * l**2, 2 * KXX * l**2
    # conical critical speeds: w = W in the frequency equation, (Id^2 - Ip^2) W^4 - Id (ktx + kty) W^2 + ktx kty = 0
    roots = np.roots([(ID_R**2 - IP_R**2), -ID_R * (ktx + kty), ktx * kty])
    crit_conical = np.sort(np.sqrt(roots[(roots.real > 0) & (np.abs(roots.imag) < 1e-9)].real))
    expected = np.sort(np.concatenate([cylindrical, crit_conical[crit_conical < 1500.0]]))
    np.testing.assert_allclose(located, expected, rtol=2e-5)


def test_linear_matrices_of_the_rigid_rotor_hold_its_mass_and_bearings():
    model = rigid_rotor()
    M, C, K = linear_matrices(model)
    names = model.coordinate_names
    x = np.array([1.0 if n.startswith("x") else 0.0 for n in names])  # rigid translation in x
    y = np.array([1.0 if n.startswith("y") else 0.0 for n in names])
    assert x @ (M @ x) == pytest.approx(MASS, rel=1e-12)
    assert x @ (K @ x) == pytest.approx(2 * KXX, rel=1e-9)  # a rigid motion does not bend the beam
    assert y @ (K @ y) == pytest.approx(2 * KYY, rel=1e-9)
    assert C.count_nonzero() == 0  # at rest: no damping, no gyroscopic term
    assert station_positions(model) == {"1": 0.0, "2": L_R / 2, "3": L_R}
