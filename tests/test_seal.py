"""Seal: LinearBearing's coefficients and tables, a direct stiffness of any sign, a static-stability warning.

Closed forms: a Jeffcott rotor (disk ``m`` at mid-span of a massless shaft
on rigid supports, lateral stiffness ``k``) with a seal at the disk has
the natural frequency ``sqrt((k + k_seal) / m)``; it is statically
unstable exactly when ``k_seal < -k`` (the model warns then, not before).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rotorkit import LinearBearing, LumpedMass, Model, Rotor, ShaftSegment
from rotorkit.analysis.linear_matrices import linear_matrices
from rotorkit.analysis.modal import modes_from_matrices
from rotorkit.elements import Seal
from rotorkit.elements.seal import StaticInstabilityWarning, static_stiffness_margin
from rotorkit.errors import ParameterError

M, K_SHAFT = 10.0, 4.0e6  # kg, N/m


def jeffcott(seal):
    """A disk (station 2) on a shaft of stiffness K_SHAFT to a rigid journal (station 1), with the seal at the disk."""
    return Model([Rotor(name="R", stations=(1, 2), speed=0.0), LumpedMass(station=1, mass=1.0),
                  LumpedMass(station=2, mass=M), ShaftSegment(start=1, end=2, bending_stiffness=K_SHAFT),
                  LinearBearing(station=1, kxx=1e15, kyy=1e15), seal])


@pytest.mark.parametrize("k_seal", [-1.5e6, 0.0, 2.0e6])
def test_jeffcott_frequency_with_seal_stiffness(k_seal):
    with warnings.catch_warnings():
        warnings.simplefilter("error", StaticInstabilityWarning)
        model = jeffcott(Seal(station=2, kxx=k_seal, kyy=k_seal))
    M_, C, K = linear_matrices(model)
    modes = modes_from_matrices(M_, C, K, model.coordinate_names, left=False, n_modes=2)
    exact = math.sqrt(K_SHAFT * 1e15 / (K_SHAFT + 1e15) / M + k_seal / M)  # series shaft and rigid journal spring
    np.testing.assert_allclose(modes.frequencies[:2], exact, rtol=1e-9)
    assert static_stiffness_margin(model) > 0


def test_warns_below_minus_shaft_stiffness_only():
    with pytest.warns(StaticInstabilityWarning, match=r"'seal2'.*statically unstable"):
        unstable = jeffcott(Seal(station=2, kxx=-1.05 * K_SHAFT, kyy=-1.05 * K_SHAFT))
    assert static_stiffness_margin(unstable) < 0
    with warnings.catch_warnings():
        warnings.simplefilter("error", StaticInstabilityWarning)
        jeffcott(Seal(station=2, kxx=-0.95 * K_SHAFT, kyy=-0.95 * K_SHAFT))
    # one direction is enough to diverge, and a table is checked at the model's speed
    with pytest.warns(StaticInstabilityWarning):
        jeffcott(Seal.tabulated(station=2, speeds=[0.0, 100.0], kxx=[-1.2 * K_SHAFT, 0.0], kyy=[0.0, 0.0]))


def test_seal_reuses_bearing_tables(tmp_path):
    seal = Seal.tabulated(station=2, speeds=[0.0, 300.0], kxx=[-1e5, -3e5], kyy=[-1e5, -3e5], kxy=[0.0, 2e5],
                          kyx=[0.0, -2e5], cxx=[100.0, 200.0], cyy=[100.0, 200.0], interpolation="pchip")
    path = tmp_path / "seal.csv"
    seal.to_csv(path)
    back = Seal.from_csv(path, station=2, interpolation="pchip")
    assert isinstance(back, Seal) and back.parameters() == seal.parameters()
    assert isinstance(back.replace_parameters(kxx1=-4e5), Seal)
    model = jeffcott(seal).with_values(R_speed=150.0)
    K = linear_matrices(model)[2].toarray()
    i, j = model.coordinate_names.index("x2"), model.coordinate_names.index("y2")
    assert K[i, i] == pytest.approx(K_SHAFT - 2e5, rel=1e-12)  # the midpoint of a two-point (linear) pchip
    assert K[i, j] == pytest.approx(1e5, rel=1e-12)


@pytest.mark.parametrize("make, match", [
    (lambda: Seal(station=2, kxx=-1.0, kyy=1.0, cxx=-3.0), r"Seal.cxx = -3.0"),
    (lambda: Seal.tabulated(station=2, speeds=[0, 1], kxx=[-1, -2], kyy=[1, 2], cyy=[1, -2]),
     r"Seal at station 2: cyy\[1\] = -2.0 is negative"),
    (lambda: Seal(station=2, kxx=1.0), r"Seal at station 2: kyy is required \(N/m, any sign\)"),
    (lambda: LinearBearing(station=2, kxx=-1.0, kyy=1.0), r"kxx"),
])
def test_bad_seal_input(make, match):
    with pytest.raises(ParameterError, match=match):
        make()
