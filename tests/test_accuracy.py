"""The accuracy study: error measures on known differences, a small study end to end."""

import numpy as np
import pytest

import rotorkit as rk
from rotorkit import accuracy
from rotorkit.result import Result


def fake(t, x2, torsion):
    y = np.vstack([x2, torsion, np.zeros_like(t)])
    return Result(t=t, y=y, state_names=("x2", "alpha2", "alpha5"))


def test_error_measures_on_known_signals():
    t = np.arange(0, 4.0, 1e-4)
    ref = fake(t, 1e-4 * np.sin(1500 * t), 2e-5 * np.sin(1200 * t))
    # a 1 % amplitude error and a small constant offset (removed by the high-pass before the spectrum)
    res = fake(t, 1.01e-4 * np.sin(1500 * t) + 1e-6, 2e-5 * np.sin(1200 * t))
    pointwise, spectral = accuracy.errors(res, ref, ("x2", "alpha2-alpha5"), (2.2, 3.8))
    assert pointwise["x2"] == pytest.approx(0.01 + 1e-6 / 1e-4, rel=0.05)
    assert spectral["x2"] == pytest.approx(0.01, rel=0.02)
    assert pointwise["alpha2-alpha5"] == 0.0 and spectral["alpha2-alpha5"] == 0.0


def test_errors_need_the_same_samples():
    t = np.arange(0, 1.0, 1e-3)
    with pytest.raises(rk.ParameterError, match="same sample times"):
        accuracy.errors(fake(t, t, t), fake(t + 1e-3, t, t), ("x2",), (0.2, 0.8))


def test_small_study_errors_shrink_with_tolerance():
    model = rk.Model([rk.Rotor(name="R", stations=(2,), speed=150.0),
                      rk.Disk(station=2, mass=1.0, radius=0.1, eccentricity=1e-4),
                      rk.ElasticSupport(station=2, stiffness=1e4, damping=20.0),
                      rk.RubStator(station=2, clearance=1.2e-4, contact_stiffness=1e5, friction_coefficient=0.1)])
    system = model.compile()
    # a sound rubbing orbit (about 0.22 mm, in contact most of the time), not a run-away
    runs, _ = accuracy.study(system, (0.0, 1.0), cases=(("scipy", "RK45"),), tolerances=(1e-4, 1e-7),
                             signals=("x2",), window=(0.5, 1.0))
    assert [r.rtol for r in runs] == [1e-4, 1e-7] and all(r.success for r in runs)
    loose, tight = runs
    assert tight.pointwise["x2"] < loose.pointwise["x2"] / 10
    assert tight.spectral["x2"] < loose.spectral["x2"]
    assert tight.nfev > loose.nfev
    rows = accuracy.to_rows(runs, ("x2",))
    assert set(rows[0]) >= {"engine", "method", "rtol", "wall_time", "pointwise_x2", "spectral_x2"}
