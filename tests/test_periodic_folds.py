"""The smooth fold's location (rotorkit.periodic.folds.turning_point): the vertex of the parabola lambda(s)
through three points, s their arclength (amplitudes over the largest, the parameter over its range)."""

import math

import numpy as np
import pytest

from rotorkit.periodic.folds import turning_point


def points_on_parabola(s, vertex, curvature, s_vertex):
    """Three points whose arclength steps are exactly the steps of ``s`` and whose parameter is the parabola
    ``vertex - curvature (s - s_vertex)^2``: one coefficient, 1 at the first point and falling, so that the
    amplitude scale is 1 and each step's amplitude part is what the parameter part leaves of it."""
    lam = vertex - curvature * (np.asarray(s) - s_vertex) ** 2
    width = float(np.ptp(lam))
    Z = [1.0]
    for k in range(len(s) - 1):
        h = s[k + 1] - s[k]
        d = (lam[k + 1] - lam[k]) / width
        Z.append(Z[-1] - math.sqrt(h * h - d * d))
    Z = np.array(Z).reshape(-1, 1, 1)
    assert np.max(np.abs(Z)) == 1.0
    return lam, Z


@pytest.mark.parametrize("s, s_vertex", [((0.0, 1.0, 2.5), 1.2), ((0.0, 1.0, 2.2), 0.8), ((0.0, 1.2, 2.4), 0.9)])
def test_vertex_of_a_parabola_in_the_arclength(s, s_vertex):
    lam, Z = points_on_parabola(s, 150.0, 0.5, s_vertex)
    i = 0 if lam[1] > lam[0] else 1  # the fold between the two points around the vertex
    assert turning_point(lam, Z, i) == pytest.approx(150.0, rel=1e-12, abs=0.0)


def test_vertex_as_numpys_least_squares_parabola():
    """Points of an irregular branch: the vertex of numpy's degree-2 fit through the same three points."""
    rng = np.random.default_rng(3)
    lam = np.array([100.0, 104.0, 105.1, 104.2, 101.0])
    Z = rng.standard_normal((5, 3, 2)) * 1e-4
    i = 1  # turns between points 2 and 3; the three nearest the extreme: 1, 2, 3
    j = [1, 2, 3]
    size, width = np.max(np.abs(Z)), np.ptp(lam)
    steps = [np.sqrt(np.sum(((Z[b] - Z[a]) / size) ** 2) + ((lam[b] - lam[a]) / width) ** 2) for a, b in
             zip(j, j[1:])]
    a, b, c = np.polyfit(np.concatenate([[0.0], np.cumsum(steps)]), lam[j], 2)
    assert turning_point(lam, Z, i + 1) == pytest.approx(c - b * b / (4 * a), rel=1e-12)


def test_a_straight_line_gives_the_farther_point():
    lam = np.array([100.0, 101.0, 102.0])
    Z = np.array([0.0, 1.0, 2.0]).reshape(-1, 1, 1)
    assert turning_point(lam, Z, 1) == 102.0
