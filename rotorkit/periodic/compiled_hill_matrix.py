"""Hill's matrix of a point for the compiled harmonic-balance path (:mod:`rotorkit.periodic.compiled_hill`).

The lower blocks of Hill's companion matrix of
:func:`rotorkit.periodic.stability.hill_exponents`, from the Jacobian of the
model at the AFT samples of the point, its change from rest projected onto
the harmonics by sums of ``cos m t``, ``sin m t`` (``m <= 2H``) over the
samples (:func:`hill_matrix`, the table of those sums per block
:func:`block_table`).
"""

from __future__ import annotations

import numba
import numpy as np

from .compiled_aft import aft_states
from .eigen import eigenpair_near, eigenvalues

__all__ = ["block_table", "hill_matrix", "harmonic_groups", "group_eigenvalues", "group_workspace", "group_of",
           "follow_exponent"]


@numba.njit(cache=False)
def block_table(H):
    """The sums giving block ``(c, d)`` of ``proj(D) = P diag(D_j) E`` (:func:`hill_matrix`): ``kk[c, d]``,
    ``cc[c, d]`` such that the block is ``w_c (cc[c, d, 0] S[kk[c, d, 0]] + cc[c, d, 1] S[kk[c, d, 1]])`` (``S[2 m]``,
    ``S[2 m + 1]`` the sums of ``cos(m t_j) D_j``, ``sin(m t_j) D_j``; ``w_c = 1 / N`` for ``c = 0``, else
    ``2 / N``): ``P[c, j] E[j, d]`` is a product of two of 1, ``cos a t``, ``sin a t``, half a sum of two of
    ``cos m t``, ``sin m t`` (``m <= 2H``)."""
    H2 = 2 * H + 1
    kk = np.zeros((H2, H2, 2), dtype=np.int64)
    cc = np.zeros((H2, H2, 2))
    for c in range(H2):
        a = (c + 1) // 2
        ka = 0 if c == 0 else 2 - c % 2  # harmonic of row block c; kind: 0 constant, 1 cos, 2 sin
        for d in range(H2):
            b = (d + 1) // 2
            kb = 0 if d == 0 else 2 - d % 2
            lo = abs(a - b)
            sg = 1.0 if a >= b else -1.0
            hi = a + b
            k1, c1, k2, c2 = 0, 1.0, 0, 0.0  # rows 2 m: cosines, 2 m + 1: sines
            if ka == 0 and kb == 0:
                pass
            elif ka == 0:
                k1 = 2 * b if kb == 1 else 2 * b + 1
                k2 = k1
            elif kb == 0:
                k1 = 2 * a if ka == 1 else 2 * a + 1
                k2 = k1
            elif ka == 1 and kb == 1:  # cos a cos b
                k1, c1, k2, c2 = 2 * lo, 0.5, 2 * hi, 0.5
            elif ka == 2 and kb == 2:  # sin a sin b
                k1, c1, k2, c2 = 2 * lo, 0.5, 2 * hi, -0.5
            elif ka == 1:  # cos a sin b
                k1, c1, k2, c2 = 2 * hi + 1, 0.5, 2 * lo + 1, -0.5 * sg
            else:  # sin a cos b
                k1, c1, k2, c2 = 2 * hi + 1, 0.5, 2 * lo + 1, 0.5 * sg
            kk[c, d, 0], kk[c, d, 1] = k1, k2
            cc[c, d, 0], cc[c, d, 1] = c1, c2
    return kk, cc


@numba.njit(cache=False)
def hill_matrix(z, omega, period, p, A0, jac, ints, E, ED, y, Aj, f, F, cs, used, kk, cc, Q, V):
    """The lower blocks ``A21``, ``A22`` of Hill's matrix ``[[0, I], [A21, A22]]`` of
    :func:`rotorkit.periodic.stability.hill_exponents` into the workspace, on the frame ``p``, ``A0``,
    ``omega``, ``period`` at the point's speed (work arrays of :func:`~rotorkit.periodic.compiled_hill.hill_workspace`).

    The reference's ``A21 = -kron(I, M^-1) (Kt + Ct kron(wD, I) + kron(wD^2, M))`` and
    ``A22 = -kron(I, M^-1) (2 kron(wD, M) + Ct)``, with ``Kt = K0 - proj(M Dq)``, ``Ct = C0 - proj(M Dv)``,
    ``K0 = -M A_q``, ``C0 = -M A_v`` (``Dq``, ``Dv`` the acceleration Jacobian's change from rest at the AFT
    samples), without the mass matrix, which cancels: ``A21 = Q + V kron(wD, I) - kron(wD^2, I)`` and
    ``A22 = V - 2 kron(wD, I)``, ``Q = blockdiag(A_q) + proj(Dq)``, ``V = blockdiag(A_v) + proj(Dv)`` (equal to
    rounding).

    ``proj(D) = P diag(D_j) E`` block by block from the sums ``F[r, 2 m] = sum_j cos(m t_j) D_j[r]``,
    ``F[r, 2 m + 1] = sum_j sin(m t_j) D_j[r]`` (``m <= 2H``; ``D_j = (Dq, Dv)`` flat, ``r < 2 n^2``) and the
    table of :func:`block_table` (``kk``, ``cc``): the same sums as the products, fewer operations; an entry
    ``r`` zero at every sample (``used[r]`` False: e.g. no contact, or a force without velocity terms) is not
    summed (the same values: adding zeros)."""
    n, H, N = ints[0], ints[1], ints[2]
    H2 = 2 * H + 1
    nn = n * n
    F[:, :] = 0.0
    used[:] = False
    for j in range(N):
        aft_states(z, j, omega, E, ED, n, y)
        Aj[:, :] = 0.0
        jac(period * j / N, y, p, Aj)
        for i in range(n):
            for l in range(n):
                f[i * n + l] = Aj[n + i, l] - A0[n + i, l]
                f[nn + i * n + l] = Aj[n + i, n + l] - A0[n + i, n + l]
        cs[0], cs[1] = 1.0, 0.0  # cos m t_j, sin m t_j interleaved
        for m in range(1, H + 1):
            cs[2 * m], cs[2 * m + 1] = E[j, 2 * m - 1], E[j, 2 * m]
        for m in range(H + 1, H2):  # cos/sin (H + k) t from the addition theorems
            k = m - H
            cs[2 * m] = cs[2 * H] * cs[2 * k] - cs[2 * H + 1] * cs[2 * k + 1]
            cs[2 * m + 1] = cs[2 * H + 1] * cs[2 * k] + cs[2 * H] * cs[2 * k + 1]
        for r in range(2 * nn):
            fr = f[r]
            if fr == 0.0:  # zero here (at rest or out of contact at this instant)
                continue
            used[r] = True
            row = F[r]
            for m in range(2 * H2):
                row[m] += cs[m] * fr
    for c in range(H2):  # V first: Q's blocks take V's (before its wD part) times wD
        weight = (1.0 if c == 0 else 2.0) / N
        for d in range(H2):
            k1, k2 = kk[c, d, 0], kk[c, d, 1]
            c1, c2 = cc[c, d, 0], cc[c, d, 1]
            diag = c == d
            for i in range(n):
                for l in range(n):
                    e = i * n + l
                    v = A0[n + i, n + l] if diag else 0.0
                    if used[nn + e]:
                        v += weight * (c1 * F[nn + e, k1] + c2 * F[nn + e, k2])
                    V[c * n + i, d * n + l] = v
    for c in range(H2):
        weight = (1.0 if c == 0 else 2.0) / N
        for d in range(H2):
            k1, k2 = kk[c, d, 0], kk[c, d, 1]
            c1, c2 = cc[c, d, 0], cc[c, d, 1]
            diag = c == d
            k = (d + 1) // 2
            wk = omega * k
            for i in range(n):
                for l in range(n):
                    e = i * n + l
                    q = A0[n + i, l] if diag else 0.0
                    if used[e]:
                        q += weight * (c1 * F[e, k1] + c2 * F[e, k2])
                    if d > 0:  # V kron(wD, I): wD[2k-1, 2k] = k w, wD[2k, 2k-1] = -k w
                        if d % 2 == 0:
                            q += wk * V[c * n + i, (d - 1) * n + l]
                        else:
                            q -= wk * V[c * n + i, (d + 1) * n + l]
                    Q[c * n + i, d * n + l] = q
    for k in range(1, H + 1):  # wD^2 = diag(0, -(w k)^2 twice per k)
        wk = omega * k
        ca, sb = (2 * k - 1) * n, 2 * k * n
        for i in range(n):
            Q[ca + i, ca + i] += wk * wk
            Q[sb + i, sb + i] += wk * wk
            V[ca + i, sb + i] -= 2.0 * wk
            V[sb + i, ca + i] += 2.0 * wk


@numba.njit(cache=False)
def harmonic_groups(A21, A22, n, H, group):
    """The harmonics Hill's matrix couples, in groups: ``group[k]`` (``k = 0 ... H``) the lowest harmonic of
    ``k``'s group (harmonic ``k``'s rows and columns: ``n`` for ``k = 0``, the ``2n`` of ``a_k``, ``b_k``
    otherwise); two harmonics are coupled where an entry of ``A21`` or ``A22`` (of :func:`hill_matrix`) joining
    them exceeds the rounding of the matrix, ``eps`` times its largest absolute row sum (a perturbation below
    the QR iteration's own backward error). One group per harmonic for a time-invariant Jacobian along the
    orbit (e.g. out of contact); even and odd harmonics apart for a Jacobian of harmonics 0 and 2 only (a
    circular orbit of an isotropic rotor). Returns the number of groups."""
    size = A21.shape[0]
    norm = 0.0
    for i in range(size):
        row = 0.0
        for c in range(size):
            row += abs(A21[i, c]) + abs(A22[i, c])
        norm = max(norm, row)
    tol = 2.220446049250313e-16 * norm
    for k in range(H + 1):
        group[k] = k
    for i in range(size):
        a = (i // n + 1) // 2
        for c in range(size):
            b = (c // n + 1) // 2
            if a != b and (abs(A21[i, c]) > tol or abs(A22[i, c]) > tol):
                ga, gb = group[a], group[b]
                if ga != gb:  # merge: every member of the higher group joins the lower
                    lo, hi = min(ga, gb), max(ga, gb)
                    for k in range(H + 1):
                        if group[k] == hi:
                            group[k] = lo
    count = 0
    for k in range(H + 1):
        if group[k] == k:
            count += 1
    return count


@numba.njit(cache=False)
def group_eigenvalues(A21, A22, n, H, group, wr, wi):
    """The eigenvalues ``wr + i wi`` of Hill's companion matrix ``[[0, I], [A21, A22]]`` group by group of
    :func:`harmonic_groups` (the entries joining two groups taken as zero): those of each group's companion
    matrix (twice its harmonics' rows; :func:`~rotorkit.periodic.eigen.eigenvalues`, a complex pair stored as
    there), in the order of the groups' lowest harmonics. False if one does not converge."""
    size = A21.shape[0]
    rows = np.empty(size, dtype=np.int64)
    at = 0
    for g in range(H + 1):
        if group[g] != g:
            continue
        m = 0
        for i in range(size):
            if group[(i // n + 1) // 2] == g:
                rows[m] = i
                m += 1
        big = np.zeros((2 * m, 2 * m))
        re = np.empty(2 * m)
        im = np.empty(2 * m)
        for i in range(m):
            big[i, m + i] = 1.0
            for c in range(m):
                big[m + i, c] = A21[rows[i], rows[c]]
                big[m + i, m + c] = A22[rows[i], rows[c]]
        if not eigenvalues(big, re, im):
            return False
        wr[at:at + 2 * m] = re
        wi[at:at + 2 * m] = im
        at += 2 * m
    return True


@numba.njit(cache=False)
def group_workspace(n, H):
    """The work arrays of :func:`follow_exponent` (n coordinates, H harmonics), made once per branch:
    ``(group, rows, f21, f22, fGr, fG, v)``, the flat ones (``size^2``) viewed as square per group."""
    size = n * (2 * H + 1)
    return (np.empty(H + 1, dtype=np.int64), np.empty(size, dtype=np.int64), np.empty(size * size),
            np.empty(size * size), np.empty(size * size), np.empty(size * size, dtype=np.complex128),
            np.empty(size, dtype=np.complex128))


@numba.njit(cache=False)
def group_of(u, n, group):
    """The group (``group`` of :func:`harmonic_groups`) holding every entry of ``u`` above ``1e-12`` times its
    largest (by modulus), -1 if they lie in several groups (or ``u`` is zero)."""
    big = 0.0
    for r in range(u.shape[0]):
        big = max(big, u[r].real ** 2 + u[r].imag ** 2)
    floor = 1e-24 * big
    g = -1
    for r in range(u.shape[0]):
        if u[r].real ** 2 + u[r].imag ** 2 > floor:
            k = group[(r // n + 1) // 2]
            if g < 0:
                g = k
            elif k != g:
                return -1
    return g


@numba.njit(cache=False)
def _follow(A21, A22, n0, n1, sigma, u, Gr, ur, wr, br, invr, piv, G, w, b, inv, scale):
    """:func:`~rotorkit.periodic.eigen.eigenpair_near` of Hill's quadratic problem from the shift ``sigma`` and
    the start vector ``u`` (replaced by the eigenvector): ``(lam, converged)``; in real arithmetic where both
    are real (the complex iteration's values); ``scale`` the pivots' floor (0: the matrix's own)."""
    real = sigma.imag == 0.0
    for r in range(u.shape[0]):
        real = real and u[r].imag == 0.0
    if real:
        for r in range(u.shape[0]):
            ur[r] = u[r].real
        lam, ok = eigenpair_near(A22, A21, n0, n1, sigma.real, ur, Gr, piv, wr, br, invr, 3, 4, 1e-12, scale)
        for r in range(u.shape[0]):
            u[r] = ur[r]
        return complex(lam, 0.0), ok
    return eigenpair_near(A22, A21, n0, n1, sigma, u, G, piv, w, b, inv, 3, 4, 1e-12, scale)


@numba.njit(cache=False)
def follow_exponent(A21, A22, n, groups, group, rows, f21, f22, fGr, fG, v, n0, n1, sigma, u, Gr, ur, wr, br, invr,
                    piv, G, w, b, inv):
    """The eigenpair of Hill's quadratic problem ``A21 + lam A22 - lam^2 I`` nearest the shift ``sigma`` by
    shifted inverse iteration from the start vector ``u`` (replaced by the eigenvector): ``(lam, converged)``
    (:func:`~rotorkit.periodic.eigen.eigenpair_near`; in real arithmetic where ``sigma`` and ``u`` are real).

    Where Hill's matrix splits into ``groups > 1`` groups of coupled harmonics (``group`` of
    :func:`harmonic_groups`) and ``u`` lies in one of them (:func:`group_of`), the iteration runs on that
    group's rows and columns only (copied into the work arrays ``rows``, ``f21``, ``f22``, ``fGr``, ``fG``,
    ``v`` of :func:`group_workspace`), the stopping rule on the whole matrix's norms ``n0 = ||A21||``,
    ``n1 = ||A22||``, the pivots' floor on their bound ``n0 + |sigma| n1 + |sigma|^2`` of the whole matrix's
    entries (a group's block may be singular to the last bit where the whole matrix is not: out of contact a
    multiple of the identity at the exponent), the eigenvector zero outside the group; else on the whole
    matrix."""
    g = group_of(u, n, group) if groups > 1 else -1
    if g < 0:
        return _follow(A21, A22, n0, n1, sigma, u, Gr, ur, wr, br, invr, piv, G, w, b, inv, 0.0)
    m = 0
    for i in range(u.shape[0]):
        if group[(i // n + 1) // 2] == g:
            rows[m] = i
            m += 1
    a21 = f21[:m * m].reshape(m, m)
    a22 = f22[:m * m].reshape(m, m)
    for i in range(m):
        ri = rows[i]
        for c in range(m):
            a21[i, c] = A21[ri, rows[c]]
            a22[i, c] = A22[ri, rows[c]]
        v[i] = u[ri]
    x = v[:m]
    lam, ok = _follow(a21, a22, n0, n1, sigma, x, fGr[:m * m].reshape(m, m), ur[:m], wr[:m], br[:m], invr[:m],
                      piv[:m], fG[:m * m].reshape(m, m), w[:m], b[:m], inv[:m], n0 + abs(sigma) * n1 + abs(sigma) ** 2)
    u[:] = 0.0
    for i in range(m):
        u[rows[i]] = x[i]
    return lam, ok
