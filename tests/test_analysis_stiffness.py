"""Stiffness scan from the analytic Jacobian."""

import warnings

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.analysis.stiffness import stiffness_report


def test_preset_is_oscillatory_not_stiff():
    """MODEL_NOTES: fastest time scale about 80 us, stiffness ratio about 40 at the paper's values."""
    system = rk.preset("al31f").compile()
    report = stiffness_report(system, rk.simulate(system, (0.0, 0.2), sample_rate=2000.0))
    assert 40e-6 < report.fastest_time_scale < 160e-6
    assert 20 < report.ratio < 80
    assert report.suggested_method == "DOP853"


def two_mass(k_stiff):
    return rk.Model([rk.Rotor(name="R", stations=(1, 2), speed=0.0),
                     rk.LumpedMass(station=1, mass=1.0), rk.LumpedMass(station=2, mass=1.0),
                     rk.ElasticSupport(station=1, stiffness=100.0, damping=1.0),
                     rk.ShaftSegment(start=1, end=2, bending_stiffness=k_stiff)]).compile()


def test_closed_form_time_scales():
    """Two unit masses: support k = 100, link K: modes sqrt(k (..)) -> ratio known in closed form."""
    K = 1e10
    report = stiffness_report(two_mass(K))
    w_fast = np.sqrt(2 * K + 100)  # out-of-phase mode, approximately
    assert report.fastest_time_scale == pytest.approx(1 / w_fast, rel=1e-3)
    assert report.ratio > 1e3 and report.suggested_method == "Radau"


def test_explicit_run_of_a_stiff_scene_warns_with_the_fix():
    """K = 1e12 between unit masses: |lambda| = sqrt(2e12), DOP853 steps <= 3.3/1.41e6 = 2.3 us, 850 per 2 ms
    output interval, 1.3e4 over the span: an explicit run is held by a time scale the output never sees."""
    system = two_mass(1e12)
    with pytest.warns(RuntimeWarning, match=r"steps of about 2\.3\de-06 s.*method='Radau'"):
        rk.simulate(system, (0.0, 0.03), y0=system.initial_state(x1=1e-6), sample_rate=500.0)


def test_no_warning_when_the_fastest_scale_is_resolved_anyway():
    """The same scene sampled at 1 MHz: the output resolves the fast scale, an implicit method would not help."""
    system = two_mass(1e12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rk.simulate(system, (0.0, 2e-4), y0=system.initial_state(x1=1e-6), sample_rate=1e6)
        rk.simulate(two_mass(1e3), (0.0, 1e-2), y0=two_mass(1e3).initial_state(x1=1e-3))


def test_a_very_slow_time_scale_is_not_stiffness():
    """A mass floating on a support of 1e-3 N/m (time scale ~30 s) beside an ordinary 1e5 N/m link: the
    stiffness ratio is huge (the old check warned), yet nothing limits the explicit step below the output."""
    system = rk.Model([rk.Rotor(name="R", stations=(1, 2), speed=0.0),
                       rk.LumpedMass(station=1, mass=1.0), rk.LumpedMass(station=2, mass=1.0),
                       rk.ElasticSupport(station=1, stiffness=1e-3),
                       rk.ShaftSegment(start=1, end=2, bending_stiffness=1e5)]).compile()
    assert stiffness_report(system).ratio > 1e3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rk.simulate(system, (0.0, 2.0), y0=system.initial_state(x1=1e-3), sample_rate=1000.0)


def test_fastest_rate_of_a_large_system_without_a_full_eigenproblem(monkeypatch):
    """Above DENSE_EIG_STATES states the spectral radius comes from ARPACK and agrees with the full problem."""
    from rotorkit.analysis import stiffness

    rng = np.random.default_rng(1)
    n = 150  # 300 states: a lumped chain's first-order form
    K = np.diag(np.full(n, 2.0)) - np.diag(np.ones(n - 1), 1) - np.diag(np.ones(n - 1), -1)
    K *= 1e6 * (1 + rng.random(n))[:, None]
    J = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -1e-3 * K]])
    exact = np.abs(np.linalg.eigvals(J)).max()
    monkeypatch.setattr(np.linalg, "eigvals", lambda *a: (_ for _ in ()).throw(AssertionError("full eig")))
    assert stiffness.fastest_rate(J) == pytest.approx(exact, rel=1e-3)
