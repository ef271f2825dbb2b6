"""Modal damping ``C = M Phi diag(2 zeta_k w_k) Phi^T M`` from the undamped non-rotating modes.

Closed form: on a non-rotating beam on (anisotropic) bearings, mode ``k`` of
``M q'' + C q' + K q = 0`` has the eigenvalue
``-zeta_k w_k +- i w_k sqrt(1 - zeta_k^2)``: natural frequency ``w_k`` (the
undamped one, from an independent ``scipy.linalg.eigh``) and damping ratio
``zeta_k`` exactly, and the modes beyond the ratios given get ``remaining``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import eigh

from rotorkit import BeamSegment, LinearBearing, Material, Model, Rotor
from rotorkit.analysis.linear_matrices import linear_matrices
from rotorkit.linear.modal_damping import modal_damped_modes, modal_damping_matrix
from rotorkit.errors import ParameterError

RATIOS = [0.01, 0.02, 0.05, 0.03]


@pytest.fixture(scope="module")
def beam():
    return Model([Rotor(name="R", stations=(1, 2), speed=300.0),
                  BeamSegment(start=1, end=2, length=0.8, outer_diameter=0.04, material=Material.steel(), elements=3),
                  LinearBearing(station=1, kxx=2e7, kyy=5e7), LinearBearing(station=2, kxx=2e7, kyy=5e7)])


def test_each_mode_has_its_ratio(beam):
    values = dict(beam.parameters, R_speed=0.0)
    M, _, K = (a.toarray() for a in linear_matrices(beam, 0.0, values))
    w = np.sqrt(eigh(K, M, eigvals_only=True))
    modes = modal_damped_modes(beam, RATIOS, remaining=0.004)
    np.testing.assert_allclose(modes.frequencies[:8], w[:8], rtol=1e-8)
    expected = RATIOS + [0.004] * 4
    np.testing.assert_allclose(modes.damping_ratios[:8], expected, rtol=1e-7, atol=1e-12)


def test_matrix_is_symmetric_and_diagonal_in_the_modes(beam):
    C = modal_damping_matrix(beam, RATIOS)
    np.testing.assert_allclose(C, C.T, rtol=1e-12, atol=1e-12 * np.abs(C).max())
    values = dict(beam.parameters, R_speed=0.0)
    M, _, K = (a.toarray() for a in linear_matrices(beam, 0.0, values))
    w2, Phi = eigh(K, M)
    modal = Phi.T @ C @ Phi
    np.testing.assert_allclose(np.diag(modal)[:4], 2 * np.array(RATIOS) * np.sqrt(w2[:4]), rtol=1e-8)
    off = modal - np.diag(np.diag(modal))
    assert np.abs(off).max() <= 1e-8 * np.abs(modal).max()


@pytest.mark.parametrize("ratios, remaining, match", [
    ([], 0.0, r"ratios=\[\]"),
    ([0.02, -0.1], 0.0, r"ratios\[1\]=-0.1"),
    ([0.02], 1.5, r"remaining=1.5"),
    ("0.02", 0.0, r"ratios='0.02'"),
])
def test_bad_ratios(beam, ratios, remaining, match):
    with pytest.raises(ParameterError, match=match):
        modal_damping_matrix(beam, ratios, remaining=remaining)
