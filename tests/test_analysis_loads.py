"""Manoeuvre load on a station against MODEL_NOTES eq. 18."""

import math

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.analysis.loads import maneuver_load


def test_barrel_roll_load_on_disk_2_matches_eq_18():
    t = np.linspace(0.0, 6.0, 601)
    load = maneuver_load(rk.preset("al31f"), 2, t)
    m, w, R, g = 10.0, math.pi, 3.0, 9.81
    theta = w * np.clip(t - 2.0, 0.0, 2.0)
    inside = ((t >= 2.0) & (t < 4.0)).astype(float)
    np.testing.assert_allclose(load.fx, m * (inside * w**2 * R * np.cos(theta) - g * np.sin(2 * theta)), atol=1e-9)
    np.testing.assert_allclose(load.fy, m * (-inside * w**2 * R * np.sin(theta) - g * np.cos(2 * theta)), atol=1e-9)
    assert load.fy[0] == pytest.approx(-m * g) and load.fy[-1] == pytest.approx(-m * g)  # gravity before and after
    assert load.magnitude.max() > m * g * 2  # the roll adds about m w^2 R = 296 N
    assert len(load.plot().lines) == 3


def test_errors():
    with pytest.raises(rk.ParameterError, match="no Maneuver"):
        maneuver_load(rk.Model([rk.Rotor(name="R", stations=(1,), speed=1.0), rk.LumpedMass(station=1, mass=1.0),
                                rk.ElasticSupport(station=1, stiffness=1.0)]), 1, [0.0])
    with pytest.raises(rk.ParameterError, match="station 9"):
        maneuver_load(rk.preset("al31f"), 9, [0.0])
