"""Bearing tables against the whirl frequency, and modes with each mode's coefficients at its own frequency.

Closed forms and independent derivations:

- a mass ``m`` on a bearing ``k(nu) = k0 + a nu`` (a two-point table
  continued linearly, exact for every ``nu``): ``m w^2 = k0 + a w``, so
  ``w = (a + sqrt(a^2 + 4 m k0)) / (2 m)``;
- a Jeffcott rotor (disk ``m2`` on a massless shaft ``k_s`` to a journal
  ``m1`` on that bearing): the root of the characteristic equation
  ``(k_s - m2 w^2)(k_s + k(w) - m1 w^2) - k_s^2 = 0`` found by ``brentq``;
- added-mass equivalence: a bearing ``k(nu) = k0 - m_a nu^2`` read at the
  frequency of an undamped mode acts as ``k0`` with the added mass
  ``m_a``; a table through that law with knots at the modes of the
  constant-coefficient model (a beam rotor on ``LinearBearing(kxx=k0,
  mxx=m_a)``) has matched-whirl frequencies equal to those modes;
- a grid against speed and frequency is read as scipy reads it: bilinear,
  and for PCHIP the frequency rows interpolated first, then the speed
  (nested ``PchipInterpolator``).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

from rotorkit import BeamSegment, LinearBearing, LumpedMass, Material, Model, Rotor, ShaftSegment
from rotorkit.analysis.linear_matrices import linear_evaluator, linear_matrices
from rotorkit.linear.matched_whirl import MatchedWhirlWarning, matched_whirl_campbell, matched_whirl_modes
from rotorkit.analysis.modal import modes_from_matrices
from rotorkit.errors import ParameterError, SimulationError

K0, A = 1.0e6, 500.0  # N/m, N s/m: k(nu) = K0 + A nu


def linear_in_frequency(station=1, name="b"):
    return LinearBearing.frequency_table(station=station, name=name, frequencies=[0.0, 1000.0],
                                         kxx=[K0, K0 + A * 1000.0], kyy=[K0, K0 + A * 1000.0], extrapolation="linear")


def test_mass_on_frequency_dependent_bearing_closed_form():
    m = 2.0
    model = Model([Rotor(name="R", stations=(1,), speed=100.0), LumpedMass(station=1, mass=m), linear_in_frequency()])
    result = matched_whirl_modes(model, n_modes=2)
    expected = (A + math.sqrt(A * A + 4 * m * K0)) / (2 * m)
    assert result.converged.all()
    np.testing.assert_allclose(result.whirl_frequencies, expected, rtol=1e-10)
    np.testing.assert_allclose(result.damped_frequencies, expected, rtol=1e-9)
    # the synchronous reading (the model as given, k at 100 rad/s) is a different, wrong answer
    M, C, K = (x.toarray() for x in linear_matrices(model))
    assert K[0, 0] == pytest.approx(K0 + A * 100.0)


def test_jeffcott_rotor_matched_frequency_solves_characteristic_equation():
    m1, m2, ks = 1.0, 10.0, 4.0e6
    model = Model([Rotor(name="R", stations=(1, 2), speed=300.0), LumpedMass(station=1, mass=m1),
                   LumpedMass(station=2, mass=m2), ShaftSegment(start=1, end=2, bending_stiffness=ks),
                   linear_in_frequency()])
    result = matched_whirl_modes(model, n_modes=4)

    def characteristic(w):
        return (ks - m2 * w * w) * (ks + K0 + A * w - m1 * w * w) - ks * ks

    first = brentq(characteristic, 1.0, math.sqrt(ks / m2), xtol=1e-14)
    second = brentq(characteristic, math.sqrt(ks / m2), 1e5, xtol=1e-14)
    assert result.converged.all()
    np.testing.assert_allclose(result.damped_frequencies, [first, first, second, second], rtol=1e-9)
    for w in result.damped_frequencies:
        assert abs(characteristic(w)) <= 1e-8 * ks * ks


def beam_rotor(bearings, speed=0.0):
    steel = Material.steel()
    return Model([Rotor(name="R", stations=(1, 2), speed=speed),
                  BeamSegment(start=1, end=2, length=1.0, outer_diameter=0.05, material=steel, elements=2),
                  *bearings])


def test_frequency_table_equals_added_mass_model_at_its_modes():
    k0, ma = 5.0e7, 3.0
    constant = beam_rotor([LinearBearing(station=s, kxx=k0, kyy=k0, mxx=ma, myy=ma) for s in (1, 2)])
    M, C, K = linear_matrices(constant)
    reference = modes_from_matrices(M, C, K, constant.coordinate_names, left=False).frequencies[:4]
    knots = np.concatenate([[0.0], np.unique(np.round(reference, 9)), [1.2 * reference[-1]]])
    law = [k0 - ma * nu * nu for nu in knots]
    for interpolation in ("linear", "pchip"):
        tabulated = beam_rotor([LinearBearing.frequency_table(station=s, frequencies=knots, kxx=law, kyy=law,
                                                              interpolation=interpolation) for s in (1, 2)])
        result = matched_whirl_modes(tabulated, n_modes=4)
        assert result.converged.all()
        np.testing.assert_allclose(result.damped_frequencies, reference, rtol=1e-9)


@pytest.mark.parametrize("interpolation", ["linear", pytest.param("pchip", marks=pytest.mark.slow)])
def test_grid_against_speed_and_frequency_is_read_as_scipy(interpolation):
    speeds, freqs = [0.0, 200.0, 500.0], [0.0, 100.0, 250.0, 600.0]
    grid = np.array([[1.0, 1.5, 1.2, 3.0], [2.0, 2.2, 2.6, 2.0], [0.5, 1.0, 4.0, 4.5]]) * 1e6
    bearing = LinearBearing.frequency_table(station=1, name="b", speeds=speeds, frequencies=freqs,
                                            kxx=grid.tolist(), kyy=grid.tolist(), interpolation=interpolation)
    model = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=1.0), bearing])
    evaluator = linear_evaluator(model, free=("R_speed", "b_whirl_ratio", "b_whirl_frequency"))
    for w, nu in [(50.0, 30.0), (333.0, 420.0), (500.0, 99.0), (120.0, 600.0)]:
        K = evaluator(R_speed=w, b_whirl_ratio=0.0, b_whirl_frequency=nu)[2].toarray()
        if interpolation == "linear":
            rows = [np.interp(nu, freqs, row) for row in grid]
            expected = np.interp(w, speeds, rows)
        else:
            rows = [float(PchipInterpolator(freqs, row)(nu)) for row in grid]
            expected = float(PchipInterpolator(speeds, rows)(w))
        assert K[0, 0] == pytest.approx(expected, rel=1e-12)
    # synchronous by default: read at nu = speed
    K = evaluator(R_speed=250.0, b_whirl_ratio=1.0, b_whirl_frequency=0.0)[2].toarray()
    K_fixed = evaluator(R_speed=250.0, b_whirl_ratio=0.0, b_whirl_frequency=250.0)[2].toarray()
    assert K[0, 0] == pytest.approx(K_fixed[0, 0], rel=1e-14)


def test_fixed_whirl_and_grid_csv_round_trip(tmp_path):
    bearing = LinearBearing.frequency_table(station=1, speeds=[0.0, 100.0], frequencies=[0.0, 50.0, 80.0],
                                            kxx=[[1, 2, 3], [4, 5, 6]], kyy=[[1, 2, 3], [4, 5, 7]], whirl=60.0,
                                            interpolation="pchip")
    assert bearing.parameters()["whirl_ratio"] == 0.0 and bearing.parameters()["whirl_frequency"] == 60.0
    path = tmp_path / "grid.csv"
    bearing.to_csv(path)
    back = LinearBearing.from_csv(path, station=1, whirl=60.0, interpolation="pchip")
    assert back.parameters() == bearing.parameters()
    assert back.replace_parameters(kyy1_2=8.0).kyy[1] == (4.0, 5.0, 8.0)


@pytest.mark.parametrize("make, match", [
    (lambda: LinearBearing(station=1, kxx=1.0, kyy=1.0, whirl=3.0), r"whirl = 3.0 is only used with a table"),
    (lambda: LinearBearing.frequency_table(station=1, speeds=[0, 1], frequencies=[0, 1], kxx=[[1, 2]],
                                           kyy=[[1, 2], [1, 2]]), r"kxx = .*: expected 2 rows"),
    (lambda: LinearBearing.frequency_table(station=1, frequencies=[0, 1], kxx=[1, -2], kyy=[1, 2]),
     r"kxx\[1\] = -2.0 is negative"),
    (lambda: LinearBearing.frequency_table(station=1, frequencies=[1, 0], kxx=[1, 2], kyy=[1, 2]),
     r"frequencies = .* is not strictly increasing"),
])
def test_bad_frequency_tables_are_named_errors(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


def test_non_convergence_is_reported():
    model = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=2.0), linear_in_frequency()])
    with pytest.warns(MatchedWhirlWarning, match=r"mode\(s\) \[1, 2\] .* did not converge in 1 steps"):
        result = matched_whirl_modes(model, n_modes=2, max_iterations=1)
    assert not result.converged.any() and (result.residuals > 0).all()
    with pytest.raises(SimulationError, match="did not converge"):
        matched_whirl_modes(model, n_modes=2, max_iterations=1, strict=True)
    with pytest.raises(ParameterError, match="max_iterations=0"):
        matched_whirl_modes(model, max_iterations=0)


def test_model_without_frequency_tables_gives_its_modes():
    m, k = 2.0, 8.0e6
    model = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=m),
                   LinearBearing(station=1, kxx=k, kyy=k)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        result = matched_whirl_modes(model, n_modes=2)
    np.testing.assert_allclose(result.frequencies, math.sqrt(k / m), rtol=1e-12)
    assert (result.iterations == 0).all()


def test_compiled_rhs_reads_the_table_at_the_whirl_frequency():
    m = 2.0
    model = Model([Rotor(name="R", stations=(1,), speed=200.0), LumpedMass(station=1, mass=m), linear_in_frequency()])
    system = model.compile(backend="python")
    for given, nu in [({}, 200.0), ({"b_whirl_ratio": 0.0, "b_whirl_frequency": 640.0}, 640.0)]:
        sys_nu = system.with_parameters(**given)
        y = sys_nu.initial_state(x1=1e-3)
        ax = sys_nu.rhs(0.0, y)[sys_nu.state_index("x1_dot")]
        assert ax == pytest.approx(-(K0 + A * nu) * 1e-3 / m, rel=1e-12)


def test_campbell_with_speed_and_frequency_grid_closed_form():
    """k(W, nu) = K0 + A nu + B W (exact on a 2 x 2 bilinear grid continued linearly): m w^2 = k(W, w)."""
    m, b = 2.0, 800.0
    grid = [[K0 + b * W + A * nu for nu in (0.0, 1000.0)] for W in (0.0, 500.0)]
    bearing = LinearBearing.frequency_table(station=1, speeds=[0.0, 500.0], frequencies=[0.0, 1000.0], kxx=grid,
                                            kyy=grid, extrapolation="linear")
    model = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=m), bearing])
    speeds = [0.0, 250.0, 700.0]
    diagram = matched_whirl_campbell(model, speeds, n_modes=2)
    expected = [(A + math.sqrt(A * A + 4 * m * (K0 + b * W))) / (2 * m) for W in speeds]
    assert diagram.converged.all()
    np.testing.assert_allclose(diagram.frequencies, np.column_stack([expected, expected]), rtol=1e-9)
    lines = diagram.plot()
    assert len(lines) == 2
