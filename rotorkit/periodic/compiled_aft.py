"""numba kernels of the compiled harmonic-balance path: the frame at a speed and the AFT evaluation.

The frame at a speed (prepared parameters, the linear part, the AFT instants) rebuilt from the quadratic speed
fit of :class:`~rotorkit.periodic.evaluate.Evaluator` (:func:`speed_frame`, :func:`frame_at`, or into a
workspace: :func:`frame_into`); the harmonic-balance residual and its AFT Jacobian (:func:`residual`, the
Jacobian assembled from the cosine and sine sums of the sampled force Jacobians up to harmonic ``2H``: see
:mod:`rotorkit.periodic.compiled`); the force scale (:func:`scale_at_rest`, :func:`force_scale_into`) and the
contact switches at the AFT samples (:func:`switches_of`). They repeat, operation for operation, the Python
reference (:class:`~rotorkit.periodic.hb.HarmonicBalance`); the continuation loop that calls them is
:mod:`rotorkit.periodic.compiled`, the per-point data :mod:`rotorkit.periodic.compiled_points`.
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np

__all__ = ["prepared_parameters", "linear_entry", "linear_blocks", "speed_frame", "frame_at", "aft_states", "workspace",
           "aft_tables", "projection_terms", "frame_into", "residual", "residual_same_states", "jacobian_at_states",
           "scale_at_rest", "switches_of", "same_state", "force_scale_into"]


@numba.njit(cache=False)
def prepared_parameters(lam, fl, base, varying, coef, window, p):
    """The prepared parameter vector at speed ``lam`` into ``p``: ``base``, the entries that vary with the speed
    from their quadratic fit in ``lam / fl[0]``, and the time window in the last two."""
    for k in range(base.shape[0]):
        p[k] = base[k]
    s = lam / fl[0]
    for k in range(varying.shape[0]):
        p[varying[k]] = coef[0, k] + s * (coef[1, k] + s * coef[2, k])
    p[p.shape[0] - 2] = window[0]
    p[p.shape[0] - 1] = window[1]


@numba.njit(cache=False)
def linear_entry(M, A0, n, i, l):
    """``(K[i, l], C[i, l])`` of the linear part at rest: ``K = -M A_q``, ``C = -M A_v`` (``A0`` the
    acceleration Jacobian at rest, (2n, 2n))."""
    kk = 0.0
    cc = 0.0
    for j in range(n):
        kk -= M[i, j] * A0[n + j, l]
        cc -= M[i, j] * A0[n + j, n + l]
    return kk, cc


@numba.njit(cache=False)
def linear_blocks(K, C, M, omega, H, n, L):
    """The linear part of the harmonic balance into the zeroed ``L`` (n (2H + 1) square): ``K`` for the mean,
    and per harmonic ``h`` the block ``[[K - (h w)^2 M, h w C], [-h w C, K - (h w)^2 M]]``."""
    for i in range(n):
        for l in range(n):
            L[i, l] = K[i, l]
    for h in range(1, H + 1):
        ra, rb = (2 * h - 1) * n, 2 * h * n
        kw = h * omega
        for i in range(n):
            for l in range(n):
                diagonal = K[i, l] - kw * kw * M[i, l]
                L[ra + i, ra + l] = diagonal
                L[rb + i, rb + l] = diagonal
                L[ra + i, rb + l] = kw * C[i, l]
                L[rb + i, ra + l] = -kw * C[i, l]


@numba.njit(cache=False)
def speed_frame(lam, jac, ints, fl, base, varying, coef, window, M, p, A0, L):
    """Prepared parameters ``p``, the Jacobian at rest ``A0`` (2n, 2n) and the linear operator ``L`` at speed
    ``lam``; returns the base frequency."""
    n, H, nu = ints[0], ints[1], ints[3]
    prepared_parameters(lam, fl, base, varying, coef, window, p)
    A0[:, :] = 0.0
    jac(0.0, np.zeros(2 * n), p, A0)
    omega = lam / nu
    K = np.empty((n, n))
    C = np.empty((n, n))
    for i in range(n):
        for l in range(n):
            K[i, l], C[i, l] = linear_entry(M, A0, n, i, l)
    L[:, :] = 0.0
    linear_blocks(K, C, M, omega, H, n, L)
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


@numba.njit(cache=False, inline="always")  # inlined: called per instant and coordinate in the hot loops
def _sample_sums(z, j, E, ED, n, i):
    """Coordinate ``i`` and its velocity per unit base frequency at AFT instant ``j``: ``(E z)[j, i]``,
    ``(ED z)[j, i]``."""
    q = 0.0
    v = 0.0
    for h in range(E.shape[1]):
        q += E[j, h] * z[h * n + i]
        v += ED[j, h] * z[h * n + i]
    return q, v


@numba.njit(cache=False)
def aft_states(z, j, omega, E, ED, n, y):
    """The state ``y`` (2n) at AFT instant ``j`` from the coefficients ``z``."""
    for i in range(n):
        q, v = _sample_sums(z, j, E, ED, n, i)
        y[i] = q
        y[n + i] = omega * v


@numba.njit(cache=False)
def workspace(ints, base, trig, terms, weights):
    """Work arrays of one kernel call (the frame at a speed, cached by its speed, and the AFT loop's buffers):
    ``(p, A0, K, C, info, zero, Y, a, g, f, Aj, G, S, trig, terms, weights, V, acc, last)``; ``info`` holds the
    speed of the frame in ``p``, ``A0``, ``K``, ``C``, its base frequency and period, and whether it is set;
    ``trig``, ``terms``, ``weights``: :func:`aft_tables` (made once per size, passed in), ``G`` one instant's
    force Jacobian entries, ``S`` (2 n^2, 2 (2H + 1)) their sums per entry, ``V`` (N, n) the last residual's
    velocities per unit base frequency, ``acc`` (N, n) its accelerations ``a(t_j, y_j)`` and ``last[0]`` its
    parameter (nan before the first)."""
    n, N = ints[0], ints[2]
    H2 = terms.shape[0]
    return (np.empty(base.shape[0]), np.empty((2 * n, 2 * n)), np.empty((n, n)), np.empty((n, n)), np.zeros(4),
            np.zeros(2 * n), np.empty((N, 2 * n)), np.empty(2 * n), np.empty(n), np.empty((N, n)),
            np.empty((2 * n, 2 * n)),
            np.empty(2 * n * n), np.empty((2 * n * n, 2 * H2)), trig, terms, weights, np.empty((N, n)),
            np.empty((N, n)), np.full(1, np.nan))


@functools.lru_cache(maxsize=16)
def aft_tables(H2, N):
    """``(trig, terms, weights)`` of the AFT Jacobian for ``H2 = 2H + 1`` basis functions and ``N`` samples
    (plain Python, made once per size and passed to the kernels, which only read them): ``trig`` (N, 2 H2)
    ``cos(m tau_j)``, ``sin(m tau_j)`` for m = 0 ... 2H (products of two basis functions), ``terms``,
    ``weights`` (H2, H2, 4): :func:`projection_terms`."""
    trig = np.empty((N, 2 * H2))
    for j in range(N):
        for m in range(H2):
            angle = 2.0 * np.pi * ((m * j) % N) / N
            trig[j, 2 * m] = math.cos(angle)
            trig[j, 2 * m + 1] = math.sin(angle)
    terms, weights = projection_terms(H2, N)
    return trig, terms, weights


def projection_terms(H2, N):
    """The AFT projection of the sampled force Jacobians, ``F_j`` (coordinates, entries ``G[j, :n n]``) and
    ``V_j`` (velocities, ``G[j, n n:]``), from their sums ``S[:, 2 m] = sum_j cos(m tau_j) G_j`` and
    ``S[:, 2 m + 1] = sum_j sin(m tau_j) G_j``, ``m = 0 ... 2H``: block ``(c, d)`` of
    ``sum_j P[c, j] (E[j, d] F_j + w ED[j, d] V_j)`` is ``sum_t weights[c, d, t] S[:, terms[c, d, t]]`` (of the
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


@numba.njit(cache=False, inline="always")  # inlined: a call passing the work arrays costs ~0.2 us
def frame_into(lam, jac, ints, fl, base, varying, coef, window, M, ws):
    """The frame at ``lam`` into the workspace (:func:`speed_frame`'s values; ``K = -M A_q``, ``C = -M A_v``
    instead of the whole linear operator), unless it holds it already."""
    p, A0, K, C, info = ws[0], ws[1], ws[2], ws[3], ws[4]
    if info[3] == 1.0 and info[0] == lam:
        return
    n, nu = ints[0], ints[3]
    prepared_parameters(lam, fl, base, varying, coef, window, p)
    A0[:, :] = 0.0
    jac(0.0, ws[5], p, A0)
    for i in range(n):
        for l in range(n):
            K[i, l], C[i, l] = linear_entry(M, A0, n, i, l)
    omega = lam / nu
    info[0] = lam
    info[1] = omega
    info[2] = 2.0 * np.pi / omega
    info[3] = 1.0


@numba.njit(cache=False)
def residual(z, lam, want, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R, J):
    """``R`` (and ``J`` if ``want``: :func:`jacobian_at_states`) of the harmonic balance at ``(z, lam)``; False
    if ``R`` is not finite. The states at the AFT samples stay in the workspace (``ws[6]``; their velocities per
    unit base frequency in ``ws[16]``)."""
    return _residual(z, lam, want, False, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R, J)


@numba.njit(cache=False)
def residual_same_states(z, lam, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R):
    """:func:`residual` (no Jacobian) at the ``z`` of the last :func:`residual` call on this workspace and a new
    ``lam``: the sampled displacements and the velocities per unit base frequency are those the last call left
    (the same sums of the same numbers: equal to the bit), only the velocities' frequency factor is new."""
    return _residual(z, lam, False, True, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R,
                     ws[10])


@numba.njit(cache=False, inline="always")
def _residual(z, lam, want, same, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R, J):
    """:func:`residual`; with ``same`` the sampled states of the last call at ``z`` reused (velocities rescaled)."""
    n, H, N = ints[0], ints[1], ints[2]
    H2 = E.shape[1]
    frame_into(lam, jac, ints, fl, base, varying, coef, window, M, ws)
    p, A0, K, C, info = ws[0], ws[1], ws[2], ws[3], ws[4]
    Y, a, g, f, acc = ws[6], ws[7], ws[8], ws[9], ws[17]
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
    V = ws[16]
    if same:
        for j in range(N):
            for i in range(n):
                Y[j, n + i] = omega * V[j, i]
    else:
        for j in range(N):  # the states at all instants first
            for i in range(n):
                q, v = _sample_sums(z, j, E, ED, n, i)
                Y[j, i] = q
                V[j, i] = v
                Y[j, n + i] = omega * v
    for j in range(N):
        t = period * j / N
        y = Y[j]
        for i in range(2 * n):
            a[i] = 0.0
        rhs(t, y, p, a)
        for i in range(n):
            acc[j, i] = a[n + i]
            s = a[n + i]
            for k in range(2 * n):
                s -= A0[n + i, k] * y[k]
            g[i] = s
        for i in range(n):
            s = 0.0
            for k in range(n):
                s += M[i, k] * g[k]
            f[j, i] = s
    for h in range(H2):  # R -= P f, per entry in the order of the samples
        for i in range(n):
            s = R[h * n + i]
            for j in range(N):
                s -= P[h, j] * f[j, i]
            R[h * n + i] = s
    ws[18][0] = lam
    if want:
        jacobian_at_states(jac, ints, E, M, ws, J)
    s = 0.0
    for r in range(R.shape[0]):
        s += R[r] * R[r]
    return math.isfinite(s)


@numba.njit(cache=False)
def jacobian_at_states(jac, ints, E, M, ws, J):
    """The residual's Jacobian ``J`` at the states and frame the workspace holds (those of the last
    :func:`residual` call): the linear part per harmonic block; the local forces' Jacobian projected as
    ``J[c, d] -= sum_j P[c, j] (E[j, d] Fq_j + w ED[j, d] Fv_j)``, summed from the sampled Jacobians' cosine
    and sine sums up to harmonic 2H (a product of two basis functions is a sum of two of those).

    A sampled entry that is exactly zero adds nothing to its sums (they start at +0.0 and are never -0.0, so
    adding +-0 leaves them as they are: skipped); where no velocity entry is nonzero at any sample (forces
    that depend on the displacements alone) the velocity sums are all +0.0 and the assembly uses that value
    without reading them: the same numbers to the bit, with half the work for such forces."""
    n, H, N = ints[0], ints[1], ints[2]
    H2 = E.shape[1]
    size = n * H2
    p, A0, K, C, info = ws[0], ws[1], ws[2], ws[3], ws[4]
    Y, Aj, G, S = ws[6], ws[10], ws[11], ws[12]
    trig, terms, weights = ws[13], ws[14], ws[15]
    nn = n * n  # G is (Fq, Fv) of one instant, flat
    omega, period = info[1], info[2]
    for r in range(size):
        for c in range(size):
            J[r, c] = 0.0
    linear_blocks(K, C, M, omega, H, n, J)
    for e in range(2 * nn):  # S[e, k]: per entry its sums, contiguous
        for k in range(2 * H2):
            S[e, k] = 0.0
    contact = False
    velocity = False  # whether some velocity entry (Fv) is nonzero
    for j in range(N):
        for r in range(2 * n):
            for c in range(2 * n):
                Aj[r, c] = 0.0
        jac(period * j / N, Y[j], p, Aj)
        nonzero = False  # M times the local forces' part of the Jacobian (Aj - A0) into G
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
                    nonzero = True
        if not nonzero:
            continue  # the linear part alone here (no contact at this instant): nothing to project
        contact = True
        tj = trig[j]
        for e in range(2 * nn):
            ge = G[e]
            if ge == 0.0:
                continue
            if e >= nn:
                velocity = True
            se = S[e]
            for k in range(2 * H2):
                se[k] += tj[k] * ge
    if contact:
        for c in range(H2):
            for d in range(H2):
                w0, w1, w2, w3 = weights[c, d, 0], weights[c, d, 1], weights[c, d, 2], weights[c, d, 3]
                t0, t1, t2, t3 = terms[c, d, 0], terms[c, d, 1], terms[c, d, 2], terms[c, d, 3]
                if velocity:
                    for i in range(n):
                        for l in range(n):
                            e = i * n + l
                            J[c * n + i, d * n + l] -= ((w0 * S[e, t0] + w1 * S[e, t1])
                                                        + omega * (w2 * S[nn + e, t2] + w3 * S[nn + e, t3]))
                else:  # the velocity sums are +0.0: the same value without reading them
                    v = omega * (w2 * 0.0 + w3 * 0.0)
                    for i in range(n):
                        for l in range(n):
                            e = i * n + l
                            J[c * n + i, d * n + l] -= (w0 * S[e, t0] + w1 * S[e, t1]) + v


@numba.njit(cache=False)
def switches_of(z, lam, state, rhs, jac, sw, ints, fl, E, ED, M, base, varying, coef, window):
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
def same_state(a, b):
    """Whether two contact states (per switch, :func:`switches_of`) are equal."""
    for i in range(a.shape[0]):
        if a[i] != b[i]:
            return False
    return True


@numba.njit(cache=False)
def scale_at_rest(rhs, p, period, n, N, M, P, y, a, f):
    """Largest amplitude of an oscillating harmonic of the forces at rest (N), the residual's scale: the forces
    ``M a`` at the zero state ``y`` on the ``N`` AFT instants of ``period`` (prepared parameters ``p``; work
    arrays ``a`` (2n), ``f`` (N, n)), projected in the order of the samples."""
    H2 = P.shape[0]
    for j in range(N):
        for i in range(2 * n):
            a[i] = 0.0
        rhs(period * j / N, y, p, a)
        for i in range(n):
            s = 0.0
            for k in range(n):
                s += M[i, k] * a[n + k]
            f[j, i] = s
    biggest = 0.0
    for h in range(1, (H2 - 1) // 2 + 1):  # the cosine and sine rows of harmonic h (no array: no allocation)
        for i in range(n):
            a_h = 0.0
            for j in range(N):
                a_h += P[2 * h - 1, j] * f[j, i]
            b_h = 0.0
            for j in range(N):
                b_h += P[2 * h, j] * f[j, i]
            biggest = max(biggest, math.hypot(a_h, b_h))
    return biggest


@numba.njit(cache=False, inline="always")  # inlined: a call passing the work arrays costs ~0.2 us
def force_scale_into(lam, rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws):
    """:func:`scale_at_rest` at ``lam`` with the frame of the workspace."""
    frame_into(lam, jac, ints, fl, base, varying, coef, window, M, ws)
    p, info = ws[0], ws[4]
    return scale_at_rest(rhs, p, info[2], ints[0], ints[2], M, P, ws[5], ws[7], ws[9])
