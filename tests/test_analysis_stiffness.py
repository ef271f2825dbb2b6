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
    system = two_mass(1e10)
    with pytest.warns(RuntimeWarning, match="method='Radau'"):
        rk.simulate(system, (0.0, 1e-4), y0=system.initial_state(x1=1e-3), sample_rate=1e5)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rk.simulate(two_mass(1e3), (0.0, 1e-2), y0=two_mass(1e3).initial_state(x1=1e-3))
