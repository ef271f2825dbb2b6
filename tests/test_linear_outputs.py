"""Tables, CSV files, figures and the stability verdict of the linear analyses.

- An undamped rotor has log decrements that are rounding noise (+-1e-13):
  no instability onset is reported (a tolerance scaled to the problem,
  :func:`rotorkit.analysis.campbell.neutral_tolerance`), while a real
  negative log decrement still is.
- ``n_modes`` returns exactly that many modes, dense or sparse solve.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit.analysis.campbell import campbell, neutral_tolerance
from rotorkit.analysis.linear_model import LinearModel


def undamped_chain(n=12, damping=0.0, cross=0.0):
    """A free-free chain of ``n`` tilting stations on two end springs, gyroscopic at each station (48 coordinates).

    ``cross``: a cross-coupled stiffness at the first station (destabilises the forward modes with speed).
    """
    names = []
    for s in range(1, n + 1):
        names += [f"x{s}", f"y{s}", f"thx{s}", f"thy{s}"]
    N = 4 * n
    rng = np.random.default_rng(3)
    M = np.diag(rng.uniform(0.5, 2.0, N))
    M[2::4, 2::4] *= 1e-3
    M[3::4, 3::4] *= 1e-3
    K = np.zeros((N, N))
    for i in range(N - 4):
        k = rng.uniform(1e5, 1e7)
        K[i, i] += k
        K[i + 4, i + 4] += k
        K[i, i + 4] -= k
        K[i + 4, i] -= k
    for i in (0, 1, N - 4, N - 3):
        K[i, i] += 1e6
    K[2::4, 2::4] += np.eye(n) * 1e3
    K[3::4, 3::4] += np.eye(n) * 1e3
    K[0, 1], K[1, 0] = cross, -cross
    G = np.zeros((N, N))
    for s in range(n):
        G[4 * s + 2, 4 * s + 3], G[4 * s + 3, 4 * s + 2] = 2e-3, -2e-3
    return LinearModel(mass=M, damping=damping * np.eye(N), stiffness=K, gyroscopic=G, coordinate_names=tuple(names),
                       rotor_speeds={"R": (0.0, 1.0)}, station_rotors={str(s): "R" for s in range(1, n + 1)},
                       speed_parameter="R_speed")


def test_undamped_rotor_reports_no_instability_onset():
    diagram = campbell(undamped_chain(), np.linspace(0.0, 1000.0, 5), n_modes=6)
    noise = np.abs(diagram.log_decrements)
    assert np.all(noise < 1e-9) and np.any(diagram.log_decrements != 0.0)  # rounding noise of either sign
    assert np.all(noise <= diagram.neutral_log_decrements)
    assert diagram.onsets == ()
    assert diagram.instability_onset is None


def test_a_real_instability_is_still_reported():
    diagram = campbell(undamped_chain(damping=1e-3, cross=-3e4), np.linspace(0.0, 1000.0, 5), n_modes=6)
    assert diagram.instability_onset is not None
    assert np.any(diagram.log_decrements < -10 * diagram.neutral_log_decrements)


def test_neutral_tolerance_scales_with_the_spectral_radius():
    lam = np.array([1e-12 + 100j, -1e-12 + 100j])
    assert neutral_tolerance(lam, 1e3).tolist() == [1e-8, 1e-8]  # the floor
    big = neutral_tolerance(lam, 1e8)  # a stiff model: high modes 1e6 x the low ones
    np.testing.assert_allclose(big, 2 * np.pi * 1e3 * np.finfo(float).eps * 1e8 / 100)


@pytest.mark.parametrize("count", [1, 3, 8, 20])
def test_linear_model_modes_returns_n_modes(count):
    model = undamped_chain(damping=0.1)
    assert len(model.modes(0.0, n_modes=count)) == count  # 2 n > 4 count + 20: sparse solve
    assert len(model.modes(300.0, n_modes=count, left=False)) == count
    small = undamped_chain(n=3, damping=0.1)  # dense solve
    assert len(small.modes(0.0, n_modes=min(count, 12))) == min(count, 12)
