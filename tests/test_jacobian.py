"""The analytic Jacobian generated from the symbolic equations, against finite differences."""

import math

import numpy as np
import pytest

import rotorkit as rk


def finite_difference(system, t, y):
    n = len(y)
    J = np.empty((n, n))
    scale = np.r_[np.full(n // 2, 1e-9), np.full(n // 2, 1e-6)]  # well below ball deformations (um)
    for k in range(n):
        h = scale[k]
        yp, ym = y.copy(), y.copy()
        yp[k] += h
        ym[k] -= h
        J[:, k] = (system.rhs(t, yp) - system.rhs(t, ym)) / (2 * h)
    return J


def preset_states():
    rng = np.random.default_rng(5)
    delta = 1.34e-4
    out = {}
    y = rng.normal(size=32) * np.r_[np.full(16, 2e-5), np.full(16, 2e-3)]
    y[1], y[8] = 0.3 * delta, 0.2 * delta
    out["no contact"] = (1.0, y)
    for name, factor in (("rub engaged", 1.6), ("deep rub", 3.0)):
        y = rng.normal(size=32) * np.r_[np.full(16, 2e-5), np.full(16, 2e-3)]
        angle = rng.uniform(0, 2 * math.pi)
        y[1], y[8] = factor * delta * math.cos(angle), factor * delta * math.sin(angle)
        y[6] += 4e-5  # x7 - x4: several balls loaded
        out[name] = (2.6, y)  # inside the roll window
    return out


@pytest.mark.parametrize("backend", rk.available_backends())
@pytest.mark.parametrize("case", list(preset_states()))
def test_preset_jacobian_matches_finite_differences(backend, case):
    system = rk.preset("al31f").compile(backend=backend)
    t, y = preset_states()[case]
    J = system.jacobian(t, y)
    J_fd = finite_difference(system, t, y)
    n = 16
    np.testing.assert_array_equal(J[:n, n:], np.eye(n))
    np.testing.assert_array_equal(J[:n, :n], 0.0)
    scale = np.abs(J_fd[n:]).max(axis=1, keepdims=True)
    assert np.all(np.abs(J[n:] - J_fd[n:]) <= 1e-5 * scale + 1e-9), case


def test_jacobian_is_finite_at_the_origin_and_zero_clearance():
    system = rk.preset("al31f", rub_clearance=0.0).compile()
    J = system.jacobian(0.5, np.zeros(32))
    assert np.all(np.isfinite(J))


def test_jeffcott_jacobian_is_the_linear_system():
    m, k, c = 2.0, 2e4, 6.0
    system = rk.Model([rk.Rotor(name="R", stations=(1,), speed=30.0),
                       rk.Disk(station=1, mass=m, radius=0.1),
                       rk.ElasticSupport(station=1, stiffness=k, damping=c)]).compile()
    J = system.jacobian(0.3, np.array([1e-3, -2e-3, 0.1, 0.2]))
    expected = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-k / m, 0, -c / m, 0], [0, -k / m, 0, -c / m]])
    np.testing.assert_allclose(J, expected, rtol=1e-14)


@pytest.mark.parametrize("backend", rk.available_backends())
def test_state_dependent_mass_matrix_term(backend):
    """A strongly eccentric torsional disk: the -dM/dalpha q'' part of the Jacobian matters here."""
    system = rk.Model([
        rk.Rotor(name="R", stations=(0, 1), speed=40.0),
        rk.LumpedMass(station=0, mass=1.0),
        rk.Disk(station=1, mass=2.0, radius=0.1, eccentricity=0.05, torsion=True),
        rk.ElasticSupport(station=0, stiffness=1e4),
        rk.ElasticSupport(station=1, stiffness=2e4, damping=3.0),
        rk.ShaftSegment(start=0, end=1, bending_stiffness=5e4, torsional_stiffness=300.0, torsional_damping=0.2),
    ]).compile(backend=backend)
    y = np.array([1e-3, 2e-3, -1e-3, 1.5e-3, 0.4, 0.1, -0.2, 0.3, -0.1, 5.0])  # x0 x1 y0 y1 alpha1, rates
    J, J_fd = system.jacobian(0.7, y), finite_difference(system, 0.7, y)
    np.testing.assert_allclose(J, J_fd, rtol=1e-6, atol=1e-6 * np.abs(J_fd).max())


@pytest.mark.parametrize("backend", rk.available_backends())
def test_permanent_contact_is_linear_at_the_origin(backend):
    """Zero clearance: the rub force is -k_r (x - mu y, mu x + y), linear through r = 0."""
    m, k, kr, mu = 2.0, 2e4, 6e4, 0.2
    system = rk.Model([rk.Rotor(name="R", stations=(1,), speed=0.0), rk.Disk(station=1, mass=m, radius=0.1),
                       rk.ElasticSupport(station=1, stiffness=k),
                       rk.RubStator(station=1, clearance=0.0, contact_stiffness=kr, friction_coefficient=mu)]
                      ).compile(backend=backend)
    expected = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-(k + kr) / m, mu * kr / m, 0, 0], [-mu * kr / m, -(k + kr) / m, 0, 0]])
    for y in (np.zeros(4), np.array([1e-4, -2e-4, 0.0, 0.0])):
        np.testing.assert_allclose(system.jacobian(0.0, y), expected, rtol=1e-12)
    np.testing.assert_allclose(system.rhs(0.0, np.array([1e-4, 0, 0, 0]))[2:], [-(k + kr) * 1e-4 / m, -mu * kr * 1e-4 / m])


def test_with_parameters_keeps_the_time_window():
    system = rk.preset("al31f").compile()
    window = system.within(2.0, 4.0)
    changed = window.with_parameters(LP_speed=1000.0)
    np.testing.assert_array_equal(changed.prepared_parameters[-2:], window.prepared_parameters[-2:])
    assert changed.parameters["LP_speed"] == 1000.0
