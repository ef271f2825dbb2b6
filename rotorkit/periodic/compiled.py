"""numba kernels of the compiled harmonic-balance path: the continuation loop (the per-point data: compiled_points).

They repeat, operation for operation, what the Python reference does
(:class:`~rotorkit.periodic.hb.HarmonicBalance` residual and AFT Jacobian,
:func:`~rotorkit.periodic.hb.newton`, :func:`~rotorkit.periodic.continuation.continue_branch`
with its grazing-corner rule and end at a bound, the truncation-error estimate of
:mod:`rotorkit.analysis.periodic` and :func:`~rotorkit.periodic.stability.hill_multipliers`),
with the model's ``rhs``/``jac``/``switches`` passed as first-class numba
functions, so that a whole branch runs in one call. The frame at a speed
(prepared parameters, linear part, AFT instants) is rebuilt inside from the
quadratic speed fit of :class:`~rotorkit.periodic.evaluate.Evaluator`. The
glue, the conditions and the fallbacks are in :mod:`rotorkit.periodic.fastpath`.

The continuation loop computes the same quantities as the reference with
less work: its work arrays are allocated once per call (the frame kept
while the speed is the same); the corrector's residual at the prediction
is both the base of the forward difference ``dR/dlambda`` and Newton's
first evaluation; and the AFT Jacobian ``sum_j P[c, j] (E[j, d] F_j + w
(E D)[j, d] V_j)`` is assembled from the cosine and sine sums of the
sampled force Jacobians up to harmonic ``2H`` (a product of two basis
functions is half a sum of two at the difference and the sum of their
harmonics: ``O(N n^2 H)`` per evaluation instead of ``O(N n^2 H^2)``), equal
to rounding.

Integer settings ``ints``: ``n, H, N, nu, n_switches, max_iterations, max_new, count, max_points, start``;
float settings ``fl``: ``s0, z_scale, l_scale, lo, hi, d_lam, h, min_step, max_step, tol, direction, bound``;
``ints[10]``: whether :func:`~rotorkit.periodic.compiled_points.point_data_kernel` computes Hill's multipliers.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .eigen import lu_factor, lu_solve

__all__ = ["continue_kernel", "speed_frame", "frame_at", "local_jacobian", "aft_states", "force_scale"]

# statuses of continue_kernel
PAUSED, BUDGET, BOUND, MIN_STEP = 0, 1, 2, 3


@numba.njit(cache=False)
def speed_frame(lam, jac, ints, fl, base, varying, coef, window, M, p, A0, L):
    """Prepared parameters ``p``, the Jacobian at rest ``A0`` (2n, 2n) and the linear operator ``L`` at speed
    ``lam``; returns the base frequency."""
    n, H, nu = ints[0], ints[1], ints[3]
    for k in range(base.shape[0]):
        p[k] = base[k]
    s = lam / fl[0]
    for k in range(varying.shape[0]):
        p[varying[k]] = coef[0, k] + s * (coef[1, k] + s * coef[2, k])
    p[p.shape[0] - 2] = window[0]
    p[p.shape[0] - 1] = window[1]
    A0[:, :] = 0.0
    jac(0.0, np.zeros(2 * n), p, A0)
    omega = lam / nu
    L[:, :] = 0.0
    for i in range(n):
        for l in range(n):
            kk = 0.0
            cc = 0.0
            for j in range(n):
                kk -= M[i, j] * A0[n + j, l]
                cc -= M[i, j] * A0[n + j, n + l]
            L[i, l] = kk
            for h in range(1, H + 1):
                a, b = 2 * h - 1, 2 * h
                kw = h * omega
                diagonal = kk - kw * kw * M[i, l]
                L[a * n + i, a * n + l] = diagonal
                L[b * n + i, b * n + l] = diagonal
                L[a * n + i, b * n + l] = kw * cc
                L[b * n + i, a * n + l] = -kw * cc
    return omega


@numba.njit(cache=False)
def frame_at(lam, jac, ints, fl, base, varying, coef, window, M, size):
    """The frame at ``lam`` in new arrays: ``(p, A0, L, omega, period)`` (:func:`speed_frame`)."""
    n = ints[0]
    p = np.empty(base.shape[0])
    A0 = np.empty((2 * n, 2 * n))
    L = np.empty((size, size))
    omega = speed_frame(lam, jac, ints, fl, base, varying, coef, window, M, p, A0, L)
    return p, A0, L, omega, 2.0 * np.pi / omega


@numba.njit(cache=False)
def local_jacobian(M, Aj, A0, n, Fq, Fv):
    """``Fq``, ``Fv`` (n, n): ``M`` times the local forces' part of the acceleration Jacobian ``Aj`` (``Aj - A0``
    in its displacement and velocity columns); False where both are zero (no contact at this instant)."""
    for i in range(n):
        for l in range(n):
            sq = 0.0
            sv = 0.0
            for k in range(n):
                sq += M[i, k] * (Aj[n + k, l] - A0[n + k, l])
                sv += M[i, k] * (Aj[n + k, n + l] - A0[n + k, n + l])
            Fq[i, l] = sq
            Fv[i, l] = sv
    return np.any(Fq != 0.0) or np.any(Fv != 0.0)


@numba.njit(cache=False)
def aft_states(z, j, omega, E, ED, n, y):
    H2 = E.shape[1]
    for i in range(n):
        q = 0.0
        v = 0.0
        for h in range(H2):
            q += E[j, h] * z[h * n + i]
            v += ED[j, h] * z[h * n + i]
        y[i] = q
        y[n + i] = omega * v


@numba.njit(cache=False)
def _workspace(ints, E, base):
    """Work arrays of one kernel call (the frame at a speed, cached by its speed, and the AFT loop's buffers):
    ``(p, A0, K, C, info, zero, Y, a, g, f, Aj, G, S, trig, terms, weights)``; ``info`` holds the speed
    of the frame in ``p``, ``A0``, ``K``, ``C``, its base frequency and period, and whether it is set;
    ``G``, ``S``, ``terms``, ``weights``: :func:`_projection_terms`."""
    n, N = ints[0], ints[2]
    H2 = E.shape[1]
    trig = np.empty((N, 2 * H2))  # cos(m tau_j), sin(m tau_j) for m = 0 ... 2H: products of two basis functions
    for j in range(N):
        for m in range(H2):
            angle = 2.0 * np.pi * ((m * j) % N) / N
            trig[j, 2 * m] = math.cos(angle)
            trig[j, 2 * m + 1] = math.sin(angle)
    terms, weights = _projection_terms(H2, N)
    return (np.empty(base.shape[0]), np.empty((2 * n, 2 * n)), np.empty((n, n)), np.empty((n, n)), np.zeros(4),
            np.zeros(2 * n), np.empty((N, 2 * n)), np.empty(2 * n), np.empty(n), np.empty((N, n)), np.empty((2 * n, 2 * n)),
            np.empty(2 * n * n), np.empty((2 * H2, 2 * n * n)), trig, terms, weights)


@numba.njit(cache=False)
def _projection_terms(H2, N):
    """The AFT projection of the sampled force Jacobians, ``F_j`` (coordinates, entries ``G[j, :n n]``) and
    ``V_j`` (velocities, ``G[j, n n:]``), from their sums ``S[2 m] = sum_j cos(m tau_j) G_j`` and
    ``S[2 m + 1] = sum_j sin(m tau_j) G_j``, ``m = 0 ... 2H``: block ``(c, d)`` of
    ``sum_j P[c, j] (E[j, d] F_j + w ED[j, d] V_j)`` is ``sum_t weights[c, d, t] S[terms[c, d, t]]`` (of the
    ``F`` entries for t = 0, 1, of the ``V`` entries times ``w`` for t = 2, 3).

    Basis function ``c``: ``cos(k tau)`` (c = 2k - 1, and c = 0 with k = 0) or ``sin(k tau)`` (c = 2k); a product
    of two is half a sum of two at ``k1 - k2`` and ``k1 + k2``; ``d/dtau cos(k tau) = -k sin(k tau)``,
    ``d/dtau sin(k tau) = k cos(k tau)``."""
    terms = np.zeros((H2, H2, 4), dtype=np.int64)
    weights = np.zeros((H2, H2, 4))
    for c in range(H2):
        tc, kc = (0, 0) if c == 0 else ((c + 1) % 2, (c + 1) // 2)
        wc = (1.0 if c == 0 else 2.0) / N
        for d in range(H2):
            td, kd = (0, 0) if d == 0 else ((d + 1) % 2, (d + 1) // 2)
            for part in range(2):  # 0: E[j, d] F_j; 1: ED[j, d] G_j
                if part == 0:
                    t2, factor = td, wc
                else:
                    if d == 0:
                        continue
                    t2, factor = 1 - td, (-kd if td == 0 else kd) * wc
                diff, total = kc - kd, kc + kd
                sign = -1.0 if diff < 0 else 1.0
                kind = 0
                t = 2 * part
                if tc == 0 and t2 == 0:  # cos cos = (cos(k1 - k2) + cos(k1 + k2)) / 2
                    terms[c, d, t], weights[c, d, t] = 2 * abs(diff) + kind, 0.5 * factor
                    terms[c, d, t + 1], weights[c, d, t + 1] = 2 * total + kind, 0.5 * factor
                elif tc == 1 and t2 == 1:  # sin sin = (cos(k1 - k2) - cos(k1 + k2)) / 2
                    terms[c, d, t], weights[c, d, t] = 2 * abs(diff) + kind, 0.5 * factor
                    terms[c, d, t + 1], weights[c, d, t + 1] = 2 * total + kind, -0.5 * factor
                elif tc == 1:  # sin k1 cos k2 = (sin(k1 + k2) + sin(k1 - k2)) / 2
                    terms[c, d, t], weights[c, d, t] = 2 * total + kind + 1, 0.5 * factor
                    terms[c, d, t + 1], weights[c, d, t + 1] = 2 * abs(diff) + kind + 1, 0.5 * sign * factor
                else:  # cos k1 sin k2 = (sin(k1 + k2) - sin(k1 - k2)) / 2
                    terms[c, d, t], weights[c, d, t] = 2 * total + kind + 1, 0.5 * factor
                    terms[c, d, t + 1], weights[c, d, t + 1] = 2 * abs(diff) + kind + 1, -0.5 * sign * factor
    return terms, weights


@numba.njit(cache=False)
def _frame(lam, jac, ints, fl, base, varying, coef, window, M, ws):
    """The frame at ``lam`` into the workspace (:func:`speed_frame`'s values; ``K = -M A_q``, ``C = -M A_v``
    instead of the whole linear operator), unless it holds it already."""
    p, A0, K, C, info = ws[0], ws[1], ws[2], ws[3], ws[4]
    if info[3] == 1.0 and info[0] == lam:
        return
    n, nu = ints[0], ints[3]
    for k in range(base.shape[0]):
        p[k] = base[k]
    s = lam / fl[0]
    for k in range(varying.shape[0]):
        p[varying[k]] = coef[0, k] + s * (coef[1, k] + s * coef[2, k])
    p[p.shape[0] - 2] = window[0]
    p[p.shape[0] - 1] = window[1]
    A0[:, :] = 0.0
    jac(0.0, ws[5], p, A0)
    for i in range(n):
        for l in range(n):
            kk = 0.0
            cc = 0.0
            for j in range(n):
                kk -= M[i, j] * A0[n + j, l]
                cc -= M[i, j] * A0[n + j, n + l]
            K[i, l] = kk
            C[i, l] = cc
    omega = lam / nu
    info[0] = lam
    info[1] = omega
    info[2] = 2.0 * np.pi / omega
    info[3] = 1.0


@numba.njit(cache=False)
def _residual(z, lam, want, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R, J):
    """``R`` (and ``J`` if ``want``) of the harmonic balance at ``(z, lam)``; False if ``R`` is not finite.

    The linear part per harmonic block; the local forces' Jacobian projected as
    ``J[c, d] -= sum_j P[c, j] (E[j, d] Fq_j + w ED[j, d] Fv_j)``, summed from the sampled Jacobians' cosine
    and sine sums up to harmonic 2H (a product of two basis functions is a sum of two of those)."""
    n, H, N = ints[0], ints[1], ints[2]
    H2 = E.shape[1]
    size = n * H2
    _frame(lam, jac, ints, fl, base, varying, coef, window, M, ws)
    p, A0, K, C, info = ws[0], ws[1], ws[2], ws[3], ws[4]
    Y, a, g, f, Aj, G, S = ws[6], ws[7], ws[8], ws[9], ws[10], ws[11], ws[12]
    trig, terms, weights = ws[13], ws[14], ws[15]
    nn = n * n
    omega, period = info[1], info[2]
    # R = L z per block: K z_0; (K - (kw)^2 M) a_k + kw C b_k; -kw C a_k + (K - (kw)^2 M) b_k
    for i in range(n):
        s = 0.0
        for l in range(n):
            s += K[i, l] * z[l]
        R[i] = s
    for h in range(1, H + 1):
        ra, rb = (2 * h - 1) * n, 2 * h * n
        kw = h * omega
        for i in range(n):
            s = 0.0
            for l in range(n):
                s += (K[i, l] - kw * kw * M[i, l]) * z[ra + l]
            for l in range(n):
                s += (kw * C[i, l]) * z[rb + l]
            R[ra + i] = s
            s = 0.0
            for l in range(n):
                s += (-kw * C[i, l]) * z[ra + l]
            for l in range(n):
                s += (K[i, l] - kw * kw * M[i, l]) * z[rb + l]
            R[rb + i] = s
    if want:
        for r in range(size):
            for c in range(size):
                J[r, c] = 0.0
        for i in range(n):
            for l in range(n):
                J[i, l] = K[i, l]
        for h in range(1, H + 1):
            ra, rb = (2 * h - 1) * n, 2 * h * n
            kw = h * omega
            for i in range(n):
                for l in range(n):
                    diagonal = K[i, l] - kw * kw * M[i, l]
                    J[ra + i, ra + l] = diagonal
                    J[rb + i, rb + l] = diagonal
                    J[ra + i, rb + l] = kw * C[i, l]
                    J[rb + i, ra + l] = -kw * C[i, l]
        for k in range(2 * H2):
            for e in range(2 * nn):
                S[k, e] = 0.0
    for j in range(N):  # the states at the instants (aft_states for all of them)
        for i in range(n):
            q = 0.0
            v = 0.0
            for h in range(H2):
                q += E[j, h] * z[h * n + i]
                v += ED[j, h] * z[h * n + i]
            Y[j, i] = q
            Y[j, n + i] = omega * v
    contact = False
    for j in range(N):
        t = period * j / N
        y = Y[j]
        for i in range(2 * n):
            a[i] = 0.0
        rhs(t, y, p, a)
        for i in range(n):
            s = a[n + i]
            for k in range(2 * n):
                s -= A0[n + i, k] * y[k]
            g[i] = s
        for i in range(n):
            s = 0.0
            for k in range(n):
                s += M[i, k] * g[k]
            f[j, i] = s
        if want:
            for r in range(2 * n):
                for c in range(2 * n):
                    Aj[r, c] = 0.0
            jac(t, y, p, Aj)
            here = False
            for i in range(n):
                for l in range(n):
                    sq = 0.0
                    sv = 0.0
                    for k in range(n):
                        sq += M[i, k] * (Aj[n + k, l] - A0[n + k, l])
                        sv += M[i, k] * (Aj[n + k, n + l] - A0[n + k, n + l])
                    G[i * n + l] = sq
                    G[nn + i * n + l] = sv
                    if sq != 0.0 or sv != 0.0:
                        here = True
            if not here:
                continue  # the linear part alone here (no contact at this instant): nothing to project
            contact = True
            for k in range(2 * H2):
                tk = trig[j, k]
                for e in range(2 * nn):
                    S[k, e] += tk * G[e]
    for h in range(H2):  # R -= P f, per entry in the order of the samples
        for i in range(n):
            s = R[h * n + i]
            for j in range(N):
                s -= P[h, j] * f[j, i]
            R[h * n + i] = s
    if want and contact:
        for c in range(H2):
            for d in range(H2):
                k0, k1, k2, k3 = terms[c, d, 0], terms[c, d, 1], terms[c, d, 2], terms[c, d, 3]
                w0, w1, w2, w3 = weights[c, d, 0], weights[c, d, 1], weights[c, d, 2], weights[c, d, 3]
                for i in range(n):
                    for l in range(n):
                        e = i * n + l
                        J[c * n + i, d * n + l] -= ((w0 * S[k0, e] + w1 * S[k1, e])
                                                    + omega * (w2 * S[k2, nn + e] + w3 * S[k3, nn + e]))
    s = 0.0
    for r in range(size):
        s += R[r] * R[r]
    return math.isfinite(s)


@numba.njit(cache=False)
def force_scale(lam, rhs, jac, ints, fl, E, P, M, base, varying, coef, window):
    """Largest amplitude of an oscillating harmonic of the forces at rest (N): the residual's scale."""
    n, N = ints[0], ints[2]
    H2 = E.shape[1]
    size = n * H2
    p, A0, L, omega, period = frame_at(lam, jac, ints, fl, base, varying, coef, window, M, size)
    y = np.zeros(2 * n)
    a = np.empty(2 * n)
    F = np.zeros((H2, n))
    for j in range(N):
        a[:] = 0.0
        rhs(period * j / N, y, p, a)
        for i in range(n):
            s = 0.0
            for k in range(n):
                s += M[i, k] * a[n + k]
            for h in range(H2):
                F[h, i] += P[h, j] * s
    biggest = 0.0
    for h in range(1, (H2 - 1) // 2 + 1):
        for i in range(n):
            biggest = max(biggest, math.hypot(F[2 * h - 1, i], F[2 * h, i]))
    return biggest


@numba.njit(cache=False)
def _switches_of(z, lam, state, rhs, jac, sw, ints, fl, E, ED, M, base, varying, coef, window):
    """Per switch whether it is positive at some AFT sample (into ``state``); returns the largest value."""
    n, N, ns = ints[0], ints[2], ints[4]
    H2 = E.shape[1]
    size = n * H2
    p, A0, L, omega, period = frame_at(lam, jac, ints, fl, base, varying, coef, window, M, size)
    y = np.empty(2 * n)
    out = np.empty(max(ns, 1))
    state[:] = False
    biggest = -np.inf
    for j in range(N):
        aft_states(z, j, omega, E, ED, n, y)
        out[:] = 0.0
        sw(period * j / N, y, p, out)
        for k in range(ns):
            if out[k] > 0.0:
                state[k] = True
            biggest = max(biggest, out[k])
    return biggest if ns else 0.0


@numba.njit(cache=False)
def _scale(lam, rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws):
    """:func:`force_scale` with the frame of the workspace."""
    n, N = ints[0], ints[2]
    H2 = E.shape[1]
    _frame(lam, jac, ints, fl, base, varying, coef, window, M, ws)
    p, info, y, a, f = ws[0], ws[4], ws[5], ws[7], ws[9]
    period = info[2]
    for j in range(N):
        for i in range(2 * n):
            a[i] = 0.0
        rhs(period * j / N, y, p, a)
        for i in range(n):
            s = 0.0
            for k in range(n):
                s += M[i, k] * a[n + k]
            f[j, i] = s
    F = np.empty((H2, n))
    for h in range(H2):  # in the order of the samples, as force_scale
        for i in range(n):
            s = 0.0
            for j in range(N):
                s += P[h, j] * f[j, i]
            F[h, i] = s
    biggest = 0.0
    for h in range(1, (H2 - 1) // 2 + 1):
        for i in range(n):
            biggest = max(biggest, math.hypot(F[2 * h - 1, i], F[2 * h, i]))
    return biggest


@numba.njit(cache=False)
def _buffers(m, size):
    """Newton's work arrays for ``m`` unknowns (``size`` of them harmonic coefficients):
    ``(R_new, J_new, LU, piv, dz, x, trial, z, Rz, Jz, plus, column, B, b)``."""
    return (np.empty(m), np.empty((m, m)), np.empty((m, m)), np.empty(m, dtype=np.int64), np.empty(m), np.empty(m),
            np.empty(m), np.empty(size), np.empty(size), np.empty((size, size)), np.empty(size), np.empty(size),
            np.empty((size + 1, size + 1)), np.empty(size + 1))


@numba.njit(cache=False)
def _max_abs(x):
    """``max |x|`` (nan if an entry is)."""
    biggest = 0.0
    for i in range(x.shape[0]):
        v = abs(x[i])
        if v > biggest or v != v:
            biggest = v
            if v != v:
                return v
    return biggest


@numba.njit(cache=False)
def _norm(x):
    s = 0.0
    for i in range(x.shape[0]):
        s += x[i] * x[i]
    return math.sqrt(s)


@numba.njit(cache=False)
def _bordered(u, u_pred, tvec, column, scale, z_scale, Rz, Jz, want, F, JF):
    """The corrector's bordered system from the residual ``Rz`` (and Jacobian ``Jz``) at ``u``."""
    size = Rz.shape[0]
    s = 0.0
    for i in range(size + 1):
        s += tvec[i] * (u[i] - u_pred[i])
    for i in range(size):
        F[i] = Rz[i]
    F[size] = scale * s
    if want:
        for r in range(size):
            for c in range(size):
                JF[r, c] = Jz[r, c] * z_scale
            JF[r, size] = column[r]
        for c in range(size + 1):
            JF[size, c] = scale * tvec[c]


@numba.njit(cache=False)
def _fun(u, want, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac, ints, fl, E, P, ED, M, base, varying,
         coef, window, ws, nb, F, JF):
    """Newton's function: ``mode`` 0 the residual at ``lam_fixed``; 1 the corrector's bordered system."""
    if mode == 0:
        return _residual(u, lam_fixed, want, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, F,
                         JF)
    z, Rz, Jz = nb[7], nb[8], nb[9]
    size = z.shape[0]
    z_scale, l_scale = fl[1], fl[2]
    for i in range(size):
        z[i] = u[i] * z_scale
    lam = u[size] * l_scale
    ok = _residual(z, lam, want, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, Rz, Jz)
    _bordered(u, u_pred, tvec, column, scale, z_scale, Rz, Jz, want, F, JF)
    return ok


@numba.njit(cache=False)
def _newton(u, mode, lam_fixed, u_pred, tvec, column, scale, max_iterations, evaluated, rhs, jac, ints, fl, E, P,
            ED, M, base, varying, coef, window, ws, nb, R, JF):
    """:func:`rotorkit.periodic.hb.newton` on ``u`` (in place); returns ``(converged, iterations, norm)`` with
    the function in ``R`` and the Jacobian at the solution in ``JF`` (both given at ``u`` if ``evaluated``)."""
    m = u.shape[0]
    tol = fl[9]
    R_new, J_new, LU, piv, dz, x, trial = nb[0], nb[1], nb[2], nb[3], nb[4], nb[5], nb[6]
    if not evaluated and not _fun(u, True, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac, ints, fl, E, P,
                                  ED, M, base, varying, coef, window, ws, nb, R, JF):
        return False, 0, np.inf
    norm = _max_abs(R) / scale
    for iteration in range(max_iterations + 1):
        if norm <= tol:
            return True, iteration, norm
        if iteration == max_iterations:
            break
        for r in range(m):
            for c in range(m):
                LU[r, c] = JF[r, c]
        lu_factor(LU, piv)
        for i in range(m):
            x[i] = -R[i]
        lu_solve(LU, piv, x, dz)
        size = _norm(dz)
        step = 1.0
        ok = False
        while True:
            for i in range(m):
                trial[i] = u[i] + step * dz[i]
            finite = _fun(trial, step == 1.0, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac, ints, fl, E,
                          P, ED, M, base, varying, coef, window, ws, nb, R_new, J_new)
            if finite:
                for i in range(m):
                    x[i] = -R_new[i]
                lu_solve(LU, piv, x, x)
                ok = _norm(x) <= (1.0 - step / 4.0) * size
            else:
                ok = False
            if ok or step < 1.0 / 128.0:
                break
            step *= 0.5
        for i in range(m):
            u[i] += step * dz[i]
        if ok and step == 1.0:
            for r in range(m):
                R[r] = R_new[r]
                for c in range(m):
                    JF[r, c] = J_new[r, c]
        elif not _fun(u, True, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac, ints, fl, E, P, ED, M,
                      base, varying, coef, window, ws, nb, R, JF):
            return False, iteration + 1, np.inf
        norm = _max_abs(R) / scale
    return False, max_iterations, norm


@numba.njit(cache=False)
def _tangent(A, reference, t, nb):
    """Unit ``t`` solving ``[A; reference^T] t = [0; 1]`` (``A`` (m, m + 1)); False if singular."""
    m = A.shape[0]
    B, piv, b = nb[12], nb[3], nb[13]
    for r in range(m):
        for c in range(m + 1):
            B[r, c] = A[r, c]
    for c in range(m + 1):
        B[m, c] = reference[c]
        b[c] = 0.0
    if not lu_factor(B, piv):
        return False
    b[m] = 1.0
    lu_solve(B, piv, b, t)
    norm = _norm(t)
    if not math.isfinite(norm) or norm == 0.0:
        return False
    for i in range(m + 1):
        t[i] /= norm
    return True


@numba.njit(cache=False)
def _full_jacobian(u, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, A):
    """``[dR/dz z_s, dR/dlambda l_s]`` at the scaled ``u`` (``dR/dlambda`` by the forward difference of step
    ``d_lam``); False if not finite."""
    z, R, J, plus = nb[7], nb[8], nb[9], nb[10]
    size = z.shape[0]
    z_scale, l_scale = fl[1], fl[2]
    for i in range(size):
        z[i] = u[i] * z_scale
    lam = u[size] * l_scale
    d = fl[5]
    if not _residual(z, lam + d, False, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, plus, J):
        return False
    if not _residual(z, lam, True, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R, J):
        return False
    for r in range(size):
        for c in range(size):
            A[r, c] = J[r, c] * z_scale
        A[r, size] = (plus[r] - R[r]) / d * l_scale
    return True


@numba.njit(cache=False)
def _correct(u_pred, tvec, u, A1, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, F, JF):
    """The corrector of :func:`~rotorkit.periodic.continuation.continue_branch`: ``(converged, iterations,
    norm)``, the solution in ``u`` and the Jacobian rows of the residual in ``A1`` (m, m + 1).

    ``dR/dlambda`` (frozen at the prediction) is the forward difference of step ``d_lam`` from the residual
    at the prediction, which is also Newton's first evaluation."""
    zp, Rz, Jz, plus, column = nb[7], nb[8], nb[9], nb[10], nb[11]
    size = zp.shape[0]
    z_scale, l_scale = fl[1], fl[2]
    for i in range(size):
        zp[i] = u_pred[i] * z_scale
    lp = u_pred[size] * l_scale
    scale = _scale(lp, rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws)
    if not _residual(zp, lp, True, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, Rz, Jz):
        return False, 0, np.inf
    if not _residual(zp, lp + fl[5], False, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, plus,
                     Jz):
        return False, 0, np.inf
    for i in range(size):
        column[i] = (plus[i] - Rz[i]) / fl[5]
    for i in range(size):
        column[i] *= l_scale
    for i in range(size + 1):
        u[i] = u_pred[i]
    _bordered(u, u_pred, tvec, column, scale, z_scale, Rz, Jz, True, F, JF)
    ok, iterations, norm = _newton(u, 1, 0.0, u_pred, tvec, column, scale, ints[5], True, rhs, jac, ints, fl, E, P,
                                   ED, M, base, varying, coef, window, ws, nb, F, JF)
    for r in range(size):
        for c in range(size + 1):
            A1[r, c] = JF[r, c]
    return ok, iterations, norm


@numba.njit(cache=False)
def _distance(a, b, h, c):
    """``|a - (b + h c)|``."""
    s = 0.0
    for i in range(a.shape[0]):
        d = a[i] - (b[i] + h * c[i])
        s += d * d
    return math.sqrt(s)


@numba.njit(cache=False)
def _same(a, b):
    for i in range(a.shape[0]):
        if a[i] != b[i]:
            return False
    return True


@numba.njit(cache=False)
def _corner(u0, t0, h, u1, t_new, rhs, jac, sw, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, F,
            JF):
    """:func:`rotorkit.periodic.continuation._corner`: ``(accepted, iterations, norm)``."""
    m = u0.shape[0]
    size = m - 1
    z_scale, l_scale = fl[1], fl[2]
    ns = max(ints[4], 1)
    u_pred = u0 + h * t0
    s0 = np.zeros(ns, dtype=np.bool_)
    sp = np.zeros(ns, dtype=np.bool_)
    g0 = _switches_of(u0[:size] * z_scale, u0[size] * l_scale, s0, rhs, jac, sw, ints, fl, E, ED, M, base, varying,
                      coef, window)
    gp = _switches_of(u_pred[:size] * z_scale, u_pred[size] * l_scale, sp, rhs, jac, sw, ints, fl, E, ED, M, base,
                      varying, coef, window)
    if _same(s0, sp):
        return False, 0, 0.0
    A = np.empty((size, m))
    t1 = np.empty(m)
    if not _full_jacobian(u_pred, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, A):
        return False, 0, 0.0
    if not _tangent(A, t0, t1, nb):
        return False, 0, 0.0
    into = gp - g0
    ua = u0 + h * t1
    along = _switches_of(ua[:size] * z_scale, ua[size] * l_scale, sp, rhs, jac, sw, ints, fl, E, ED, M, base,
                         varying, coef, window) - g0
    if along * into < 0:
        for i in range(m):
            t1[i] = -t1[i]
    u_pred = u0 + h * t1
    A1 = np.empty((size, m))
    ok, iterations, norm = _correct(u_pred, t1, u1, A1, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef,
                                    window, ws, nb, F, JF)
    if not ok:
        return False, 0, 0.0
    if _distance(u1, u0, h, t1) > h:
        return False, 0, 0.0
    s1 = np.zeros(ns, dtype=np.bool_)
    _switches_of(u1[:size] * z_scale, u1[size] * l_scale, s1, rhs, jac, sw, ints, fl, E, ED, M, base, varying, coef,
                 window)
    if _same(s1, s0):
        return False, 0, 0.0
    if not _tangent(A1, t1, t_new, nb):
        return False, 0, 0.0
    return True, iterations, norm


@numba.njit(cache=False)
def _solve_fixed(z, lam, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws):
    """Newton at the fixed parameter ``lam`` from ``z`` (in place, unscaled): ``(converged, iterations, norm)``."""
    size = z.shape[0]
    scale = _scale(lam, rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws)
    nb = _buffers(size, size)
    R = np.empty(size)
    JF = np.empty((size, size))
    return _newton(z, 0, lam, z, z, z, scale, ints[5], False, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef,
                   window, ws, nb, R, JF)


@numba.njit(cache=False)
def continue_kernel(rhs, jac, sw, ints, fl, E, P, ED, M, base, varying, coef, window, u0, t0, out_u, out_t, out_norm,
                    out_corner):
    """The loop of :func:`~rotorkit.periodic.continuation.continue_branch` from ``(u0, t0)`` (scaled; updated to
    resume) for at most ``ints[6]`` new points; ``ints[7]`` points exist. With ``ints[9] == 1`` the start tangent
    is computed first (along ``fl[10]``); ``ints[9] == 2``: only Newton at ``fl[11]`` (tolerance ``fl[9]``) from
    ``u0[:-1]`` (unscaled) into ``out_u[0]``, returning ``(converged, iterations)``; ``ints[9] == 3``: the
    largest amplitude of the linear response (one Newton step from zero) over the parameter values in ``t0``,
    into ``out_norm[0]``; ``ints[9] == 4``: the contact switches at ``(u0[:-1], fl[11])``, the largest value
    into ``out_norm[0]`` and per switch whether it is positive at some sample into ``out_corner``. Returns ``(status, new points)``; ``fl[6]`` holds the next step."""
    m = u0.shape[0]
    size = m - 1
    lo, hi = fl[3], fl[4]
    min_step, max_step = fl[7], fl[8]
    contact = ints[4] > 0
    max_new, count, max_points = ints[6], ints[7], ints[8]
    ws = _workspace(ints, E, base)
    if ints[9] == 2:  # Newton at the fixed parameter fl[11] from u0[:size] (unscaled): (converged, iterations)
        z = u0[:size].copy()
        ok, iterations, norm = _solve_fixed(z, fl[11], rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window,
                                            ws)
        out_u[0, :size] = z
        out_norm[0] = norm
        return (1 if ok else 0), iterations
    if ints[9] == 3:  # the linear response's largest amplitude over the parameter values t0 (into out_norm[0])
        z = np.zeros(size)
        R = np.empty(size)
        J = np.empty((size, size))
        piv = np.empty(size, dtype=np.int64)
        dz = np.empty(size)
        biggest = 0.0
        for k in range(t0.shape[0]):
            if not _residual(z, t0[k], True, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R,
                             J):
                continue
            if not lu_factor(J, piv):
                continue  # singular: numpy.linalg.solve raises, and the reference skips the value
            for i in range(size):
                R[i] = -R[i]
            lu_solve(J, piv, R, dz)
            biggest = max(biggest, np.max(np.abs(dz)))
        out_norm[0] = biggest
        return 0, 0
    if ints[9] == 4:  # the contact switches at (u0[:size], fl[11]) (unscaled): gap into out_norm[0], state
        state = np.zeros(max(ints[4], 1), dtype=np.bool_)
        out_norm[0] = _switches_of(u0[:size], fl[11], state, rhs, jac, sw, ints, fl, E, ED, M, base, varying, coef,
                                   window)
        for k in range(ints[4]):
            out_corner[k] = state[k]
        return 0, 0
    nb = _buffers(m, size)
    F = np.empty(m)
    JF = np.empty((m, m))
    if ints[9]:
        A = np.empty((size, m))
        reference = np.zeros(m)
        reference[size] = fl[10]
        if not _full_jacobian(u0, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, A):
            return -1, 0
        if not _tangent(A, reference, t0, nb):
            return -1, 0
        if t0[size] * fl[10] < 0:
            for i in range(m):
                t0[i] = -t0[i]
    h = fl[6]
    new = 0
    u1 = np.empty(m)
    t1 = np.empty(m)
    u_pred = np.empty(m)
    A1 = np.empty((size, m))
    while True:
        if count + new >= max_points:
            fl[6] = h
            return BUDGET, new
        if new >= max_new:
            fl[6] = h
            return PAUSED, new
        accepted = False
        corner = False
        iterations = 0
        norm = 0.0
        for i in range(m):
            u_pred[i] = u0[i] + h * t0[i]
        ok, iterations, norm = _correct(u_pred, t0, u1, A1, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef,
                                        window, ws, nb, F, JF)
        if ok and _distance(u1, u0, h, t0) <= h:
            if _tangent(A1, t0, t1, nb):
                cosine = 0.0
                for i in range(m):
                    cosine += t1[i] * t0[i]
                if cosine > 0.7 or h <= 4.0 * min_step:
                    accepted = True
        if not accepted and contact:
            accepted, iterations, norm = _corner(u0, t0, h, u1, t1, rhs, jac, sw, ints, fl, E, P, ED, M, base,
                                                 varying, coef, window, ws, nb, F, JF)
            corner = accepted
        if not accepted:
            h *= 0.5
            if h < min_step:
                fl[6] = h
                return MIN_STEP, new
            continue
        lam1 = u1[size] * fl[2]
        if lam1 > hi or lam1 < lo:
            bound = hi if lam1 > hi else lo
            la = u0[size] * fl[2]
            w = 0.0 if lam1 == la else (bound - la) / (lam1 - la)
            z = np.empty(size)
            for i in range(size):
                za = u0[i] * fl[1]
                z[i] = za + w * (u1[i] * fl[1] - za)
            ok, its, nrm = _solve_fixed(z, bound, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws)
            if ok and np.all(np.isfinite(z)):
                for i in range(size):
                    out_u[new, i] = z[i]
                out_u[new, size] = bound
                out_t[new] = t1
                out_norm[new] = nrm
                out_corner[new] = False
                new += 1
            fl[6] = h
            fl[11] = bound
            return BOUND, new
        for i in range(size):
            out_u[new, i] = u1[i] * fl[1]
        out_u[new, size] = lam1
        out_t[new] = t1
        out_norm[new] = norm
        out_corner[new] = corner
        new += 1
        u0[:] = u1
        t0[:] = t1
        if iterations <= 3:
            h = min(max_step, h * 1.5)
        elif iterations >= 7:
            h = h * 0.6
