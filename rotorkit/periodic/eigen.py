"""Small dense linear algebra compiled with numba for the compiled harmonic-balance path.

At the sizes of the Hill matrices of small systems (a few dozen rows, one per
branch point) the call and blocking overheads of LAPACK's general
eigensolver dominate. Here: balancing, reduction to upper Hessenberg form by
stabilised elementary similarity transformations and the Francis
double-shift QR iteration (the classical EISPACK ``balanc``/``elmhes``/
``hqr`` sequence), eigenvalues only; an LU factorisation with partial
pivoting (as LAPACK's ``getrf``) for the Newton steps and tangents; a complex
LU (:func:`complex_lu`) for null vectors and for one eigenpair of a quadratic
eigenproblem near a shift by inverse iteration (:func:`quadratic_eigenpair`:
following Hill's exponents along a branch). All functions are ``numba.njit`` helpers inlined
into the kernels of :mod:`rotorkit.periodic.compiled`; this module imports
numba at import time and is only imported by that path.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba import types
from numba.extending import overload

__all__ = ["lu_factor", "lu_solve", "eigenvalues", "complex_lu", "floored_lu", "inverse_solve", "complex_null_vector",
           "null_vector_into", "quadratic_eigenpair", "row_norms", "eigenpair_near"]


@numba.njit(cache=False)
def lu_factor(A, piv):
    """In-place LU with partial pivoting (``A = P L U``, the first largest pivot as ``getrf``); False if a pivot
    is exactly zero (the factors are still formed: a solve then gives inf/nan, as LAPACK's)."""
    m = A.shape[0]
    regular = True
    for k in range(m):
        p, big = k, abs(A[k, k])
        for i in range(k + 1, m):
            if abs(A[i, k]) > big:
                p, big = i, abs(A[i, k])
        piv[k] = p
        if p != k:
            for j in range(m):
                A[k, j], A[p, j] = A[p, j], A[k, j]
        pivot = A[k, k]
        if pivot == 0.0:
            regular = False
            continue
        for i in range(k + 1, m):
            f = A[i, k] / pivot
            A[i, k] = f
            if f != 0.0:
                for j in range(k + 1, m):
                    A[i, j] -= f * A[k, j]
    return regular


@numba.njit(cache=False, inline="always")
def _substitute(LU, piv, x, inv):
    """``x = A^-1 x`` in place from LU factors with row pivots ``piv``: the row swaps, the forward and the back
    substitution, dividing by the pivots, or (``inv`` not None) multiplying by their reciprocals ``inv``."""
    m = LU.shape[0]
    for k in range(m):
        p = piv[k]
        if p != k:
            x[k], x[p] = x[p], x[k]
    for i in range(m):
        s = x[i]
        for j in range(i):
            s -= LU[i, j] * x[j]
        x[i] = s
    for i in range(m - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, m):
            s -= LU[i, j] * x[j]
        if inv is None:
            x[i] = s / LU[i, i]
        else:
            x[i] = s * inv[i]


@numba.njit(cache=False)
def lu_solve(LU, piv, b, x):
    """``x = A^-1 b`` from :func:`lu_factor`'s factors (``x`` may be ``b``)."""
    if x is not b:
        for i in range(LU.shape[0]):
            x[i] = b[i]
    _substitute(LU, piv, x, None)


@numba.njit(cache=False)
def _balance(a):
    """Scale rows and columns by powers of 2 so that their norms are alike (a similarity: eigenvalues kept)."""
    n = a.shape[0]
    done = False
    while not done:
        done = True
        for i in range(n):
            r = 0.0
            c = 0.0
            for j in range(n):
                if j != i:
                    c += abs(a[j, i])
                    r += abs(a[i, j])
            if c != 0.0 and r != 0.0:
                g = r / 2.0
                f = 1.0
                s = c + r
                while c < g:
                    f *= 2.0
                    c *= 4.0
                g = r * 2.0
                while c > g:
                    f /= 2.0
                    c /= 4.0
                if (c + r) / f < 0.95 * s:
                    done = False
                    g = 1.0 / f
                    for j in range(n):
                        a[i, j] *= g
                    for j in range(n):
                        a[j, i] *= f


@numba.njit(cache=False)
def _hessenberg(a):
    """Reduce to upper Hessenberg form by elementary similarity transformations with pivoting (in place)."""
    n = a.shape[0]
    for m in range(1, n - 1):
        x = 0.0
        i = m
        for j in range(m, n):
            if abs(a[j, m - 1]) > abs(x):
                x = a[j, m - 1]
                i = j
        if i != m:
            for j in range(m - 1, n):
                a[i, j], a[m, j] = a[m, j], a[i, j]
            for j in range(n):
                a[j, i], a[j, m] = a[j, m], a[j, i]
        if x != 0.0:
            for i in range(m + 1, n):
                y = a[i, m - 1]
                if y != 0.0:
                    y /= x
                    a[i, m - 1] = y
                    for j in range(m, n):
                        a[i, j] -= y * a[m, j]
                    for j in range(n):
                        a[j, m] += y * a[j, i]
    for i in range(2, n):
        for j in range(i - 1):
            a[i, j] = 0.0


@numba.njit(cache=False)
def _hqr(a, wr, wi):
    """Eigenvalues of the upper Hessenberg ``a`` (destroyed) by the Francis double-shift QR iteration; False if
    an eigenvalue needs more than 30 iterations."""
    n = a.shape[0]
    anorm = 0.0
    for i in range(n):
        for j in range(max(i - 1, 0), n):
            anorm += abs(a[i, j])
    nn = n - 1
    t = 0.0
    p = q = r = x = y = z = w = 0.0
    while nn >= 0:
        its = 0
        while True:
            l = nn
            while l >= 1:
                s = abs(a[l - 1, l - 1]) + abs(a[l, l])
                if s == 0.0:
                    s = anorm
                if abs(a[l, l - 1]) + s == s:
                    a[l, l - 1] = 0.0
                    break
                l -= 1
            x = a[nn, nn]
            if l == nn:
                wr[nn] = x + t
                wi[nn] = 0.0
                nn -= 1
            else:
                y = a[nn - 1, nn - 1]
                w = a[nn, nn - 1] * a[nn - 1, nn]
                if l == nn - 1:
                    p = 0.5 * (y - x)
                    q = p * p + w
                    z = math.sqrt(abs(q))
                    x += t
                    if q >= 0.0:
                        z = p + (z if p >= 0.0 else -z)
                        wr[nn - 1] = wr[nn] = x + z
                        if z != 0.0:
                            wr[nn] = x - w / z
                        wi[nn - 1] = wi[nn] = 0.0
                    else:
                        wr[nn - 1] = wr[nn] = x + p
                        wi[nn] = z
                        wi[nn - 1] = -z
                    nn -= 2
                else:
                    if its == 30:
                        return False
                    if its == 10 or its == 20:  # exceptional shift
                        t += x
                        for i in range(nn + 1):
                            a[i, i] -= x
                        s = abs(a[nn, nn - 1]) + abs(a[nn - 1, nn - 2])
                        x = y = 0.75 * s
                        w = -0.4375 * s * s
                    its += 1
                    m = nn - 2
                    while m >= l:
                        z = a[m, m]
                        r = x - z
                        s = y - z
                        p = (r * s - w) / a[m + 1, m] + a[m, m + 1]
                        q = a[m + 1, m + 1] - z - r - s
                        r = a[m + 2, m + 1]
                        s = abs(p) + abs(q) + abs(r)
                        p /= s
                        q /= s
                        r /= s
                        if m == l:
                            break
                        u = abs(a[m, m - 1]) * (abs(q) + abs(r))
                        v = abs(p) * (abs(a[m - 1, m - 1]) + abs(z) + abs(a[m + 1, m + 1]))
                        if u + v == v:
                            break
                        m -= 1
                    for i in range(m + 2, nn + 1):
                        a[i, i - 2] = 0.0
                        if i != m + 2:
                            a[i, i - 3] = 0.0
                    for k in range(m, nn):
                        if k != m:
                            p = a[k, k - 1]
                            q = a[k + 1, k - 1]
                            r = 0.0
                            if k != nn - 1:
                                r = a[k + 2, k - 1]
                            x = abs(p) + abs(q) + abs(r)
                            if x != 0.0:
                                p /= x
                                q /= x
                                r /= x
                        s = math.sqrt(p * p + q * q + r * r)
                        if p < 0.0:
                            s = -s
                        if s != 0.0:
                            if k == m:
                                if l != m:
                                    a[k, k - 1] = -a[k, k - 1]
                            else:
                                a[k, k - 1] = -s * x
                            p += s
                            x = p / s
                            y = q / s
                            z = r / s
                            q /= p
                            r /= p
                            for j in range(k, nn + 1):
                                p = a[k, j] + q * a[k + 1, j]
                                if k != nn - 1:
                                    p += r * a[k + 2, j]
                                    a[k + 2, j] -= p * z
                                a[k + 1, j] -= p * y
                                a[k, j] -= p * x
                            mmin = nn if nn < k + 3 else k + 3
                            for i in range(l, mmin + 1):
                                p = x * a[i, k] + y * a[i, k + 1]
                                if k != nn - 1:
                                    p += z * a[i, k + 2]
                                    a[i, k + 2] -= p * r
                                a[i, k + 1] -= p * q
                                a[i, k] -= p
            if not l < nn - 1:
                break
    return True


@numba.njit(cache=False)
def eigenvalues(A, wr, wi):
    """Eigenvalues ``wr + i wi`` of the real square ``A`` (destroyed); a complex pair is stored as
    adjacent entries ``w, conj(w)``. False if the QR iteration does not converge."""
    _balance(A)
    _hessenberg(A)
    return _hqr(A, wr, wi)


@numba.njit(cache=False)
def _size(c):
    """``|re| + |im|``: LAPACK's measure for complex pivots (no square root)."""
    return abs(c.real) + abs(c.imag)


@numba.njit(cache=False)
def complex_lu(G, piv):
    """In-place LU with partial pivoting of the complex square ``G`` (pivots by ``|re| + |im|`` as LAPACK's), a
    pivot below ``1e-17`` times the largest entry replaced by that floor (a nearly singular ``G`` is wanted
    here: inverse iteration); solve with :func:`lu_solve`. A real ``G`` gives the values of the complex
    computation on it (zero imaginary parts stay zero)."""
    floored_lu(G, piv, np.empty(G.shape[0], dtype=G.dtype))


@numba.njit(cache=False)
def floored_lu(G, piv, inv, scale=0.0):
    """:func:`complex_lu`, the reciprocals of the pivots into ``inv`` (for :func:`inverse_solve`); the floor
    ``1e-17`` times the larger of the largest entry and ``scale`` (that of a larger matrix ``G`` is a block of)."""
    m = G.shape[0]
    big = scale
    for i in range(m):
        for j in range(m):
            big = max(big, _size(G[i, j]))
    floor = max(big * 1e-17, 1e-300)
    for k in range(m):
        p, size = k, _size(G[k, k])
        for i in range(k + 1, m):
            s = _size(G[i, k])
            if s > size:
                p, size = i, s
        piv[k] = p
        if p != k:
            for j in range(m):
                G[k, j], G[p, j] = G[p, j], G[k, j]
        if _size(G[k, k]) < floor:
            G[k, k] = floor
        inverse = 1.0 / G[k, k]
        inv[k] = inverse
        for i in range(k + 1, m):
            f = G[i, k] * inverse
            G[i, k] = f
            if f != 0.0:
                for j in range(k + 1, m):
                    G[i, j] -= f * G[k, j]


@numba.njit(cache=False)
def inverse_solve(LU, piv, inv, x):
    """``x = A^-1 x`` in place from :func:`floored_lu`'s factors, dividing by the pivots as multiplying by their
    reciprocals ``inv`` (a complex division costs several multiplications)."""
    _substitute(LU, piv, x, inv)


@numba.njit(cache=False)
def complex_null_vector(G, x):
    """A vector ``x`` with ``G x ~ 0`` for a nearly singular complex ``G`` (destroyed): one inverse-iteration
    step, ``G x = e`` (``e`` all ones) by :func:`complex_lu` and :func:`lu_solve`."""
    null_vector_into(G, np.empty(G.shape[0], dtype=np.int64), x)


@numba.njit(cache=False)
def null_vector_into(G, piv, x):
    """:func:`complex_null_vector` with the pivot array given; real or complex (a real ``G`` with a real ``x``
    gives the complex computation's values: its imaginary parts stay zero)."""
    complex_lu(G, piv)
    for i in range(G.shape[0]):
        x[i] = 1.0
    lu_solve(G, piv, x, x)


def _pack(like, re, im):
    """``re + i im`` if ``like`` is complex, else ``re`` (in the kernels by :func:`_pack_typed`, on the type)."""
    return complex(re, im) if isinstance(like, complex) else re


@overload(_pack)
def _pack_typed(like, re, im):
    if isinstance(like, types.Complex):
        return lambda like, re, im: complex(re, im)
    return lambda like, re, im: re


@numba.njit(cache=False)
def _quadratic_matrix(A1, A0, s, G):
    """``G = A0 + s A1 - s^2 I`` (a real matrix times the real and imaginary parts of ``s`` apart: the values of
    the complex products, at half the operations)."""
    m = A0.shape[0]
    sr, si = s.real, s.imag
    for r in range(m):
        for c in range(m):
            a = A1[r, c]
            G[r, c] = _pack(s, A0[r, c] + sr * a, si * a)
        G[r, r] -= s * s


@numba.njit(cache=False)
def row_norms(A1, A0):
    """``(||A0||, ||A1||)``: the largest absolute row sums of two square matrices (:func:`eigenpair_near`)."""
    m = A0.shape[0]
    n0 = 0.0
    n1 = 0.0
    for r in range(m):
        s0 = 0.0
        s1 = 0.0
        for c in range(m):
            s0 += abs(A0[r, c])
            s1 += abs(A1[r, c])
        n0 = max(n0, s0)
        n1 = max(n1, s1)
    return n0, n1


@numba.njit(cache=False)
def quadratic_eigenpair(A1, A0, sigma, u, max_shifts=3, steps=4, rtol=1e-12):
    """The eigenpair ``(lam, u)`` of ``lam^2 u = lam A1 u + A0 u`` nearest ``sigma`` (complex; the eigenvalue of
    the companion matrix ``[[0, I], [A0, A1]]`` nearest it) by shifted inverse iteration from the start vector
    ``u`` (complex, replaced by the eigenvector, unit norm).

    Inverse iteration on the companion matrix, each step one solve with ``A0 + s A1 - s^2 I`` (size ``m``, not
    ``2m``); up to ``steps`` steps per shift ``s``, the shift then moved to the eigenvalue estimate (at most
    ``max_shifts`` factorisations). Converged when two successive estimates agree to ``rtol`` times
    ``|lam| + sqrt(||A0||) + ||A1||`` and the residual ``||(A0 + lam A1 - lam^2 I) u||`` is below
    ``1e3 * rtol`` times ``(||A0|| + |lam| ||A1|| + |lam|^2)`` (norms: largest absolute row sums). Returns
    ``(lam, converged)``. The work of :func:`eigenpair_near`, with its norms and work arrays made here.
    """
    m = A0.shape[0]
    n0, n1 = row_norms(A1, A0)
    G = np.empty((m, m), dtype=np.complex128)
    piv = np.empty(m, dtype=np.int64)
    w = np.empty(m, dtype=np.complex128)
    b = np.empty(m, dtype=np.complex128)
    inv = np.empty(m, dtype=np.complex128)
    return eigenpair_near(A1, A0, n0, n1, sigma, u, G, piv, w, b, inv, max_shifts, steps, rtol)


@numba.njit(cache=False)
def eigenpair_near(A1, A0, n0, n1, sigma, u, G, piv, w, b, inv, max_shifts=3, steps=4, rtol=1e-12, floor=0.0):
    """:func:`quadratic_eigenpair` with the norms ``n0 = ||A0||``, ``n1 = ||A1||`` (:func:`row_norms`) and the
    work arrays ``G`` (m, m), ``piv``, ``w``, ``b``, ``inv`` (m) given. Complex (``sigma``, ``u``, the work arrays
    complex) or real (all of them real: the iteration from a real shift and a real start vector, whose complex
    form stays real to the last bit, at a quarter of the cost); ``lam`` of the type of ``sigma``. ``floor``: the
    ``scale`` of :func:`floored_lu`'s floor (for a block of a larger problem, the larger one's size of entries: a
    block singular to the last bit, e.g. a multiple of the identity, then gives finite iterates as it does
    inside the larger matrix)."""
    m = A0.shape[0]
    for r in range(m):
        w[r] = sigma * u[r]
    lam = sigma
    estimate = sigma
    have = False
    for shift in range(max_shifts):
        s = lam
        _quadratic_matrix(A1, A0, s, G)
        floored_lu(G, piv, inv, floor)
        for step in range(steps):
            # (C - s I) [u'; w'] = [u; w]: (A0 + s A1 - s^2 I) u' = w - (A1 - s I) u, w' = u + s u'
            for r in range(m):
                t = w[r] + s * u[r]
                tr, ti = t.real, t.imag
                for c in range(m):
                    a = A1[r, c]
                    tr -= a * u[c].real
                    ti -= a * u[c].imag
                b[r] = _pack(t, tr, ti)
            inverse_solve(G, piv, inv, b)
            num = sigma * 0.0  # zero of the shift's type (the shift is finite)
            den = 0.0
            size = 0.0
            for r in range(m):
                wn = u[r] + s * b[r]
                num += u[r].conjugate() * b[r] + w[r].conjugate() * wn
                den += u[r].real ** 2 + u[r].imag ** 2 + w[r].real ** 2 + w[r].imag ** 2
                size += b[r].real ** 2 + b[r].imag ** 2 + wn.real ** 2 + wn.imag ** 2
                w[r] = wn
            if num == 0.0 or size == 0.0 or not math.isfinite(size):
                return lam, False
            scale = 1.0 / math.sqrt(size)
            for r in range(m):
                u[r] = b[r] * scale
                w[r] *= scale
            new = s + den / num  # 1 / theta, theta = v^H v' / v^H v
            if have and abs(new - estimate) <= rtol * (abs(new) + math.sqrt(n0) + n1):
                lam = new
                # the residual of the quadratic problem at (lam, u)
                worst = 0.0
                for r in range(m):
                    r0 = i0 = r1 = i1 = 0.0
                    for c in range(m):
                        ur, ui = u[c].real, u[c].imag
                        r0 += A0[r, c] * ur
                        i0 += A0[r, c] * ui
                        r1 += A1[r, c] * ur
                        i1 += A1[r, c] * ui
                    t0 = _pack(lam, r0, i0)
                    t1 = _pack(lam, r1, i1)
                    worst = max(worst, abs(t0 + lam * t1 - lam * lam * u[r]))
                norm = 0.0
                for r in range(m):
                    norm = max(norm, abs(u[r]))
                bound = 1e3 * rtol * (n0 + abs(lam) * n1 + abs(lam) ** 2) * norm
                return lam, worst <= bound
            estimate = new
            have = True
        lam = estimate
    return lam, False
