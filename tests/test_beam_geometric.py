"""Axial force in beam elements (geometric stiffness) against the closed form.

A pinned-pinned Euler-Bernoulli shaft under an axial force ``P`` (tension
positive) vibrates in ``sin(k pi z / L)`` with
``w_k^2 = (k pi / L)^4 E I / (rho A) (1 + P / P_k)``, ``P_k = k^2 pi^2 E I / L^2``:
a compressive load ``-P`` lowers the first frequency by ``sqrt(1 - P / P_cr)``
with ``P_cr = pi^2 E I / L^2`` (Euler's buckling load).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from rotorkit import ElasticSupport, Model, Rotor
from rotorkit.analysis.linear_matrices import linear_matrices
from rotorkit.elements import BeamSegment, Material

STEEL = Material.steel()
L, D = 1.0, 0.05
INERTIA = math.pi * D**4 / 64
P_CR = math.pi**2 * STEEL.youngs_modulus * INERTIA / L**2


def first_frequencies(model, count=2):
    M, _, K = linear_matrices(model)
    w = np.sort(np.sqrt(np.abs(scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True))))
    out = []
    for v in w:
        if v > 1.0 and (not out or v > out[-1] * (1 + 1e-4)):
            out.append(v)
    return np.array(out[:count])


@pytest.fixture(scope="module")
def loaded():
    return Model([Rotor(name="R", stations=(1, 2), speed=0.0),
                  BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL, theory="euler-bernoulli",
                              rotary_inertia=False, elements=8, axial_force=0.0, name="shaft"),
                  ElasticSupport(station=1, stiffness=1e13), ElasticSupport(station=2, stiffness=1e13)])


@pytest.mark.parametrize("fraction", [-0.9, -0.5, -0.25, 0.5])
def test_axial_force_scales_pinned_pinned_frequencies(loaded, fraction):
    w0 = first_frequencies(loaded)
    w = first_frequencies(loaded.with_values(shaft_axial_force=fraction * P_CR))
    exact = np.sqrt([1 + fraction, 1 + fraction / 4])  # P_2 = 4 P_cr
    np.testing.assert_allclose(w / w0, exact, rtol=3e-4)


def test_absent_axial_force_leaves_the_beam_structure_unchanged():
    plain = BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL)
    assert all(name != "axial_force" for name, _ in plain.structure()[2])
    assert "axial_force" not in plain.parameters()
    loaded = BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL, axial_force="-3 kN")
    assert loaded.parameters()["axial_force"] == -3000.0
