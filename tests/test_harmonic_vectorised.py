"""Harmonic solves vectorised over the speeds against the point-by-point reference.

References: the speed terms evaluated at one speed at a time (the scalar
generated code, ``SpeedTerms.values``), and the dynamic stiffness
``K(W) - w^2 M + i w C(W)`` of each point assembled from
``LinearModel.matrices(W)`` (the exact matrices at that speed) and solved
densely by LAPACK (``numpy.linalg.solve``).
"""

import numpy as np
import pytest

from rotorkit import Disk, Model, Rotor
from rotorkit.elements import BeamSegment, LinearBearing, Material
from rotorkit.linear.frf import frequency_response
from rotorkit.linear.harmonic import solve_harmonic
from rotorkit.linear.linear_model import linear_model

TABLE_SPEEDS = [0.0, 300.0, 650.0, 1000.0]


def rotor(interpolation="linear", extrapolation="hold"):
    """Three beam elements, two disks, a tabulated cross-coupled bearing and a tabulated plain one."""
    steel = Material(density=7850.0, youngs_modulus=2.1e11, shear_modulus=8.1e10)
    elements = [Rotor(name="R", stations=(1, 2, 3, 4), speed=400.0)]
    elements += [BeamSegment(start=s, end=s + 1, length=0.15, outer_diameter=0.05, material=steel)
                 for s in (1, 2, 3)]
    elements += [Disk(station=2, mass=8.0, polar_inertia=0.08, diametral_inertia=0.04),
                 Disk(station=3, mass=5.0, polar_inertia=0.05, diametral_inertia=0.025)]
    options = dict(speeds=TABLE_SPEEDS, interpolation=interpolation, extrapolation=extrapolation)
    elements.append(LinearBearing.tabulated(station=1, kxx=[1e7, 2e7, 2.5e7, 3e7], kyy=[8e6, 1.2e7, 2e7, 2.5e7],
                                            kxy=[0.0, 2e6, 3e6, 5e6], kyx=[0.0, -2e6, -3e6, -5e6],
                                            cxx=[2e3, 1.5e3, 1.2e3, 1e3], cyy=[2e3, 1.6e3, 1.3e3, 1.2e3], **options))
    elements.append(LinearBearing.tabulated(station=4, kxx=[1.5e7, 1.6e7, 1.8e7, 2e7], kyy=[1e7, 1.1e7, 1.4e7, 1.5e7],
                                            cxx=[800.0, 700.0, 650.0, 600.0], cyy=[800.0, 750.0, 700.0, 650.0],
                                            **options))
    return Model(elements, name=f"vectorised_{interpolation}_{extrapolation}")


#: below, inside (on and between the knots) and above the table, a repeated speed
SPEEDS = np.array([-120.0, 0.0, 10.0, 299.0, 300.0, 301.0, 480.0, 650.0, 999.0, 1000.0, 1400.0, 480.0])


@pytest.mark.parametrize("interpolation, extrapolation",
                         [("linear", "hold"), ("linear", "linear"), ("pchip", "hold"), ("pchip", "linear")])
def test_speed_terms_at_many_speeds_equal_the_terms_at_each_speed(interpolation, extrapolation):
    terms = linear_model(rotor(interpolation, extrapolation), speed=500.0).speed_terms
    assert terms is not None and terms.many is not None
    many = terms.values_at(SPEEDS)
    assert many.shape == (SPEEDS.size, terms.matrix.size)
    for k, w in enumerate(SPEEDS):
        one = np.asarray(terms.values(w))
        np.testing.assert_allclose(many[k], one, rtol=0, atol=1e-13 * np.abs(one).max())
    assert np.abs(many).max() > 1e5  # the remainders are not all zero: a wrong value could not pass


@pytest.mark.parametrize("interpolation", ["linear", "pchip"])
def test_tables_are_evaluated_for_all_speeds_at_once(monkeypatch, interpolation):
    """The point-by-point fallback is not used for piecewise-linear or PCHIP tables (numpy.where for PCHIP's steps)."""
    import rotorkit.linear.linear_matrices as lm

    terms = linear_model(rotor(interpolation), speed=500.0).speed_terms

    def refuse(*args):
        raise AssertionError("evaluated point by point")

    monkeypatch.setattr(lm, "_scalar_rows", refuse)
    assert terms.values_at(SPEEDS).shape == (SPEEDS.size, terms.matrix.size)


def _reference(model, speeds, frequencies, forces):
    out = []
    for W, w, F in zip(speeds, frequencies, forces):
        M, C, K = model.matrices(W)
        out.append(np.linalg.solve(K - w * w * M + 1j * w * C, F))
    return np.array(out)


@pytest.mark.parametrize("interpolation", ["linear", "pchip"])
@pytest.mark.parametrize("method", ["banded", "dense"])
def test_harmonic_solves_equal_one_dense_solve_per_point(interpolation, method):
    model = linear_model(rotor(interpolation), speed=500.0)
    rng = np.random.default_rng(4)
    speeds = np.linspace(20.0, 1300.0, 40)
    frequencies = speeds * rng.uniform(0.5, 1.5, speeds.size)  # speed and frequency differ
    forces = rng.standard_normal((speeds.size, model.n, 2)) + 1j * rng.standard_normal((speeds.size, model.n, 2))
    Q = solve_harmonic(model, speeds, frequencies, forces, method=method)
    ref = _reference(model, speeds, frequencies, forces)
    scale = np.abs(ref).max(axis=(1, 2))[:, None, None]
    np.testing.assert_allclose(Q / scale, ref / scale, rtol=0, atol=1e-10)


def test_frequency_response_with_speed_terms_equals_the_inverse_dynamic_stiffness():
    model = linear_model(rotor(), speed=500.0)
    frequencies = np.linspace(0.0, 2000.0, 25)
    frf = frequency_response(model, frequencies, inputs=["x2", "y3"], outputs=["x1", "y2", "x4"], speed=820.0)
    M, C, K = model.matrices(820.0)
    cols = [model.coordinate_index(s) for s in ("x2", "y3")]
    rows = [model.coordinate_index(s) for s in ("x1", "y2", "x4")]
    for k, w in enumerate(frequencies):
        H = np.linalg.inv(K - w * w * M + 1j * w * C)[np.ix_(rows, cols)]
        np.testing.assert_allclose(frf.values[k], H, rtol=0, atol=1e-10 * np.abs(H).max())
