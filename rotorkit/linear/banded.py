"""Banded linear algebra in numpy alone: a bandwidth-reducing order and many banded solves at once.

The harmonic solves of an unbalance response or a frequency response
function (:mod:`rotorkit.linear.harmonic`) are hundreds of small banded
complex systems, one per speed. Solved one by one with LAPACK
(``scipy.linalg.solve_banded``) each costs little, but importing scipy costs
more than all of them on an everyday model. Here they are solved together,
the systems on the last axis of the arrays, so that each elimination step
is one numpy operation over all of them:

- first by Gaussian elimination without row exchanges (the band does not
  widen: ``lower x upper`` updates per column), then every system's
  residual is checked: where its normwise backward error
  ``|b - A x| / (|A| |x| + |b|)`` (infinity norms) is below
  :data:`BACKWARD_ERROR` ``x`` (band width) ``x`` machine epsilon, ``x`` is
  the exact solution of a system within rounding of the given one, as
  partial pivoting would give (several right-hand sides are checked
  together, by one combination of them with weights of distinct phases);
- the systems where it is not (a zero or small pivot) are solved again by
  elimination with partial pivoting inside the band (LAPACK's ``gbsv``
  algorithm, the pivot the entry of largest ``|Re| + |Im|``).

:func:`reverse_cuthill_mckee` orders the coordinates of a sparsity pattern
for a small bandwidth, as :func:`scipy.sparse.csgraph.reverse_cuthill_mckee`
does (breadth-first from a node of least degree, neighbours by increasing
degree, the order reversed).
"""

from __future__ import annotations

import numpy as np

__all__ = ["reverse_cuthill_mckee", "band_rows", "solve_banded_many", "solve_banded_last"]

#: accept the solution without row exchanges when its backward error is below this many band widths x epsilon
BACKWARD_ERROR = 16


def reverse_cuthill_mckee(pattern):
    """A bandwidth-reducing permutation of a symmetric boolean pattern, shape (n, n).

    Returns
    -------
    numpy.ndarray of int, shape (n,)
        ``perm``: coordinate ``perm[i]`` goes to position ``i``.
    """
    P = np.asarray(pattern, dtype=bool)
    n = P.shape[0]
    rows, cols = np.nonzero(P)  # row by row, columns ascending: plain lists below (Python loops over them)
    neighbours = [c.tolist() for c in np.split(cols, np.searchsorted(rows, np.arange(1, n)))]
    degree = (np.bincount(rows, minlength=n) - np.diagonal(P)).tolist()
    seen = [False] * n
    order = []
    for start in np.argsort(degree, kind="stable").tolist():
        if seen[start]:
            continue
        seen[start] = True
        queue, head = [start], 0
        while head < len(queue):
            node = queue[head]
            head += 1
            new = [k for k in neighbours[node] if not seen[k]]
            new.sort(key=degree.__getitem__)
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


def solve_banded_many(R, lower, upper, rhs, *, pivoting="auto"):
    """Solve many banded systems ``A_k x_k = b_k`` at once.

    Parameters
    ----------
    R : numpy.ndarray, shape (m, n, lower + upper + 1)
        The matrices in row-window band storage (:func:`band_rows`).
    lower, upper : int
        Numbers of sub- and super-diagonals.
    rhs : numpy.ndarray, shape (m, n, r)
    pivoting : {"auto", "partial"}
        ``"auto"``: without row exchanges where that is backward stable
        (checked per system), partial pivoting elsewhere; ``"partial"``:
        partial pivoting for every system.

    Returns
    -------
    numpy.ndarray, shape (m, n, r)

    Raises
    ------
    numpy.linalg.LinAlgError
        If a matrix is singular (a zero pivot).
    """
    R = np.asarray(R)
    rhs = np.asarray(rhs)
    dtype = np.result_type(R.dtype, rhs.dtype)
    bands = np.ascontiguousarray(np.moveaxis(R, 0, -1), dtype=dtype)
    y = np.ascontiguousarray(np.moveaxis(rhs, 0, -1), dtype=dtype)
    return np.moveaxis(solve_banded_last(bands, lower, upper, y, pivoting=pivoting), -1, 0)


def solve_banded_last(bands, lower, upper, rhs, *, pivoting="auto"):
    """:func:`solve_banded_many` with the systems on the last axis (no copies to reorder them).

    Parameters
    ----------
    bands : numpy.ndarray, shape (n, lower + upper + 1, m)
        ``bands[i, c, k] = A_k[i, i - lower + c]`` (zero outside the matrix); not modified.
    rhs : numpy.ndarray, shape (n, r, m)
        Not modified.
    pivoting : {"auto", "partial"}

    Returns
    -------
    numpy.ndarray, shape (n, r, m)
    """
    if pivoting not in ("auto", "partial"):
        raise ValueError(f"pivoting={pivoting!r} is unknown: expected 'auto' or 'partial'")
    n, width, m = bands.shape
    dtype = np.result_type(bands.dtype, rhs.dtype)
    if pivoting == "partial" or n < 2 or m == 0:
        return _solve_pivoted(bands, lower, upper, rhs, dtype)
    with np.errstate(all="ignore"):  # a zero pivot gives inf or nan: those systems fail the check below
        x = _solve_unpivoted(np.array(bands, dtype=dtype), lower, upper, np.array(rhs, dtype=dtype))
        b, xb = _combined(rhs, dtype), _combined(x, dtype)
        residual = np.array(b, dtype=dtype)
        product = np.empty_like(residual)  # one buffer for the products: no fresh memory per band
        for c in range(width):  # b - A x, one band at a time over all systems
            d = c - lower  # column = row + d
            lo, hi = max(0, -d), min(n, n - d)
            if lo < hi:
                residual[lo:hi] -= np.multiply(bands[lo:hi, c, :], xb[lo + d:hi + d], out=product[lo:hi])
        scale = _row_sums(bands).max(axis=0) * _size(xb).max(axis=0) + _size(b).max(axis=0)
        good = _size(residual).max(axis=0) <= BACKWARD_ERROR * width * np.finfo(dtype).eps * scale
    if not good.all():
        bad = np.flatnonzero(~good)
        x[..., bad] = _solve_pivoted(bands[..., bad], lower, upper, rhs[..., bad], dtype)
    return x


def _combined(a, dtype):
    """The right-hand sides (or solutions) ``a`` (n, r, m) combined into one per system, shape (n, m).

    One column as it is; several with fixed weights of distinct phases
    (``exp(2 pi i k phi)``, ``phi`` the golden ratio's fraction; distinct
    positive weights if real): the residual of the combination is the same
    combination of the columns' residuals, so one check (one product with
    ``A``) covers them all, not ``r`` checks (a large residual in some column
    would have to cancel against the others exactly to pass).
    """
    if a.shape[1] == 1:
        return a[:, 0]
    k = np.arange(a.shape[1]) * 0.6180339887498949
    weights = np.exp(2j * np.pi * k) if np.issubdtype(dtype, np.complexfloating) else 1.0 + k % 1.0
    return np.einsum("nrm,r->nm", a, weights.astype(dtype))


def _size(a):
    """``|Re a| + |Im a|`` (``|a|`` if real): the entries' sizes for the norms, without complex square roots."""
    if not np.iscomplexobj(a):
        return np.abs(a)
    out = np.abs(a.real)
    out += np.abs(a.imag)  # elementwise: not a reduction over an axis of length 2 (slow in numpy)
    return out


def _row_sums(bands):
    """``sum_c |Re| + |Im|`` of each row of each system, shape (n, m): the rows' norms for ``|A|_inf``."""
    if not np.iscomplexobj(bands):
        return np.abs(bands).sum(axis=1)
    width = bands.shape[1]
    bands = np.ascontiguousarray(bands)
    # the real and imaginary parts side by side on the last axis: sum over the band first (one band at a
    # time, in order, into one accumulator: no temporary the size of all bands), then the pairs
    parts = bands.view(bands.real.dtype)
    total = np.abs(parts[:, 0, :])
    size = np.empty_like(total)
    for c in range(1, width):
        total += np.abs(parts[:, c, :], out=size)
    return total[:, 0::2] + total[:, 1::2]


def _solve_unpivoted(S, lower, upper, y):
    """Elimination without row exchanges, in place on ``S`` (n, lower + upper + 1, m) and ``y`` (n, r, m)."""
    from numpy.lib.stride_tricks import as_strided

    n, _, m = S.shape
    s0, s1, s2 = S.strides
    # buffers for the factors and products of every step, reused: no fresh memory per step
    factors_buffer = np.empty((lower, m), dtype=S.dtype)
    product = np.empty((lower, upper, m), dtype=S.dtype)
    product_y = np.empty((lower,) + y.shape[1:], dtype=y.dtype)
    for j in range(n - 1):
        last = min(lower, n - 1 - j)
        if not last:
            continue
        # V[r, t] = S[j + r, lower - r + t] = A[j + r, j + t]: rows j..j+last over columns j..j+upper
        V = as_strided(S[j, lower:], shape=(last + 1, upper + 1, m), strides=(s0 - s1, s1, s2))
        factors = np.divide(V[1:, 0], V[0, 0], out=factors_buffer[:last])
        if upper:
            V[1:, 1:] -= np.multiply(factors[:, None, :], V[0, 1:], out=product[:last])
        y[j + 1:j + 1 + last] -= np.multiply(factors[:, None, :], y[j], out=product_y[:last])
    return _back_substitute(S[:, lower:], upper, y)


def _back_substitute(U, kv, y):
    """``x`` from the upper band ``U[j, t] = U_jj+t`` (n, kv + 1, m) and the reduced right-hand sides (n, r, m)."""
    n = U.shape[0]
    x = np.zeros((n + kv,) + y.shape[1:], dtype=y.dtype)
    for j in range(n - 1, -1, -1):
        x[j] = (y[j] - np.einsum("tm,trm->rm", U[j, 1:], x[j + 1:j + 1 + kv])) / U[j, 0]
    return x[:n]


def _solve_pivoted(bands, lower, upper, rhs, dtype):
    """Elimination with partial pivoting inside the band (LAPACK's ``gbsv``), the systems on the last axis."""
    from numpy.lib.stride_tricks import as_strided

    n, width, m = bands.shape
    kl, kv = lower, lower + upper
    # S[i, c] = A[i, i - kl + c] for c up to kl + kv: room for the fill-in that row exchanges bring
    S = np.zeros((n + kl, kl + kv + 1, m), dtype=dtype)
    S[:n, :width] = bands
    y = np.array(rhs, dtype=dtype)
    s0, s1, s2 = S.strides
    pivots = np.empty((n, m), dtype=dtype)
    for j in range(n):
        last = min(kl, n - 1 - j)
        # V[r, t] = S[j + r, kl - r + t] = A[j + r, j + t]: rows j..j+last over columns j..j+kv
        V = as_strided(S[j, kl:], shape=(last + 1, kv + 1, m), strides=(s0 - s1, s1, s2))
        if last:
            candidates = V[:, 0]
            p = np.argmax(np.abs(candidates.real) + np.abs(candidates.imag), axis=0)
            swap = np.flatnonzero(p)
            if swap.size:  # exchange row j with row j + p in the systems that need it
                below = p[swap]
                top = V[0, :, swap]
                V[0, :, swap] = V[below, :, swap]
                V[below, :, swap] = top
                top = y[j, :, swap]
                y[j, :, swap] = y[j + below, :, swap]
                y[j + below, :, swap] = top
        pivots[j] = V[0, 0]
        if not np.all(pivots[j] != 0):
            raise np.linalg.LinAlgError("a banded matrix is singular")
        if last:
            factors = V[1:, 0] / V[0, 0]
            V[1:, 1:] -= factors[:, None, :] * V[0, 1:]
            y[j + 1:j + 1 + last] -= factors[:, None, :] * y[j]
    return _back_substitute(S[:n, kl:], kv, y)
