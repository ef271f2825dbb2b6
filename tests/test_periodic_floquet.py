"""The monodromy matrix by exponential collocation (rotorkit.periodic.floquet) against closed forms and DOP853.

- ``phi`` functions: ``phi_0 = e^z``, ``phi_1 = (e^z - 1) / z``, ``phi_2 = (e^z - 1 - z) / z^2``, ``phi_j(0) = 1/j!``.
- A linear rotor (anisotropic, cross-coupled bearing): the multipliers are ``exp(lambda T)`` of the eigenvalues of
  its state matrix (the collocation has no nonlinear part then: the linear propagator alone, exact).
- A partial rub (contact over part of the period: the Jacobian jumps twice a period): the switch instants are roots
  of the switch function, and the multipliers equal those of the full variational equations integrated by DOP853
  (rtol 1e-12) and do not change when the steps double.
- A chain of 8 disks (16 coordinates) in annular rub: Hill's method and the collocation agree.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Maneuver, Model, Rotor, RubStator
from rotorkit.elements import LinearBearing
from rotorkit.errors import ParameterError
from rotorkit.periodic.floquet import _orbit_states, _switch_times, exponential_monodromy, phi_functions
from rotorkit.periodic.hb import HarmonicBalance, newton
from rotorkit.periodic.stability import hill_multipliers, monodromy_multipliers


def gap(a, b):
    d = np.abs(np.asarray(a)[:, None] - np.asarray(b)[None, :])
    return float(max(np.max(np.min(d, axis=1)), np.max(np.min(d, axis=0))))


@pytest.mark.parametrize("z", [0.0, 1e-3, -0.3 + 0.2j, 0.49j, -0.51, 2.0 - 1.0j, -40.0 + 300.0j])
def test_phi_functions_closed_forms(z):
    phi = phi_functions(np.array([z]), 3)[:, 0]
    assert abs(phi[0] - np.exp(z)) <= 1e-15 * abs(np.exp(z))
    if z == 0.0:
        assert np.allclose(phi, [1.0, 1.0, 0.5, 1.0 / 6.0], rtol=1e-15, atol=0)
        return
    import mpmath

    mpmath.mp.dps = 40
    zm = mpmath.mpc(z)
    exact1 = (mpmath.exp(zm) - 1) / zm
    exact2 = (mpmath.exp(zm) - 1 - zm) / zm**2
    exact3 = (mpmath.exp(zm) - 1 - zm - zm**2 / 2) / zm**3
    for value, exact in ((phi[1], exact1), (phi[2], exact2), (phi[3], exact3)):
        assert abs(value - complex(exact)) <= 1e-13 * abs(complex(exact))


@pytest.fixture(scope="module")
def linear_system():
    bearing = LinearBearing(station=1, kxx=2.0e4, kyy=1.5e4, kxy=1.0e3, kyx=-2.0e3, cxx=4.0, cyy=3.0)
    return Model([Rotor(name="R", stations=(1,), speed=100.0),
                  Disk(station=1, mass=2.0, radius=0.1, eccentricity=2e-5, torsion=False), bearing],
                 name="floqlin").compile(backend="c")


def test_linear_rotor_multipliers_are_exponentials(linear_system):
    hb = HarmonicBalance(linear_system, speed_parameter="R_speed", harmonics=2)
    frame = hb.frame()
    z = newton(lambda z, j: hb.residual(z, frame, j), np.zeros(hb.size), tol=1e-12, scale=frame.scale)[0]
    A = linear_system.jacobian(0.0, np.zeros(4))
    expected = np.exp(np.linalg.eigvals(A) * frame.period)
    for method in ("collocation", "dop853"):
        assert gap(monodromy_multipliers(hb, z, frame, method=method)[0], expected) < 1e-10
    mu, Phi = exponential_monodromy(hb, z, frame)
    from scipy.linalg import expm

    assert np.allclose(Phi, expm(A * frame.period), rtol=0, atol=1e-12)
    assert gap(hill_multipliers(hb, z, frame), expected) < 1e-8


@pytest.fixture(scope="module")
def partial_rub():
    system = Model([Rotor(name="R", stations=(1,), speed=650.0),
                    Disk(station=1, mass=2.0, radius=0.1, eccentricity=2e-5, torsion=False),
                    LinearBearing(station=1, kxx=1.2e6, kyy=1.0e6, cxx=150.0, cyy=150.0),
                    RubStator(station=1, clearance=1e-4, contact_stiffness=1e6, friction_coefficient=0.1),
                    Maneuver.steady(gravity=9.81)], name="floqpartial").compile(backend="c")
    from rotorkit.analysis.periodic import periodic_solution

    b = periodic_solution(system, harmonics=6, stability="none")
    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=6)
    return hb, b.coefficients[0].ravel(), hb.frame()


def test_switch_instants_are_roots_of_the_switch_function(partial_rub):
    hb, z, frame = partial_rub
    events = _switch_times(hb, z, frame)
    assert len(events) == 2  # contact during part of the period: one entry, one exit
    values = frame.evaluator.switches(frame.point, events, _orbit_states(hb, z, frame, events))
    grid = np.linspace(0.0, frame.period, 64)
    size = np.max(np.abs(frame.evaluator.switches(frame.point, grid, _orbit_states(hb, z, frame, grid))))
    assert np.max(np.abs(values)) <= 1e-10 * size  # roots to ~1e-11 of the gap's range (round-off of the orbit)


def test_partial_rub_collocation_equals_dop853(partial_rub):
    hb, z, frame = partial_rub
    reference = monodromy_multipliers(hb, z, frame, method="dop853", rtol=1e-12, atol=1e-14)[0]
    mu = monodromy_multipliers(hb, z, frame)[0]
    assert gap(mu, reference) < 1e-9
    assert gap(mu, monodromy_multipliers(hb, z, frame, steps=64)[0]) < 1e-10


def chain(n_stations, clearance):
    stations = tuple(range(1, n_stations + 1))
    elements = [Rotor(name="R", stations=stations, speed=300.0)]
    for s in stations:
        elements += [Disk(station=s, mass=1.0, radius=0.05, eccentricity=1e-5 if s in (1, n_stations) else 0.0,
                          torsion=False), ElasticSupport(station=s, stiffness=1e6, damping=50.0)]
    elements += [LinearBearing(station=a, other_station=b, kxx=2e6, kyy=2e6, cxx=10.0, cyy=10.0)
                 for a, b in zip(stations, stations[1:])]
    elements.append(RubStator(station=stations[n_stations // 2], clearance=clearance, contact_stiffness=1e6,
                              friction_coefficient=0.1))
    return Model(elements, name=f"floqchain{n_stations}").compile(backend="c")


def test_chain_rotor_hill_and_collocation_agree():
    from rotorkit.analysis.periodic import periodic_solution

    system = chain(8, 5e-8)
    b = periodic_solution(system, harmonics=4, condense=True, stability="none")
    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=4)
    frame = hb.frame()
    z = b.coefficients[0].ravel()
    assert b.max_radius(5)[0] > 5e-8  # in contact
    mu = monodromy_multipliers(hb, z, frame)[0]
    assert len(mu) == 32
    assert gap(mu, hill_multipliers(hb, z, frame)) < 1e-8
    assert gap(mu, monodromy_multipliers(hb, z, frame, steps=64)[0]) < 1e-10


def test_rank_limit_and_bad_method(partial_rub):
    hb, z, frame = partial_rub
    assert exponential_monodromy(hb, z, frame, rank_limit=0) is None  # x and y enter the contact Jacobian
    with pytest.raises(ParameterError, match="method='rk4' is unknown"):
        monodromy_multipliers(hb, z, frame, method="rk4")
