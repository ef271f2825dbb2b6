"""Harmonic solves ``(K + W H - w^2 M + i w (C + W G)) Q = F`` over many (W, w) pairs.

The steady unbalance response and the frequency response functions both
need the dynamic stiffness solved at many frequencies. The solve is
**direct, not by modal superposition**: it is exact (no truncation of the
basis, nothing to choose), and with gyroscopic, cross-coupled or
speed-dependent matrices a modal basis would change with the speed and
have to be recomputed (complex, non-symmetric, left and right) at each
one, which costs more than the solve it replaces. The cost is kept low by
the structure of the matrices:

- when the coordinates can be ordered so that the matrices are banded
  (beam finite elements, chains of stations: reverse Cuthill-McKee
  ordering of the union of the sparsity patterns), each frequency is a
  banded LU solve, ``O(n b^2)``, all frequencies of a batch in one
  elimination with partial pivoting (:mod:`rotorkit.linear.banded`, numpy
  alone: no scipy import);
- otherwise (small lumped models, dense couplings) the dense systems of
  all frequencies are solved in batches by :func:`numpy.linalg.solve`.
"""

from __future__ import annotations

import numpy as np

__all__ = ["solve_harmonic", "band_structure"]

#: use the banded solver when (lower + upper + 1) is below this fraction of n
BANDED_FRACTION = 0.25
#: at most this many complex entries per dense batch
_BATCH_ENTRIES = 4_000_000


def band_structure(*matrices):
    """``(permutation, lower, upper)``: a bandwidth-reducing order of the coordinates and its bands."""
    from .banded import reverse_cuthill_mckee

    pattern = np.zeros(matrices[0].shape, dtype=bool)
    for A in matrices:
        pattern |= A != 0
    pattern |= pattern.T
    np.fill_diagonal(pattern, True)
    perm = reverse_cuthill_mckee(pattern)
    P = pattern[np.ix_(perm, perm)]
    rows, cols = np.nonzero(P)
    return perm, int(np.max(rows - cols, initial=0)), int(np.max(cols - rows, initial=0))


def solve_harmonic(model, speeds, frequencies, forces, *, method="auto"):
    """Solve the dynamic stiffness at each ``(speed, frequency)`` for the right-hand sides ``forces``.

    Parameters
    ----------
    model : LinearModel
    speeds, frequencies : numpy.ndarray, shape (m,)
        Swept speed ``W`` and excitation frequency ``w`` (rad/s) of each solve.
    forces : numpy.ndarray of complex, shape (m, n, r) or (n, r)
        Complex force amplitudes (N, N m); ``(n, r)`` is used at every point.
    method : {"auto", "banded", "dense"}

    Returns
    -------
    numpy.ndarray of complex, shape (m, n, r)
        Complex amplitudes of the coordinates (m, rad).
    """
    M, C, K, G, H = model.mass, model.damping, model.stiffness, model.gyroscopic, model.circulatory
    speeds = np.asarray(speeds, dtype=float)
    w = np.asarray(frequencies, dtype=float)
    n = M.shape[0]
    F = np.asarray(forces, dtype=complex)
    shared = F.ndim == 2
    r = F.shape[-1]
    out = np.empty((w.size, n, r), dtype=complex)
    terms = getattr(model, "speed_terms", None)  # entries not affine in the speed, exact at each one
    extra = () if terms is None else (terms.pattern(),)
    perm, lower, upper = band_structure(M, C, K, G, H, *extra)

    def exact(k, om):
        """Positions and complex values of the speed terms' part of the dynamic stiffness at point ``k``."""
        v = np.asarray(terms.values(float(speeds[k])), dtype=complex)
        v[terms.matrix == 1] *= 1j * om
        return v
    if method == "auto":
        method = "banded" if lower + upper + 1 <= BANDED_FRACTION * n else "dense"
    if method == "banded":
        from .banded import band_rows, solve_banded_many

        Mb, Cb, Kb, Gb, Hb = (band_rows(A[np.ix_(perm, perm)], lower, upper) for A in (M, C, K, G, H))
        rhs_all = (F[perm] if shared else F[:, perm])
        inverse = np.empty(n, dtype=np.int64)
        inverse[perm] = np.arange(n)
        if terms is not None:  # band positions of the exact speed terms
            term_rows = inverse[terms.rows]
            term_bands = lower + inverse[terms.cols] - term_rows
        batch = max(1, _BATCH_ENTRIES // max(n * (lower + upper + 1), 1))
        for start in range(0, w.size, batch):  # all speeds of a batch in one banded elimination
            sl = slice(start, min(start + batch, w.size))
            W, om = speeds[sl, None, None], w[sl, None, None]
            ab = (Kb + W * Hb - om * om * Mb) + 1j * om * (Cb + W * Gb)
            if terms is not None:
                values = np.array([exact(k, w[k]) for k in range(sl.start, sl.stop)])
                np.add.at(ab, (np.arange(ab.shape[0])[:, None], term_rows[None, :], term_bands[None, :]), values)
            rhs = np.broadcast_to(rhs_all, (ab.shape[0],) + rhs_all.shape) if shared else rhs_all[sl]
            out[sl][:, perm] = solve_banded_many(ab, lower, upper, rhs)
        return out
    batch = max(1, _BATCH_ENTRIES // max(n * n, 1))
    for start in range(0, w.size, batch):
        sl = slice(start, min(start + batch, w.size))
        W, om = speeds[sl, None, None], w[sl, None, None]
        D = K + W * H - om * om * M + 1j * om * (C + W * G)
        if terms is not None:
            for k in range(sl.start, sl.stop):
                np.add.at(D[k - sl.start], (terms.rows, terms.cols), exact(k, w[k]))
        rhs = np.broadcast_to(F, (D.shape[0], n, r)) if shared else F[sl]
        out[sl] = np.linalg.solve(D, rhs)
    return out
