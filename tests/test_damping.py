"""Proportional (Rayleigh) damping of a rotor against the single-mode closed form.

A mode of natural frequency ``w`` of a structure with ``C = alpha M + beta K``
has the damping ratio ``zeta = alpha / (2 w) + beta w / 2`` and the
eigenvalues ``-zeta w +- i w sqrt(1 - zeta^2)`` (``|lambda| = w``).

- Uniform pinned-pinned Euler-Bernoulli beam: ``w_k = (k pi / L)^2 sqrt(E I / (rho A))``.
- Disk on a spring support (the support is not the rotor's): ``zeta = alpha / (2 sqrt(k / m))``.
- Mass on a massless shaft segment from a pinned station: ``zeta = alpha / (2 w) + beta w / 2``,
  ``w = sqrt(k / m)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from rotorkit import Disk, ElasticSupport, LumpedMass, Model, Rotor, ShaftSegment
from rotorkit.analysis.linear_matrices import linear_matrices
from rotorkit.elements import BeamSegment, Material, Rayleigh
from rotorkit.errors import ParameterError

STEEL = Material.steel()
PIN = 1e13


def eigenvalues(model):
    """Eigenvalues with positive imaginary part of M q'' + C q' + K q = 0, by |lambda|."""
    M, C, K = (a.toarray() for a in linear_matrices(model))
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    lam = scipy.linalg.eig(A, B, right=False)
    lam = lam[np.isfinite(lam) & (lam.imag > 1.0)]
    return lam[np.argsort(np.abs(lam))]


def ratio(lam):
    return -lam.real / np.abs(lam)


@pytest.fixture(scope="module")
def beam():
    damping = Rayleigh(alpha=2.0, beta=4e-6)
    return Model([Rotor(name="R", stations=(1, 2), speed=0.0, damping=damping),
                  BeamSegment(start=1, end=2, length=1.0, outer_diameter=0.05, material=STEEL,
                              theory="euler-bernoulli", rotary_inertia=False, elements=8),
                  ElasticSupport(station=1, stiffness=PIN), ElasticSupport(station=2, stiffness=PIN)])


def test_uniform_beam_modes_have_the_rayleigh_damping_ratio(beam):
    L, D = 1.0, 0.05
    A, I = math.pi * D**2 / 4, math.pi * D**4 / 64
    exact = (math.pi / L) ** 2 * math.sqrt(STEEL.youngs_modulus * I / (STEEL.density * A))
    lam = eigenvalues(beam)[::2]  # x and y planes give pairs
    alpha, beta = 2.0, 4e-6
    w = np.abs(lam[:3])
    np.testing.assert_allclose(ratio(lam[:3]), alpha / (2 * w) + beta * w / 2, rtol=1e-5)  # supports: not K_r
    assert w[0] == pytest.approx(exact, rel=1e-4)  # and the first is the beam's closed form
    assert ratio(lam[0]) == pytest.approx(alpha / (2 * exact) + beta * exact / 2, rel=1e-4)


def test_damping_coefficients_are_parameters(beam):
    assert beam.parameters["R_damping_alpha"] == 2.0 and beam.parameters["R_damping_beta"] == 4e-6
    assert beam.parameter_units["R_damping_alpha"] == "1/s"
    swept = beam.with_values(R_damping_alpha=0.0, R_damping_beta="1e-5 s")
    assert swept.structure_key == beam.structure_key  # no re-derivation
    lam = eigenvalues(swept)[0]
    assert ratio(lam) == pytest.approx(1e-5 * abs(lam) / 2, rel=1e-6)


def test_disk_mass_proportional_damping():
    m, k, alpha = 10.0, 4e6, 3.0
    model = Model([Rotor(name="R", stations=(1,), speed=100.0, damping=Rayleigh(alpha, 1e-3)),
                   Disk(station=1, mass=m, polar_inertia=0.1, eccentricity=1e-4),
                   ElasticSupport(station=1, stiffness=k)])
    lam = eigenvalues(model)
    w = math.sqrt(k / m)
    np.testing.assert_allclose(ratio(lam), alpha / (2 * w), rtol=1e-9)  # the support is no part of K_r


def test_shaft_segment_stiffness_proportional_damping():
    m, k, alpha, beta = 5.0, 2e6, 1.5, 2e-4
    model = Model([Rotor(name="R", stations=(1, 2), speed=0.0, damping=Rayleigh(alpha, beta)),
                   LumpedMass(station=1, mass=1e-3), LumpedMass(station=2, mass=m),
                   ShaftSegment(start=1, end=2, bending_stiffness=k), ElasticSupport(station=1, stiffness=PIN)])
    lam = eigenvalues(model)[0]
    w = math.sqrt(k / m)
    assert abs(lam) == pytest.approx(w, rel=1e-6)
    assert ratio(lam) == pytest.approx(alpha / (2 * w) + beta * w / 2, rel=1e-6)


def test_undamped_rotor_structure_is_unchanged():
    plain = Rotor(name="R", stations=(1, 2), speed=1.0)
    assert all(name != "damping" for name, _ in plain.structure()[2])
    assert "damping_alpha" not in plain.parameters()


def test_from_damping_ratios():
    d = Rayleigh.from_damping_ratios((0.01, "20 turn/s"), (0.03, 800.0))
    w1 = 2 * math.pi * 20
    assert d.damping_ratio(w1) == pytest.approx(0.01) and d.damping_ratio(800.0) == pytest.approx(0.03)


@pytest.mark.parametrize("make, match", [
    (lambda: Rayleigh(alpha=-1.0), r"Rayleigh.alpha = -1.0: expected a value >= 0"),
    (lambda: Rayleigh(beta="2 m"), r"Rayleigh.beta"),
    (lambda: Rotor(name="R", stations=(1,), speed=1.0, damping=0.02), r"damping = 0.02: expected Rayleigh"),
    (lambda: Rayleigh.from_damping_ratios((0.02, 100.0), (0.02, 100.0)), r"are equal"),
    (lambda: Rayleigh.from_damping_ratios((0.1, 10.0), (0.0, 100.0)), r"both coefficients >= 0"),
])
def test_bad_damping_is_a_named_error(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


def test_damped_rotor_model_file_round_trip():
    from rotorkit.modelfile import dumps_model, loads_model

    model = Model([Rotor(name="R", stations=(1,), speed=100.0, damping=Rayleigh("2 1/s", 1e-4)),
                   LumpedMass(station=1, mass=3.0), ElasticSupport(station=1, stiffness=1e6)])
    text = dumps_model(model)
    assert 'alpha = "2 1/s"' in text or "alpha = \"2.0 1/s\"" in text
    back, _ = loads_model(text)
    assert back.parameters == model.parameters and back.structure_key == model.structure_key
