"""The continuation predictor's quadratic and cubic terms (rotorkit.periodic.continuation) on a closed-form curve.

A circle of radius ``r`` traced by arclength, ``u(s) = r (cos(s/r), sin(s/r))`` with the unit tangent
``t(s) = (-sin(s/r), cos(s/r))``: from the points at ``s = -d1 - d2, -d1, 0`` (their tangents as the corrector
gives them) a step ``h`` predicts ``u(0) + h t(0) + h^2 a`` (``a`` the quadratic term), plus ``h^2 b d1 / 2 +
h^3 b / 3`` with the cubic term ``b``. The first errs by O(h^3), the second by O(h^4): halving every step divides
their errors by 8 and by 16. The compiled kernel's predictor is the same (tests/test_periodic_compiled.py
compares the branches point by point).
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit.periodic.continuation import _cubic, _curvature

R = 0.7


def u(s):
    return R * np.array([np.cos(s / R), np.sin(s / R)])


def t(s):
    return np.array([-np.sin(s / R), np.cos(s / R)])


def errors(d1, d2, h):
    curve = _curvature(u(-d1), u(0.0), t(0.0), t(-d1))
    b, d = _cubic(u(-d1 - d2), t(-d1 - d2), u(-d1), t(-d1), u(0.0), t(0.0))
    quadratic = u(0.0) + h * t(0.0) + h * h * curve
    cubic = quadratic + h * h * b * d / 2.0 + h * h * h * b / 3.0
    return np.linalg.norm(quadratic - u(h)), np.linalg.norm(cubic - u(h))


@pytest.mark.parametrize("d1, d2, h", [(0.1, 0.08, 0.12), (0.05, 0.1, 0.075), (0.1, 0.1, 0.05)])
def test_the_cubic_term_raises_the_predictors_order(d1, d2, h):
    (q1, c1), (q2, c2) = errors(d1, d2, h), errors(d1 / 2, d2 / 2, h / 2)
    assert q1 / q2 == pytest.approx(8.0, rel=0.1)  # O(h^3) without the cubic term
    assert c1 / c2 == pytest.approx(16.0, rel=0.1)  # O(h^4) with it
    assert c1 < 0.3 * q1


def test_the_cubic_term_of_a_straight_line_is_zero():
    """Tangents all alike (a straight branch): no quadratic and no cubic term."""
    direction = np.array([0.6, 0.8])
    b, d = _cubic(-0.3 * direction, direction, -0.1 * direction, direction, 0.2 * direction, direction)
    assert np.array_equal(b, np.zeros(2)) and d == pytest.approx(0.3, rel=1e-15)
