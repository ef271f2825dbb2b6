"""numba kernel of the compiled harmonic-balance path's per-point data: the error estimate and Hill's multipliers.

It repeats what the Python reference does (the truncation-error estimate of
:mod:`rotorkit.analysis.periodic` and
:func:`~rotorkit.periodic.stability.hill_multipliers`), with the frame at each
point's speed rebuilt by :func:`rotorkit.periodic.compiled.speed_frame`; the
settings ``ints``/``fl`` are those of :mod:`rotorkit.periodic.compiled`
(``ints[10]``: whether Hill's multipliers are computed). The glue is in
:mod:`rotorkit.periodic.fastpath`.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .compiled import aft_states, force_scale, frame_at, local_jacobian, speed_frame
from .eigen import complex_null_vector, eigenvalues

__all__ = ["point_data_kernel"]


@numba.njit(cache=False)
def _hill(z, lam, jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window, mu_re, mu_im):
    """:func:`rotorkit.periodic.stability.hill_multipliers` into ``mu_re + i mu_im`` (2n); False if the QR
    iteration fails."""
    n, H, N = ints[0], ints[1], ints[2]
    H2 = 2 * H + 1
    size = n * H2
    p, A0, L, omega, period = frame_at(lam, jac, ints, fl, base, varying, coef, window, M, size)
    # Kt = K0 - proj(Fq), Ct = C0 - proj(Fv) (block diagonal K0, C0)
    Kt = np.zeros((size, size))
    Ct = np.zeros((size, size))
    for h in range(H2):
        for i in range(n):
            for l in range(n):
                kk = 0.0
                cc = 0.0
                for j in range(n):
                    kk -= M[i, j] * A0[n + j, l]
                    cc -= M[i, j] * A0[n + j, n + l]
                Kt[h * n + i, h * n + l] = kk
                Ct[h * n + i, h * n + l] = cc
    y = np.empty(2 * n)
    Aj = np.empty((2 * n, 2 * n))
    Fq = np.empty((n, n))
    Fv = np.empty((n, n))
    Qq = np.empty((n, size))
    Qv = np.empty((n, size))
    for j in range(N):
        aft_states(z, j, omega, E, ED, n, y)
        Aj[:, :] = 0.0
        jac(period * j / N, y, p, Aj)
        if not local_jacobian(M, Aj, A0, n, Fq, Fv):
            continue
        for i in range(n):
            for d in range(H2):
                for l in range(n):
                    Qq[i, d * n + l] = E[j, d] * Fq[i, l]
                    Qv[i, d * n + l] = E[j, d] * Fv[i, l]
        for c in range(H2):
            pc = P[c, j]
            for i in range(n):
                row = c * n + i
                for col in range(size):
                    Kt[row, col] -= pc * Qq[i, col]
                    Ct[row, col] -= pc * Qv[i, col]
    # wD (H2, H2): D[2k-1, 2k] = k, D[2k, 2k-1] = -k
    wD = np.zeros((H2, H2))
    for k in range(1, H + 1):
        wD[2 * k - 1, 2 * k] = omega * k
        wD[2 * k, 2 * k - 1] = -omega * k
    wD2 = wD @ wD
    # J = Kt + Ct (kron(wD, I)) + kron(wD^2, M); D1 = 2 kron(wD, M) + Ct
    Jh = Kt.copy()
    for r in range(size):
        for d in range(H2):
            for l in range(n):
                s = 0.0
                for c in range(H2):
                    if wD[c, d] != 0.0:
                        s += Ct[r, c * n + l] * wD[c, d]
                Jh[r, d * n + l] += s
    D1 = Ct.copy()
    for c in range(H2):
        for d in range(H2):
            for i in range(n):
                for l in range(n):
                    Jh[c * n + i, d * n + l] += wD2[c, d] * M[i, l]
                    D1[c * n + i, d * n + l] += 2.0 * wD[c, d] * M[i, l]
    # A21 = -kron(I, Minv) J, A22 = -kron(I, Minv) D1
    A21 = np.empty((size, size))
    A22 = np.empty((size, size))
    for h in range(H2):
        for i in range(n):
            for col in range(size):
                s1 = 0.0
                s2 = 0.0
                for j in range(n):
                    s1 += Minv[i, j] * Jh[h * n + j, col]
                    s2 += Minv[i, j] * D1[h * n + j, col]
                A21[h * n + i, col] = -s1
                A22[h * n + i, col] = -s2
    big = np.zeros((2 * size, 2 * size))
    for i in range(size):
        big[i, size + i] = 1.0
        for col in range(size):
            big[size + i, col] = A21[i, col]
            big[size + i, size + col] = A22[i, col]
    wr = np.empty(2 * size)
    wi = np.empty(2 * size)
    if not eigenvalues(big, wr, wi):
        return False
    # centre of each eigenvector: the null vector p of A21 + lam A22 - lam^2 I (conjugates: minus the partner's)
    count = 2 * size
    centre = np.empty(count)
    done = np.zeros(count, dtype=np.bool_)
    G = np.empty((size, size), dtype=np.complex128)
    x = np.empty(size, dtype=np.complex128)
    power = np.empty(H2)
    for e in range(count):
        if done[e]:
            continue
        lam_e = complex(wr[e], wi[e])
        for r in range(size):
            for c in range(size):
                G[r, c] = A21[r, c] + lam_e * A22[r, c]
            G[r, r] -= lam_e * lam_e
        complex_null_vector(G, x)
        for k in range(H2):
            power[k] = 0.0
        for i in range(n):
            power[H] += x[i].real ** 2 + x[i].imag ** 2
        for k in range(1, H + 1):
            for i in range(n):
                a = x[(2 * k - 1) * n + i]
                b = x[2 * k * n + i]
                minus = a - 1j * b
                plus = a + 1j * b
                power[H + k] += (minus.real ** 2 + minus.imag ** 2) / 4.0
                power[H - k] += (plus.real ** 2 + plus.imag ** 2) / 4.0
        total = 0.0
        weighted = 0.0
        for k in range(H2):
            total += power[k]
            weighted += (k - H) * power[k]
        centre[e] = weighted / max(total, 1e-300)
        done[e] = True
        if wi[e] != 0.0:  # the conjugate eigenvalue: the conjugate vector, harmonics mirrored
            for f in range(count):
                if not done[f] and wr[f] == wr[e] and wi[f] == -wi[e]:
                    centre[f] = -centre[e]
                    done[f] = True
                    break
    order = np.argsort(np.abs(centre), kind="mergesort")
    kept = np.empty(2 * n, dtype=np.int64)
    nk = 0
    for o in range(count):
        i = order[o]
        copy = False
        for q in range(nk):
            j = kept[q]
            # (lam_i - lam_j) / (i w)
            dre = (wi[i] - wi[j]) / omega
            dim = -(wr[i] - wr[j]) / omega
            rd = math.floor(dre + 0.5)
            if abs(dim) < 1e-6 and rd != 0 and abs(dre - rd) < 1e-6:
                copy = True
                break
        if copy:
            continue
        kept[nk] = i
        nk += 1
        if nk == 2 * n:
            break
    for q in range(2 * n):
        if q < nk:
            i = kept[q]
            mag = math.exp(wr[i] * period)
            mu_re[q] = mag * math.cos(wi[i] * period)
            mu_im[q] = mag * math.sin(wi[i] * period)
        else:
            mu_re[q] = np.nan
            mu_im[q] = np.nan
    return nk == 2 * n


@numba.njit(cache=False)
def point_data_kernel(rhs, jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window, EG, EDG, EDDG, lams, Zs,
                      errors, mu_re, mu_im, hill_ok):
    """Per point: the truncation-error estimate (max |M (q'' - a)| on the grid of ``EG``'s rows over the scale)
    and, with ``ints[10]``, Hill's multipliers (``hill_ok[i]`` False where the QR iteration failed)."""
    n = ints[0]
    H2 = E.shape[1]
    size = n * H2
    G = EG.shape[0]
    p = np.empty(base.shape[0])
    A0 = np.empty((2 * n, 2 * n))
    L = np.empty((size, size))
    y = np.empty(2 * n)
    a = np.empty(2 * n)
    acc = np.empty(n)
    for pt in range(lams.shape[0]):
        lam = lams[pt]
        z = Zs[pt]
        omega = speed_frame(lam, jac, ints, fl, base, varying, coef, window, M, p, A0, L)
        scale = force_scale(lam, rhs, jac, ints, fl, E, P, M, base, varying, coef, window)
        worst = 0.0
        for j in range(G):
            t = 2.0 * np.pi * j / (G * omega)
            for i in range(n):
                q = 0.0
                v = 0.0
                w2 = 0.0
                for h in range(H2):
                    c = z[h * n + i]
                    q += EG[j, h] * c
                    v += EDG[j, h] * c
                    w2 += EDDG[j, h] * c
                y[i] = q
                y[n + i] = omega * v
                acc[i] = omega * omega * w2
            a[:] = 0.0
            rhs(t, y, p, a)
            for i in range(n):
                s = 0.0
                for k in range(n):
                    s += (acc[k] - a[n + k]) * M[i, k]
                worst = max(worst, abs(s))
        errors[pt] = worst / scale
        if ints[10]:
            hill_ok[pt] = _hill(z, lam, jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window, mu_re[pt],
                                mu_im[pt])
