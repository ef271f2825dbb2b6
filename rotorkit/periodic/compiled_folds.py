"""numba kernel part of the compiled harmonic-balance path: the grazing fold's location in one call.

:func:`grazing_value` repeats, operation for operation, :func:`rotorkit.periodic.folds.grazing_point` (the
Python reference, which the compiled path's small calls serve one Newton solve or one switch evaluation at a
time): the two pieces around the corner ordered by their nearest point's penetration, each followed to zero
penetration by inverse interpolation in the gap (``_piece_to_grazing``, ``_step_on_piece``), with the same
Newton solves (:func:`~rotorkit.periodic.compiled_newton.solve_fixed`) and the same contact switches
(:func:`~rotorkit.periodic.compiled_aft.switches_of`). A piece's points are kept in a window of at most three
(gap, parameter, coefficients), oldest first, as the reference's list ``points[-3:]``.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .compiled_aft import same_state, switches_of
from .compiled_newton import solve_fixed

__all__ = ["grazing_value"]


@numba.njit(cache=False)
def _larger(a, b):
    """Python's ``max(a, b)``: ``b`` only if ``b > a``."""
    return b if b > a else a


@numba.njit(cache=False)
def _smaller(a, b):
    """Python's ``min(a, b)``: ``b`` only if ``b < a``."""
    return b if b < a else a


@numba.njit(cache=False)
def _interpolate(pg, pl, pz, start, stop, g, want, z):
    """The reference's ``_interpolate`` through the window's points ``start ... stop - 1``: the parameter at gap
    ``g`` (returned) and, if ``want``, the coefficients into ``z``."""
    w = np.empty(3)
    for a in range(start, stop):
        v = 1.0
        for b in range(start, stop):
            if b != a:
                v *= (g - pg[b]) / (pg[a] - pg[b])
        w[a] = v
    lam = 0.0
    for a in range(start, stop):
        lam += w[a] * pl[a]
    if want:
        for i in range(z.shape[0]):
            z[i] = w[start] * pz[start, i]
        for a in range(start + 1, stop):
            for i in range(z.shape[0]):
                z[i] += w[a] * pz[a, i]
    return lam


@numba.njit(cache=False)
def _step_on_piece(pg, pl, pz, count, aim, state, size, tries, found_z, rhs, jac, sw, ints, fl, E, P, ED, M, base,
                   varying, coef, window, ws):
    """The reference's ``_step_on_piece``: ``(found, gap, parameter)``, the coefficients into ``found_z``."""
    g_b = pg[count - 1]
    start = max(count - 3, 0)
    st = np.zeros(max(ints[4], 1), dtype=np.bool_)
    for _ in range(tries):
        l_c = _interpolate(pg, pl, pz, start, count, aim, True, found_z)
        if not math.isfinite(l_c):
            return False, 0.0, 0.0
        ok = solve_fixed(found_z, l_c, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws)[0]
        if ok:
            g_c = switches_of(found_z, l_c, st, rhs, jac, sw, ints, fl, E, ED, M, base, varying, coef, window)
            if g_c != pg[count - 2] and g_c != pg[count - 1] and (abs(g_c) <= 1e-6 * size or same_state(st, state)):
                return True, g_c, l_c
        aim = 0.5 * (aim + g_b)
    return False, 0.0, 0.0


@numba.njit(cache=False)
def _piece_to_grazing(pg, pl, pz, count, state, steps, tries, rhs, jac, sw, ints, fl, E, P, ED, M, base, varying,
                      coef, window, ws):
    """The reference's ``_piece_to_grazing`` from the window's ``count`` (2 or 3) points: ``(value,
    converged)``."""
    size = abs(pg[0])
    for k in range(1, count):
        size = _larger(size, abs(pg[k]))
    z_c = np.empty(pz.shape[1])
    for _ in range(steps):
        g_b, l_b = pg[count - 1], pl[count - 1]
        if abs(g_b) <= 1e-9 * size or pg[count - 2] == g_b:
            break
        if count >= 3:
            linear = _interpolate(pg, pl, pz, count - 2, count, 0.0, False, z_c)
            quadratic = _interpolate(pg, pl, pz, count - 3, count, 0.0, False, z_c)
            slope = (g_b - pg[count - 2]) / (l_b - pl[count - 2]) if l_b != pl[count - 2] else 0.0
            error = 2.0 * abs(slope * (quadratic - linear))
            aim = math.copysign(_smaller(0.5 * abs(g_b), _larger(error, 1e-12 * size)), g_b)
        else:
            aim = 0.01 * g_b
        found, g_c, l_c = _step_on_piece(pg, pl, pz, count, aim, state, size, tries, z_c, rhs, jac, sw, ints, fl, E,
                                         P, ED, M, base, varying, coef, window, ws)
        if not found:
            break
        if count == 3:  # points = [*points[-2:], found]
            for k in range(2):
                pg[k], pl[k] = pg[k + 1], pl[k + 1]
                pz[k] = pz[k + 1]
            count = 2
        pg[count], pl[count] = g_c, l_c
        pz[count] = z_c
        count += 1
    converged = abs(pg[count - 1]) <= 1e-9 * size
    if pg[count - 1] == pg[count - 2]:
        return pl[count - 1], converged
    return _interpolate(pg, pl, pz, max(count - 3, 0), count, 0.0, False, z_c), converged


@numba.njit(cache=False)
def grazing_value(points, valid, steps, tries, rhs, jac, sw, ints, fl, E, P, ED, M, base, varying, coef, window,
                  ws):
    """:func:`rotorkit.periodic.folds.grazing_point` between the branch's points ``i`` and ``i + 1``:
    ``points`` (6, size + 1) the points ``i - 2 ... i + 3`` (coefficients, then the parameter), ``valid`` which
    of them exist; Newton at tolerance ``fl[9]`` in at most ``ints[5]`` iterations, ``steps`` steps per piece,
    ``tries`` aims per step."""
    size = points.shape[1] - 1
    ns = max(ints[4], 1)
    pieces = ((0, 1, 2), (5, 4, 3))
    keys = np.empty(2)
    single = np.empty(2, dtype=np.bool_)
    st = np.zeros(ns, dtype=np.bool_)
    for k in range(2):
        near = pieces[k][2]
        single[k] = not valid[pieces[k][1]]
        keys[k] = abs(switches_of(points[near, :size], points[near, size], st, rhs, jac, sw, ints, fl, E, ED, M, base,
                                  varying, coef, window))
    first = 0  # sorted(..., key=(single, |gap|)): stable, the second piece first only if its key is smaller
    if (single[0] and not single[1]) or (single[1] == single[0] and keys[1] < keys[0]):
        first = 1
    total = 0.0
    count = 0
    state = np.zeros(ns, dtype=np.bool_)
    pg, pl, pz = np.empty(3), np.empty(3), np.empty((3, size))
    for k in range(2):
        far, mid, near = pieces[first if k == 0 else 1 - first]
        if not valid[mid]:
            total += points[near, size]
            count += 1
            continue
        g_near = switches_of(points[near, :size], points[near, size], state, rhs, jac, sw, ints, fl, E, ED, M, base,
                             varying, coef, window)
        g_mid = switches_of(points[mid, :size], points[mid, size], st, rhs, jac, sw, ints, fl, E, ED, M, base,
                            varying, coef, window)
        n_points = 0
        if valid[far]:
            g_far = switches_of(points[far, :size], points[far, size], st, rhs, jac, sw, ints, fl, E, ED, M, base,
                                varying, coef, window)
            if same_state(st, state) and g_far != g_mid and g_far != g_near:
                pg[0], pl[0] = g_far, points[far, size]
                pz[0] = points[far, :size]
                n_points = 1
        for g, row in ((g_mid, mid), (g_near, near)):
            pg[n_points], pl[n_points] = g, points[row, size]
            pz[n_points] = points[row, :size]
            n_points += 1
        value, converged = _piece_to_grazing(pg, pl, pz, n_points, state, steps, tries, rhs, jac, sw, ints, fl, E, P,
                                             ED, M, base, varying, coef, window, ws)
        total += value
        count += 1
        if converged:
            break
    return total if count == 1 else total / count
