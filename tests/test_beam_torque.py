"""Geometric stiffness of a constant axial torque in BeamSegment (Greenhill's problem).

Closed forms and independent derivations, pinned-pinned Euler-Bernoulli shaft:

- Greenhill (1883): the shaft buckles at the torque ``T_cr = 2 pi E I / L``;
  the finite elements' critical torque (where ``K`` becomes singular)
  converges to it;
- the natural frequencies under a torque ``T`` solve the exact
  characteristic equation of ``EI w'''' - i T w''' - rho A w_n^2 w = 0``
  (``w = x + i y``), ``w = 0`` and ``EI w'' - i T w' = 0`` at both ends
  (the bending moment of the axial torque at a ball joint): a 4x4
  determinant over the four roots of ``EI r^4 - i T r^3 - rho A w_n^2``,
  solved here with ``brentq``; the first frequency drops to zero at
  ``T_cr``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rotorkit import BeamSegment, LinearBearing, Material, Model, Rotor
from rotorkit.analysis.linear_matrices import linear_evaluator
from rotorkit.elements import TaperedBeamSegment
from rotorkit.errors import ParameterError, UnitError

STEEL = Material.steel()
L, D = 1.0, 0.02
EI = STEEL.youngs_modulus * math.pi * D**4 / 64
RHO_A = STEEL.density * math.pi * D**2 / 4
T_CR = 2 * math.pi * EI / L


def pinned_shaft(elements=16, torque=0.0):
    beam = BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL, elements=elements, torque=torque,
                       theory="euler-bernoulli", rotary_inertia=False, gyroscopic=False, name="shaft")
    pins = [LinearBearing(station=s, kxx=1e16, kyy=1e16) for s in (1, 2)]
    return Model([Rotor(name="R", stations=(1, 2), speed=0.0), beam, *pins])


@pytest.fixture(scope="module")
def evaluator():
    return linear_evaluator(pinned_shaft(), free=("shaft_torque",))


def exact_frequency(T, low, high):
    """The root in (low, high) of the exact characteristic determinant (made invariant to the roots' order)."""

    def determinant(w):
        r = np.roots([EI, -1j * T, 0.0, 0.0, -RHO_A * w * w])
        moment = EI * r**2 - 1j * T * r
        rows = np.array([np.ones(4), np.exp(r * L), moment, moment * np.exp(r * L)])
        vandermonde = np.prod([r[j] - r[i] for i in range(4) for j in range(i + 1, 4)])
        return np.linalg.det(rows) / vandermonde

    phase = determinant(low) / abs(determinant(low))  # real up to a constant phase
    return brentq(lambda w: (determinant(w) / phase).real, low, high, xtol=1e-12)


def test_critical_torque_is_greenhills(evaluator):
    K0 = evaluator(shaft_torque=0.0)[2].toarray()
    K1 = evaluator(shaft_torque=1.0)[2].toarray() - K0  # K is affine in the torque
    mu = np.linalg.eigvals(np.linalg.solve(K0, -K1))
    real = mu[np.abs(mu.imag) <= 1e-9 * np.abs(mu)].real
    critical = 1.0 / np.max(np.abs(real))
    assert critical == pytest.approx(T_CR, rel=1e-4)


@pytest.mark.parametrize("fraction", [0.0, 0.5, 0.9])
def test_frequencies_under_torque_solve_the_exact_equation(evaluator, fraction):
    M, _, K = (a.toarray() for a in evaluator(shaft_torque=fraction * T_CR))
    lam = np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)
    first = math.sqrt(lam[0])
    pinned = math.pi**2 * math.sqrt(EI / (RHO_A * L**4))
    exact = exact_frequency(fraction * T_CR, 0.3 * pinned, 1.2 * pinned)
    assert first == pytest.approx(exact, rel=2e-4)
    assert lam[1] == pytest.approx(lam[0], rel=1e-3)  # a pair, split only by the discretisation


def test_frequency_drops_to_zero_at_the_critical_torque(evaluator):
    M, _, K = (a.toarray() for a in evaluator(shaft_torque=T_CR))
    lowest = np.min(np.abs(np.linalg.eigvals(np.linalg.solve(M, K))))
    at_rest = np.min(np.abs(np.linalg.eigvals(np.linalg.solve(M, evaluator(shaft_torque=0.0)[2].toarray()))))
    assert math.sqrt(lowest) < 0.1 * math.sqrt(at_rest)  # FE critical slightly above T_CR: nearly zero here
    M, _, K = (a.toarray() for a in evaluator(shaft_torque=1.01 * T_CR))
    assert np.min(np.linalg.eigvals(np.linalg.solve(M, K)).real) < 0  # beyond it the shaft diverges


def test_torque_absent_keeps_the_structure_and_stiffness_is_split():
    plain = BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL)
    loaded = BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL, torque="200 N*m")
    assert loaded.torque == 200.0
    assert plain.structure() != loaded.structure()
    assert plain.structure() == BeamSegment(start=1, end=2, length=L, outer_diameter=D,
                                            material=STEEL).structure()
    assert not any(entry[0] == "torque" for entry in plain.structure()[2])


@pytest.mark.parametrize("make, error, match", [
    (lambda: BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL, torque="3 m"), UnitError,
     r"torque"),
    (lambda: TaperedBeamSegment(start=1, end=2, length=L, outer_diameter=D, outer_diameter_end=0.01,
                                material=STEEL, torque=10.0), ParameterError, r"torque = 10.0: an axial torque"),
])
def test_bad_torque_input(make, error, match):
    with pytest.raises(error, match=match):
        make()
