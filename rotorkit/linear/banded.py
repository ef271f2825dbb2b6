"""Banded linear algebra in numpy alone: a bandwidth-reducing order and many banded solves at once.

The harmonic solves of an unbalance response or a frequency response
function (:mod:`rotorkit.analysis.harmonic`) are hundreds of small banded
complex systems, one per speed. Solved one by one with LAPACK
(``scipy.linalg.solve_banded``) each costs little, but importing scipy costs
more than all of them on an everyday model. Here they are solved together:
Gaussian elimination with partial pivoting inside the band (LAPACK's
``gbsv`` algorithm, the pivot the entry of largest ``|Re| + |Im|``), each
elimination step one numpy operation over all systems.

:func:`reverse_cuthill_mckee` orders the coordinates of a sparsity pattern
for a small bandwidth, as :func:`scipy.sparse.csgraph.reverse_cuthill_mckee`
does (breadth-first from a node of least degree, neighbours by increasing
degree, the order reversed).
"""

from __future__ import annotations

import numpy as np

__all__ = ["reverse_cuthill_mckee", "band_rows", "solve_banded_many"]


def reverse_cuthill_mckee(pattern):
    """A bandwidth-reducing permutation of a symmetric boolean pattern, shape (n, n).

    Returns
    -------
    numpy.ndarray of int, shape (n,)
        ``perm``: coordinate ``perm[i]`` goes to position ``i``.
    """
    P = np.asarray(pattern, dtype=bool)
    n = P.shape[0]
    neighbours = [np.flatnonzero(P[i]) for i in range(n)]
    degree = np.array([np.count_nonzero(row != i) for i, row in enumerate(neighbours)])
    seen = np.zeros(n, dtype=bool)
    order = []
    for start in np.argsort(degree, kind="stable"):
        if seen[start]:
            continue
        seen[start] = True
        queue, head = [int(start)], 0
        while head < len(queue):
            node = queue[head]
            head += 1
            new = [int(k) for k in neighbours[node] if not seen[k]]
            new.sort(key=lambda k: degree[k])
            for k in new:
                seen[k] = True
            queue.extend(new)
        order.extend(queue)
    return np.array(order[::-1], dtype=np.int64)


def band_rows(matrix, lower, upper):
    """Row-window band storage ``R[..., r, t] = A[..., r, r - lower + t]`` (zero outside), shape (..., n, lower + upper + 1)."""
    A = np.asarray(matrix)
    n = A.shape[-1]
    width = lower + upper + 1
    rows = np.arange(n)[:, None]
    cols = rows - lower + np.arange(width)[None, :]
    inside = (cols >= 0) & (cols < n)
    out = np.zeros(A.shape[:-2] + (n, width), dtype=A.dtype)
    out[..., inside] = A[..., np.broadcast_to(rows, cols.shape)[inside], cols[inside]]
    return out


def solve_banded_many(R, lower, upper, rhs):
    """Solve many banded systems ``A_k x_k = b_k`` at once (partial pivoting within the band).

    Parameters
    ----------
    R : numpy.ndarray, shape (m, n, lower + upper + 1)
        The matrices in row-window band storage (:func:`band_rows`).
    lower, upper : int
        Numbers of sub- and super-diagonals.
    rhs : numpy.ndarray, shape (m, n, r)

    Returns
    -------
    numpy.ndarray, shape (m, n, r)

    Raises
    ------
    numpy.linalg.LinAlgError
        If a matrix is singular (a zero pivot).
    """
    R = np.asarray(R)
    m, n, width = R.shape
    kl, kv = lower, lower + upper
    rhs = np.asarray(rhs)
    r = rhs.shape[-1]
    dtype = np.result_type(R.dtype, rhs.dtype)
    # the systems on the last axis: every step below is one vectorised operation over all of them
    rows_in = np.zeros((n + kl + 1, kv + 1, m), dtype=dtype)
    rows_in[:n] = np.moveaxis(R, 0, -1)
    y = np.zeros((n + kl, r, m), dtype=dtype)
    y[:n] = np.moveaxis(rhs, 0, -1)
    # act: rows j..j+kl over columns j..j+kv of the partly reduced matrix; next: the same one column on
    act, nxt = np.zeros((kl + 1, kv + 1, m), dtype=dtype), np.zeros((kl + 1, kv + 1, m), dtype=dtype)
    for i in range(kl + 1):  # row i of A over columns 0..kv: R's window of row i starts at column i - kl
        act[i, :upper + 1 + i] = rows_in[i, kl - i:]
    U = np.empty((n, kv + 1, m), dtype=dtype)
    batch = np.arange(m)
    for j in range(n):
        last = min(kl, n - 1 - j)
        candidates = act[:last + 1, 0]
        p = np.argmax(np.abs(candidates.real) + np.abs(candidates.imag), axis=0)
        if p.any():  # partial pivoting: swap row j with row j + p (per system)
            pivot_rows = act[p, :, batch]  # (m, kv + 1)
            act[p, :, batch] = act[0].T
            act[0] = pivot_rows.T
            pivot_y = y[j + p, :, batch]
            y[j + p, :, batch] = y[j].T
            y[j] = pivot_y.T
        pivot = act[0, 0]
        if not np.all(pivot != 0):
            raise np.linalg.LinAlgError("a banded matrix is singular")
        U[j] = act[0]
        if last:
            factors = act[1:last + 1, 0] / pivot
            y[j + 1:j + 1 + last] -= factors[:, None, :] * y[j]
            np.subtract(act[1:last + 1, 1:], factors[:, None, :] * act[0, 1:], out=nxt[:last, :kv])
        if j + 1 < n:  # move on one column: row j + kl + 1 comes in (its window starts at column j + 1)
            nxt[last:kl, :kv] = act[last + 1:, 1:]
            nxt[:kl, kv] = 0.0
            nxt[kl] = rows_in[j + kl + 1]
            act, nxt = nxt, act
    x = np.zeros((n + kv, r, m), dtype=dtype)
    for j in range(n - 1, -1, -1):
        x[j] = (y[j] - np.einsum("tm,trm->rm", U[j, 1:], x[j + 1:j + 1 + kv])) / U[j, 0]
    return np.moveaxis(x[:n], -1, 0)
