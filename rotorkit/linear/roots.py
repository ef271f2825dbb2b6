"""Two small numeric tools of the linear analyses, without scipy.optimize's import (about 0.7 s of a fresh
process that only wants a Campbell diagram): Brent's root finder and the linear assignment of tracked modes.

>>> round(brent(lambda x: x * x - 2.0, 0.0, 2.0, xtol=1e-12), 12)
1.414213562373
>>> assignment([[4.0, 1.0, 3.0], [2.0, 0.0, 5.0]])
([0, 1], [1, 0])
"""

import math

import numpy as np

from ..errors import ParameterError

__all__ = ["brent", "assignment"]


def brent(f, a, b, *, xtol=2e-12, rtol=8.881784197001252e-16, maxiter=100):
    """A root of ``f`` in ``[a, b]`` (``f(a)``, ``f(b)`` of opposite signs) by Brent's method.

    Inverse quadratic interpolation and secant steps, with bisection whenever they do not shrink the
    bracket fast enough (R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 4);
    the tolerance is scipy's ``brentq`` convention, ``2 (xtol + rtol |x|)`` on the bracket.

    Raises
    ------
    ValueError
        ``f(a)`` and ``f(b)`` have the same sign (as :func:`scipy.optimize.brentq`).
    """
    fa, fb = f(a), f(b)
    if fa == 0:
        return a
    if fb == 0:
        return b
    if (fa > 0) == (fb > 0):
        raise ValueError("f(a) and f(b) must have different signs")
    c, fc = a, fa
    d = e = b - a
    for _ in range(int(maxiter)):
        if (fb > 0) == (fc > 0):  # keep the root between b and c
            c, fc = a, fa
            d = e = b - a
        if abs(fc) < abs(fb):  # b is the best estimate
            a, b, c = b, c, b
            fa, fb, fc = fb, fc, fb
        tol = 0.5 * (xtol + rtol * abs(b))
        m = 0.5 * (c - b)
        if abs(m) <= tol or fb == 0:
            return b
        if abs(e) >= tol and abs(fa) > abs(fb):
            s = fb / fa
            if a == c:  # secant
                p, q = 2.0 * m * s, 1.0 - s
            else:  # inverse quadratic interpolation
                q, r = fa / fc, fb / fc
                p = s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0))
                q = (q - 1.0) * (r - 1.0) * (s - 1.0)
            if p > 0:
                q = -q
            p = abs(p)
            if 2.0 * p < min(3.0 * m * q - abs(tol * q), abs(e * q)):
                e, d = d, p / q
            else:
                d = e = m
        else:
            d = e = m
        a, fa = b, fb
        b += d if abs(d) > tol else math.copysign(tol, m)
        fb = f(b)
    raise ValueError(f"brent: no convergence in {maxiter} iterations")


def assignment(cost):
    """``(rows, cols)`` of the minimum-cost assignment of a rectangular cost matrix (as scipy's
    :func:`~scipy.optimize.linear_sum_assignment`): every row of the shorter side gets one distinct column.

    The shortest-augmenting-path Hungarian algorithm with potentials (Kuhn-Munkres, ``O(n^2 m)`` for
    ``n <= m``): exact, for the few tracked modes of a Campbell diagram against the modes of one speed.
    """
    a = np.asarray(cost, dtype=float)
    if a.ndim != 2:
        raise ParameterError(f"cost has shape {a.shape}: expected a 2-D matrix")
    if not np.all(np.isfinite(a)):
        raise ParameterError("cost holds NaN or infinite entries")
    if a.shape[0] > a.shape[1]:
        cols, rows = assignment(a.T)
        order = np.argsort(rows)
        return [int(rows[i]) for i in order], [int(cols[i]) for i in order]
    n, m = a.shape
    u, v = np.zeros(n + 1), np.zeros(m + 1)
    owner = np.zeros(m + 1, dtype=int)  # owner[j]: row (1-based) assigned to column j, 0 for none
    way = np.zeros(m + 1, dtype=int)
    padded = np.zeros((n + 1, m + 1))
    padded[1:, 1:] = a
    for i in range(1, n + 1):
        owner[0], j0 = i, 0
        minv = np.full(m + 1, np.inf)
        used = np.zeros(m + 1, dtype=bool)
        while True:
            used[j0] = True
            i0 = owner[j0]
            free = ~used
            free[0] = False
            cur = padded[i0] - u[i0] - v
            better = free & (cur < minv)
            minv[better] = cur[better]
            way[better] = j0
            candidates = np.where(free, minv, np.inf)
            j1 = int(np.argmin(candidates))
            delta = candidates[j1]
            u[owner[used]] += delta
            v[used] -= delta
            minv[free] -= delta
            j0 = j1
            if owner[j0] == 0:
                break
        while j0:
            j1 = way[j0]
            owner[j0] = owner[j1]
            j0 = j1
    pairs = sorted((int(owner[j]) - 1, j - 1) for j in range(1, m + 1) if owner[j])
    return [r for r, _ in pairs], [c for _, c in pairs]
