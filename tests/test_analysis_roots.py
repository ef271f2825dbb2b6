"""rotorkit.analysis.roots against scipy.optimize (brentq, linear_sum_assignment) on the same problems."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq, linear_sum_assignment

from rotorkit.analysis.roots import assignment, brent
from rotorkit.errors import ParameterError

FUNCTIONS = [
    (lambda x: x**2 - 2.0, 0.0, 2.0),
    (lambda x: math.cos(x) - x, 0.0, 1.0),
    (lambda x: x**3 - 2 * x - 5, 2.0, 3.0),
    (lambda x: math.exp(x) - 1e3, 0.0, 20.0),
    (lambda x: (x - 0.3) ** 3, -1.0, 2.0),  # a triple root: slow interpolation, bisection steps
    (lambda x: math.tanh(50 * (x - 0.7)), 0.0, 1.0),
    (lambda x: 1e-12 * (x - 400.0), 0.0, 1600.0),
]


@pytest.mark.parametrize("f, a, b", FUNCTIONS)
@pytest.mark.parametrize("xtol", [1e-12, 1e-6])
def test_brent_finds_the_root_of_brentq(f, a, b, xtol):
    ours, theirs = brent(f, a, b, xtol=xtol, maxiter=500), brentq(f, a, b, xtol=xtol, maxiter=500)
    assert abs(ours - theirs) <= 2 * xtol + 4e-15 * abs(theirs)


def test_brent_stops_like_brentq_on_a_slow_root():
    """A triple root needs more than 100 iterations at xtol 1e-12 in either implementation."""
    with pytest.raises(RuntimeError):
        brentq(lambda x: (x - 0.3) ** 3, -1.0, 2.0, xtol=1e-12)
    with pytest.raises(ValueError, match="no convergence"):
        brent(lambda x: (x - 0.3) ** 3, -1.0, 2.0, xtol=1e-12)


def test_brent_refuses_a_bracket_without_a_sign_change():
    with pytest.raises(ValueError, match="different signs"):
        brent(lambda x: x * x + 1.0, -1.0, 1.0)


@pytest.mark.parametrize("shape", [(1, 1), (3, 3), (4, 9), (9, 4), (6, 160), (12, 12)])
@pytest.mark.parametrize("seed", range(5))
def test_assignment_is_the_minimum_of_linear_sum_assignment(shape, seed):
    cost = np.random.default_rng(seed).random(shape)
    rows, cols = assignment(cost)
    r2, c2 = linear_sum_assignment(cost)
    assert rows == sorted(rows) and len(set(cols)) == len(cols) == min(shape)
    assert cost[rows, cols].sum() == pytest.approx(cost[r2, c2].sum(), rel=1e-14)
    assert (rows, cols) == (r2.tolist(), c2.tolist())  # unique optimum of random costs


def test_assignment_refuses_bad_costs():
    with pytest.raises(ParameterError, match="NaN"):
        assignment([[1.0, np.nan]])
    with pytest.raises(ParameterError, match="2-D"):
        assignment([1.0, 2.0])
