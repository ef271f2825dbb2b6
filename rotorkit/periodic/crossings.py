"""Where a Floquet multiplier leaves the unit circle between two points of a branch: a period doubling
(through -1) or a Neimark-Sacker point (a complex pair), located on the branch, not interpolated.

The modulus of the crossing multiplier less 1 is brought to zero by the Illinois variant of regula falsi on the
parameter, each value solved by Newton at that parameter
(:meth:`~rotorkit.periodic.continuation.ContinuationProblem.solve`) from the points' interpolation:
superlinear where the modulus is smooth, like bisection where it jumps (a friction rub's circle that loses
stability the instant contact begins). Where the branch also turns between the two points (a fold, or the
corner of a grazing fold, at ``fold``) each piece is followed from its point to the fold at fixed parameters
(in a few steps, each solved from the piece's nearest solutions, in its own contact state at a grazing
corner): the crossing lies on the piece whose modulus changes sign between its point and the fold, else at
the fold itself (a grazing corner joining an unstable piece to a stable one). Where a solve fails or lands
far from the branch the linear interpolation of the two points' moduli is kept.
"""

from __future__ import annotations

import numpy as np

from .errors import ConvergenceError
from .folds import SOLVE_ITERATIONS, SOLVE_TOL
from .stability import STABILITY_TOL

__all__ = ["crossing_point", "CROSSING_TOL", "CROSSING_SOLVES"]

#: a crossing is located to this share of its parameter ...
CROSSING_TOL = 1e-7
#: ... with at most this many solutions
CROSSING_SOLVES = 40
#: a piece is followed from its point towards the fold in steps to these shares of the way, as far as it can be
#: solved on the piece (where the pieces meet a solve may land on the other, and at a smooth fold Newton at a fixed
#: parameter is singular); it must get at least to the third
APPROACH = (0.5, 0.8, 0.9, 0.95, 0.98, 0.99, 0.995, 0.999)


def _modulus(mu, k, limit=1.0):
    """``|mu|`` of the ``k + 1``-th largest multiplier less ``limit``."""
    return float(np.sort(np.abs(np.asarray(mu)))[::-1][k]) - limit


def crossing_point(problem, lam, Z, i, before, after, multipliers_at, *, fold=None):
    """The parameter between points ``i`` and ``i + 1`` (parameters ``lam``, the problem's unknowns ``Z``,
    multipliers ``before`` and ``after``) where the number of multipliers outside the unit circle changes.

    ``multipliers_at(z, lam)``: the multipliers of the solution ``z`` (the problem's unknowns) at ``lam``, by
    the branch's stability method; ``fold``: the parameter of a fold between the two points, if the branch
    turns there."""
    # the k + 1-th largest modulus crosses: k the smaller count of multipliers outside (the count of
    # rotorkit.periodic.stability.is_stable and the branch's `stable`, beyond 1 + STABILITY_TOL); located where
    # it is 1, unless that does not separate the two points (a modulus within the tolerance), then 1 + tol
    k = min(int((np.abs(before) > 1.0 + STABILITY_TOL).sum()), int((np.abs(after) > 1.0 + STABILITY_TOL).sum()))
    lam = np.asarray(lam, dtype=float)
    Z = np.asarray(Z, dtype=float).reshape(len(lam), -1)
    la, lb = float(lam[i]), float(lam[i + 1])
    limit = 1.0
    ga, gb = _modulus(before, k), _modulus(after, k)
    if (ga > 0.0) == (gb > 0.0):
        limit = 1.0 + STABILITY_TOL
        ga, gb = _modulus(before, k, limit), _modulus(after, k, limit)
    interpolated = la + ga / (ga - gb) * (lb - la) if ga != gb else 0.5 * (la + lb)
    if (ga > 0.0) == (gb > 0.0) or la == lb:
        return float(interpolated)
    reach = float(np.linalg.norm(Z[i + 1] - Z[i]))  # a solution farther from its guess is not on this branch

    def modulus_at(guess, value, state=None, known=None):
        """The crossing modulus of the solution at ``value`` from ``guess`` (added to ``known``); None if it
        cannot be solved, lies farther from the guess than the two points from each other, or is not in the
        contact ``state``."""
        try:
            z = np.ravel(problem.solve(guess, value, tol=SOLVE_TOL, max_iterations=SOLVE_ITERATIONS))
        except ConvergenceError:
            return None
        if not (np.all(np.isfinite(z)) and np.linalg.norm(z - guess) <= reach):
            return None
        if state is not None and not np.array_equal(problem.contact_state(z, value), state):
            return None
        if known is not None:
            known.append((value, z))
        return _modulus(multipliers_at(z, value), k, limit)

    if fold is None:
        found = _root(lambda v: modulus_at(Z[i] + (v - la) / (lb - la) * (Z[i + 1] - Z[i]), v), la, lb, ga, gb)
        return float(interpolated if found is None else found)
    # the branch turns at the fold: each piece followed from its point towards the fold at fixed parameters (each
    # solve from the two nearest solutions on the piece; where the pieces differ in contact, a solution must be in
    # its piece's contact state), its modulus at the fold's edge compared with its point's
    states = [problem.contact_state(Z[i], la), problem.contact_state(Z[i + 1], lb)] if problem.hb.contact else None
    grazing = states is not None and not np.array_equal(*states)
    for side, (near, far, g_near) in enumerate(((i, i - 1, ga), (i + 1, i + 2, gb))):
        known = [(float(lam[near]), Z[near])]
        if 0 <= far < len(lam) and lam[far] != lam[near]:  # the piece's next point away from the fold
            known.append((float(lam[far]), Z[far]))
        state = states[side] if grazing else None

        def on_piece(v, known=known, state=state):
            pair = sorted(known, key=lambda item: abs(item[0] - v))[:2]
            if len(pair) == 1 or pair[0][0] == pair[1][0]:
                guess = pair[0][1]
            else:
                (l0, z0), (l1, z1) = pair
                guess = z0 + (v - l0) / (l1 - l0) * (z1 - z0)
            return modulus_at(guess, v, state, known)

        edge, g_edge = None, None
        for share in APPROACH:  # as near the fold as the piece can be solved (where the pieces meet, the solve
            value = float(lam[near] + share * (fold - lam[near]))  # may land on the other: not taken)
            g = on_piece(value)
            if g is None:
                break
            edge, g_edge = value, g
        if edge is None or abs(edge - fold) > (1.0 - APPROACH[2]) * abs(lam[near] - fold):
            return float(interpolated)
        if (g_edge > 0.0) != (g_near > 0.0):  # the crossing is on this piece, between its point and the fold
            found = _root(on_piece, float(lam[near]), edge, g_near, g_edge)
            return float(interpolated if found is None else found)
    return float(fold)  # each piece keeps its point's stability up to the fold: the change is at the fold


def _root(modulus_of, la, lb, ga, gb):
    """The parameter between ``la`` and ``lb`` (moduli ``ga``, ``gb`` of opposite signs) where ``modulus_of``
    changes sign (Illinois), or None if a value cannot be solved."""
    side = 0  # the end moved last (-1: a, +1: b), for the Illinois halving
    width = CROSSING_TOL * max(abs(la), abs(lb))
    for _ in range(CROSSING_SOLVES):
        if abs(lb - la) <= width:
            break
        value = (la * gb - lb * ga) / (gb - ga)
        value = min(max(value, min(la, lb) + 1e-3 * abs(lb - la)), max(la, lb) - 1e-3 * abs(lb - la))
        g = modulus_of(value)
        if g is None:
            return None
        if (g > 0.0) == (ga > 0.0):
            la, ga = value, g
            if side == -1:
                gb *= 0.5
            side = -1
        else:
            lb, gb = value, g
            if side == 1:
                ga *= 0.5
            side = 1
    return 0.5 * (la + lb)
