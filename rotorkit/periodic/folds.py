"""Where a branch turns: the smooth fold (a turning point of the parameter) and the grazing fold of contact.

:func:`turning_point` places a smooth fold at the vertex of the parabola through the points around it.
:func:`grazing_point` places the corner where a branch of a contact problem turns back because an orbit just
grazes (some contact switch active on one side, none on the other): the grazing orbit lies on both pieces, and
one piece is followed to zero penetration by inverse interpolation in the gap, each Newton solve aimed short of
the corner so that none is wasted past it (where the piece has no solution).
"""

from __future__ import annotations

import math

import numpy as np

from .errors import ConvergenceError

__all__ = ["grazing_point", "turning_point"]

#: the Newton solves on a piece: tolerance and iterations
#: (:meth:`~rotorkit.periodic.continuation.ContinuationProblem.solve`)
SOLVE_TOL, SOLVE_ITERATIONS = 1e-10, 20
#: steps along a piece towards the grazing (:func:`_piece_to_grazing`), aims per step (:func:`_step_on_piece`)
PIECE_STEPS, STEP_TRIES = 10, 30


def grazing_point(problem, lam, Z, i, *, compiled=True):
    """The parameter where the branch grazes between points ``i`` and ``i + 1`` (on two pieces: some contact
    switch is active at some instant on one side and at none on the other).

    The grazing orbit lies on both pieces. The piece whose point nearest the corner penetrates least is
    followed to it by :func:`_piece_to_grazing` from its points nearest the corner (two, or three where the
    third has the same contact state); only if that does not converge is the other piece followed too, and the
    two values averaged (a piece with a single point, at an end of the branch, comes last and gives that
    point's value).

    Where the compiled path applies (:mod:`rotorkit.periodic.fastpath`) the same steps run in one kernel call
    (:func:`rotorkit.periodic.fastpath.grazing_compiled`) unless ``compiled`` is False; the code here is the
    reference.
    """
    if compiled:
        from .fastpath import grazing_compiled

        found = grazing_compiled(problem, lam, Z, i, tol=SOLVE_TOL, max_iterations=SOLVE_ITERATIONS,
                                 steps=PIECE_STEPS, tries=STEP_TRIES)
        if found is not None:
            return found
    pieces = []
    for piece in ((i - 2, i - 1, i), (i + 3, i + 2, i + 1)):
        near = piece[2]
        single = not 0 <= piece[1] < len(lam)
        pieces.append((single, abs(problem.gap(np.ravel(Z[near]), lam[near])), piece))
    estimates = []
    for _, _, (far, mid, near) in sorted(pieces, key=lambda p: p[:2]):
        if not 0 <= mid < len(lam):
            estimates.append(float(lam[near]))
            continue
        z_near, z_mid = np.ravel(Z[near]), np.ravel(Z[mid])
        state = problem.contact_state(z_near, lam[near])
        g_near = problem.gap(z_near, lam[near])
        known = [(problem.gap(z_mid, lam[mid]), float(lam[mid]), z_mid)]
        if 0 <= far < len(lam):
            z_far = np.ravel(Z[far])
            g_far = problem.gap(z_far, lam[far])
            if np.array_equal(problem.contact_state(z_far, lam[far]), state) and g_far not in (known[0][0], g_near):
                known.insert(0, (g_far, float(lam[far]), z_far))
        known.append((g_near, float(lam[near]), z_near))
        value, converged = _piece_to_grazing(problem, known, state)
        estimates.append(value)
        if converged:
            break
    return float(np.mean(estimates))


def _interpolate(points, g, coefficients=True):
    """``(lambda, z)`` at gap ``g`` along a piece: the polynomial in the gap through ``points`` (``(gap,
    lambda, z)``; inverse interpolation: smooth through a smooth fold of the parameter, too); ``z`` None unless
    ``coefficients``."""
    weights = []
    for a, (ga, _, _) in enumerate(points):
        w = 1.0
        for b, (gb, _, _) in enumerate(points):
            if b != a:
                w *= (g - gb) / (ga - gb)
        weights.append(w)
    lam = sum(w * la for w, (_, la, _) in zip(weights, points))
    if not coefficients:
        return lam, None
    z = weights[0] * points[0][2]
    for w, (_, _, za) in zip(weights[1:], points[1:]):
        z += w * za
    return lam, z


def _piece_to_grazing(problem, points, state, iterations=PIECE_STEPS):
    """The parameter where the penetration along one piece is zero.

    ``points``: ``(gap, lambda, z)`` of two or three solutions on the piece, in order towards the corner;
    ``state`` the piece's contact state. The parameter and the coefficients are interpolated as polynomials
    in the gap (:func:`_interpolate`, the last three points). Each step aims at a gap of the piece's own sign,
    short of zero by the interpolation's estimated error (the last point's gap over 100 where no estimate
    exists yet), so that the Newton solve at the aimed parameter stays on the piece: past the corner the piece
    has no solution, and a Newton solve that fails there costs as much as ten that converge. A solve that fails
    or lands on the other piece halves the aimed gap towards the last point's. The value is the
    interpolation's at gap zero once the last point's gap is below ``1e-9`` of the first's (or after
    ``iterations`` steps). Returns ``(value, converged)``, converged when that gap was reached.
    """
    size = max(abs(g) for g, _, _ in points)
    for _ in range(iterations):
        g_b, l_b, z_b = points[-1]
        if abs(g_b) <= 1e-9 * size or points[-2][0] == g_b:
            break
        if len(points) >= 3:
            linear = _interpolate(points[-2:], 0.0, False)[0]
            quadratic = _interpolate(points[-3:], 0.0, False)[0]
            slope = (g_b - points[-2][0]) / (l_b - points[-2][1]) if l_b != points[-2][1] else 0.0
            error = 2.0 * abs(slope * (quadratic - linear))
            aim = math.copysign(min(0.5 * abs(g_b), max(error, 1e-12 * size)), g_b)
        else:
            aim = 0.01 * g_b
        found = _step_on_piece(problem, points, aim, state, size)
        if found is None:
            break
        points = [*points[-2:], found]
    converged = abs(points[-1][0]) <= 1e-9 * size
    if points[-1][0] == points[-2][0]:
        return float(points[-1][1]), converged
    return float(_interpolate(points[-3:], 0.0, False)[0]), converged


def _step_on_piece(problem, points, aim, state, size):
    """The solution ``(gap, lambda, z)`` on the piece interpolated at gap ``aim`` (halved towards the last
    point's while Newton fails there or finds the other piece), or None."""
    g_b = points[-1][0]
    for _ in range(STEP_TRIES):
        l_c, guess = _interpolate(points[-3:], aim)
        if not math.isfinite(l_c):
            return None
        try:
            z_c = problem.solve(guess, l_c, tol=SOLVE_TOL, max_iterations=SOLVE_ITERATIONS)
            g_c = problem.gap(z_c, l_c)
            if all(g_c != g for g, _, _ in points[-2:]) and (
                    abs(g_c) <= 1e-6 * size or np.array_equal(problem.contact_state(z_c, l_c), state)):
                return g_c, l_c, z_c  # still on this piece (and a new gap: the interpolation needs distinct ones)
        except ConvergenceError:
            pass
        aim = 0.5 * (aim + g_b)
    return None


def turning_point(lam, Z, i):
    """The parameter at the turning point between points ``i`` and ``i + 1``: the vertex of the parabola
    ``lambda(s)`` through the three points around it (``s`` the arclength in amplitudes over their largest
    value and the parameter over its range), else the farther of the two."""
    farther = max(lam[i], lam[i + 1]) if lam[i] >= lam[max(i - 1, 0)] else min(lam[i], lam[i + 1])
    j = [k for k in (i - 1, i, i + 1, i + 2) if 0 <= k < len(lam)]
    if len(j) < 3:
        return float(farther)
    j = j[:3] if abs(lam[j[1]] - farther) < abs(lam[j[-2]] - farther) or len(j) == 3 else j[1:]
    lam, Z = np.asarray(lam), np.asarray(Z)
    width = float(lam.max() - lam.min()) or 1.0
    size = float(np.abs(Z).max()) or 1.0
    l0, l1, l2 = (float(lam[k]) for k in j)
    h1, h2 = (math.sqrt(float((((Z[b] - Z[a]) / size) ** 2).sum()) + ((lam[b] - lam[a]) / width) ** 2)
              for a, b in zip(j, j[1:]))
    # the parabola through (0, l0), (h1, l1), (h1 + h2, l2) by divided differences: l0 + d1 s + a s (s - h1)
    if h1 == 0.0 or h2 == 0.0:
        return float(farther)
    d1, d2 = (l1 - l0) / h1, (l2 - l1) / h2
    a = (d2 - d1) / (h1 + h2)
    if a == 0.0 or not math.isfinite(a):
        return float(farther)
    b = d1 - a * h1  # l(s) = l0 + b s + a s^2
    vertex = l0 - b * b / (4.0 * a)
    low, high = min(l0, l1, l2), max(l0, l1, l2)
    return float(vertex) if low - (high - low) <= vertex <= high + (high - low) else float(farther)
