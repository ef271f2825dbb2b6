"""numba kernel of the compiled harmonic-balance path's per-point data: the error estimate and Hill's multipliers.

It repeats what the Python reference does (the truncation-error estimate of
:mod:`rotorkit.analysis.periodic` and
:func:`~rotorkit.periodic.stability.hill_multipliers`), with the frame at each
point's speed rebuilt by :func:`rotorkit.periodic.compiled_aft.speed_frame`; the
settings ``ints``/``fl`` are those of :mod:`rotorkit.periodic.compiled`
(``ints[10]``: whether Hill's multipliers are computed). The glue is in
:mod:`rotorkit.periodic.fastpath`.

Hill's multipliers along a branch
    The full method (:func:`_hill_full`) is the Python one: all
    eigenvalues of Hill's companion matrix (:func:`~rotorkit.periodic.eigen.eigenvalues`),
    the centre of every eigenvector, the selection. Consecutive points of a
    branch have close exponents, so the kernel follows the previous point's
    ``2n`` kept exponents instead (:func:`_hill_tracked`: shifted inverse
    iteration on the quadratic eigenproblem from the previous exponents,
    extrapolated, and their eigenvectors; a conjugate by conjugation), a few
    solves of size ``n (2H + 1)`` instead of a QR iteration of twice that
    size. It keeps a followed set only where it is the full method's
    selection on the evidence at hand: each exponent converged to an
    eigenvector close to its predecessor's and is its family's most centred
    member (within ``TRACK_CENTRE`` of harmonic 0, or the more centred of it
    and its copy one harmonic nearer, their centres about one harmonic
    apart), the ``2n`` are distinct families (or a double eigenvalue with
    independent eigenvectors), and the number of multipliers outside the unit
    circle is the previous point's (a stability change is always decided by
    the full method). Otherwise, at the first point and at least every
    ``ANCHOR_EVERY`` points, the full method runs; following resumes only
    from a full solve whose selection is clear-cut (the other exponents, not
    copies of the kept ones, at least ``RUNNER_CENTRE`` off centre).
    tests/test_periodic_hill_tracking.py compares both at every point of
    branches through folds.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .compiled_aft import aft_states, frame_at, linear_entry, local_jacobian, scale_at_rest, speed_frame
from .eigen import complex_lu, complex_null_vector, eigenvalues, lu_solve, quadratic_eigenpair
from .stability import STABILITY_TOL

__all__ = ["point_data_kernel", "hill_branch", "ANCHOR_EVERY", "TRACK_CENTRE", "RUNNER_CENTRE", "TRACK_OVERLAP",
           "COPY_SPREAD", "DOUBLE_OVERLAP"]

#: a full solve of Hill's eigenproblem at least every ANCHOR_EVERY points of a branch
ANCHOR_EVERY = 16
#: a followed exponent's eigenvector centred within TRACK_CENTRE harmonics (its copies then lie >= 1 - this off)
TRACK_CENTRE = 0.3
#: a followed exponent centred beyond TRACK_CENTRE is compared with its copy one harmonic nearer the centre: the
#: two centres must lie 1 +- COPY_SPREAD apart
COPY_SPREAD = 0.2
#: two followed exponents equal to rounding count as a double eigenvalue only if their eigenvectors' overlap is
#: below DOUBLE_OVERLAP (else they converged to one exponent: the full method instead)
DOUBLE_OVERLAP = 0.5
#: following starts only from a full solve whose other exponents (not copies of kept ones) lie this far off
RUNNER_CENTRE = 0.7
#: a followed eigenvector's overlap |<u, u_prev>| / (|u| |u_prev|) with its predecessor's at least
TRACK_OVERLAP = 0.9


@numba.njit(cache=False)
def _hill_matrix(z, lam, jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window):
    """The lower blocks of Hill's matrix ``[[0, I], [A21, A22]]`` of
    :func:`rotorkit.periodic.stability.hill_exponents`: ``(A21, A22, omega, period)``."""
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
                kk, cc = linear_entry(M, A0, n, i, l)
                Kt[h * n + i, h * n + l] = kk
                Ct[h * n + i, h * n + l] = cc
    # proj(F) = P diag(F_j) E block by block: P[c, j] E[j, d] is a product of two of 1, cos a t, sin a t, a sum
    # of cos m t and sin m t (m <= 2H): the sums FC[m] = sum_j cos(m t_j) F_j, FS[m] = sum_j sin(m t_j) F_j
    # give every block (the same sums as the products, fewer operations)
    y = np.empty(2 * n)
    Aj = np.empty((2 * n, 2 * n))
    Fq = np.empty((n, n))
    Fv = np.empty((n, n))
    M2 = 2 * H + 1
    nn = n * n
    f = np.empty(2 * nn)  # Fq and Fv of one sample, flat
    FC = np.zeros((M2, 2 * nn))
    FS = np.zeros((M2, 2 * nn))
    cs = np.empty(M2)
    sn = np.empty(M2)
    for j in range(N):
        aft_states(z, j, omega, E, ED, n, y)
        Aj[:, :] = 0.0
        jac(period * j / N, y, p, Aj)
        if not local_jacobian(M, Aj, A0, n, Fq, Fv):
            continue
        for i in range(n):
            for l in range(n):
                f[i * n + l] = Fq[i, l]
                f[nn + i * n + l] = Fv[i, l]
        cs[0], sn[0] = 1.0, 0.0
        for m in range(1, H + 1):
            cs[m], sn[m] = E[j, 2 * m - 1], E[j, 2 * m]
        for m in range(H + 1, M2):  # cos/sin (H + k) t from the addition theorems
            k = m - H
            cs[m] = cs[H] * cs[k] - sn[H] * sn[k]
            sn[m] = sn[H] * cs[k] + cs[H] * sn[k]
        for m in range(M2):
            cm, sm = cs[m], sn[m]
            for r in range(2 * nn):
                FC[m, r] += cm * f[r]
                FS[m, r] += sm * f[r]
    for c in range(H2):
        a = (c + 1) // 2  # harmonic of row block c; kind: 0 constant, 1 cos, 2 sin
        ka = 0 if c == 0 else 2 - c % 2
        weight = (1.0 if c == 0 else 2.0) / N
        for d in range(H2):
            b = (d + 1) // 2
            kb = 0 if d == 0 else 2 - d % 2
            lo = abs(a - b)
            sg = 1.0 if a >= b else -1.0
            hi = a + b
            for i in range(n):
                for l in range(n):
                    for t in range(2):
                        r = t * nn + i * n + l
                        if ka == 0 and kb == 0:
                            v = FC[0, r]
                        elif ka == 0:
                            v = FC[b, r] if kb == 1 else FS[b, r]
                        elif kb == 0:
                            v = FC[a, r] if ka == 1 else FS[a, r]
                        elif ka == 1 and kb == 1:  # cos a cos b
                            v = 0.5 * (FC[lo, r] + FC[hi, r])
                        elif ka == 2 and kb == 2:  # sin a sin b
                            v = 0.5 * (FC[lo, r] - FC[hi, r])
                        elif ka == 1:  # cos a sin b
                            v = 0.5 * (FS[hi, r] - sg * FS[lo, r])
                        else:  # sin a cos b
                            v = 0.5 * (FS[hi, r] + sg * FS[lo, r])
                        if t == 0:
                            Kt[c * n + i, d * n + l] -= weight * v
                        else:
                            Ct[c * n + i, d * n + l] -= weight * v
    # J = Kt + Ct kron(wD, I) + kron(wD^2, M) into Kt, D1 = 2 kron(wD, M) + Ct into Ct; wD (H2, H2) has
    # wD[2k-1, 2k] = k w, wD[2k, 2k-1] = -k w, and wD^2 = diag(0, -(w k)^2 twice per k)
    for r in range(size):
        for k in range(1, H + 1):
            wk = omega * k
            for l in range(n):
                Kt[r, 2 * k * n + l] += wk * Ct[r, (2 * k - 1) * n + l]
                Kt[r, (2 * k - 1) * n + l] -= wk * Ct[r, 2 * k * n + l]
    for k in range(1, H + 1):
        wk = omega * k
        ca, sb = (2 * k - 1) * n, 2 * k * n
        for i in range(n):
            for l in range(n):
                Kt[ca + i, ca + l] -= wk * wk * M[i, l]
                Kt[sb + i, sb + l] -= wk * wk * M[i, l]
                Ct[ca + i, sb + l] += 2.0 * wk * M[i, l]
                Ct[sb + i, ca + l] -= 2.0 * wk * M[i, l]
    Jh = Kt
    D1 = Ct
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
    return A21, A22, omega, period


@numba.njit(cache=False)
def _centre_of(x, n, H):
    """The weighted mean harmonic ``sum k |c_k|^2 / sum |c_k|^2`` of the real-basis coefficients ``x`` (size
    ``n (2H + 1)``, complex) of a Hill eigenvector (:func:`rotorkit.periodic.stability.hill_exponents`)."""
    total = 0.0
    weighted = 0.0
    for i in range(n):
        total += x[i].real ** 2 + x[i].imag ** 2
    for k in range(1, H + 1):
        for i in range(n):
            a = x[(2 * k - 1) * n + i]
            b = x[2 * k * n + i]
            minus = a - 1j * b
            plus = a + 1j * b
            pm = (minus.real ** 2 + minus.imag ** 2) / 4.0  # |c_k|^2, c_k = (a_k - i b_k) / 2
            pp = (plus.real ** 2 + plus.imag ** 2) / 4.0  # |c_-k|^2
            total += pm + pp
            weighted += k * (pm - pp)
    return weighted / max(total, 1e-300)


@numba.njit(cache=False)
def _centres(A21, A22, wr, wi, n, H, vectors):
    """The centre (:func:`_centre_of`) of each Hill eigenvector, the eigenvectors' harmonic parts into
    ``vectors`` (one row per eigenvalue): the null vector ``p`` of ``A21 + lam A22 - lam^2 I``, a conjugate
    eigenvalue's the conjugate vector (centre: minus the partner's)."""
    size = n * (2 * H + 1)
    count = 2 * size
    centre = np.empty(count)
    done = np.zeros(count, dtype=np.bool_)
    G = np.empty((size, size), dtype=np.complex128)
    x = np.empty(size, dtype=np.complex128)
    for e in range(count):
        if done[e]:
            continue
        lam_e = complex(wr[e], wi[e])
        for r in range(size):
            for c in range(size):
                G[r, c] = A21[r, c] + lam_e * A22[r, c]
            G[r, r] -= lam_e * lam_e
        complex_null_vector(G, x)
        centre[e] = _centre_of(x, n, H)
        vectors[e, :] = x
        done[e] = True
        if wi[e] != 0.0:  # the conjugate eigenvalue: the conjugate vector, harmonics mirrored
            for f in range(count):
                if not done[f] and wr[f] == wr[e] and wi[f] == -wi[e]:
                    centre[f] = -centre[e]
                    for r in range(size):
                        vectors[f, r] = x[r].conjugate()
                    done[f] = True
                    break
    return centre


@numba.njit(cache=False)
def _is_copy(a, b, omega, tol):
    """Whether ``(a - b) / (i w)`` is a nonzero integer to ``tol`` (the same Floquet multiplier)."""
    d = (a - b) / (1j * omega)
    rd = math.floor(d.real + 0.5)
    return abs(d.imag) < tol and rd != 0 and abs(d.real - rd) < tol


@numba.njit(cache=False)
def _select(wr, wi, centre, n, omega):
    """The selection of :func:`rotorkit.periodic.stability.hill_multipliers`: the indices of the ``2n`` most
    centred exponents, one per family ``lambda + i k w`` (fewer if there are not as many families), and the
    smallest ``|centre|`` of the others that are not copies of a kept one (inf if none)."""
    count = wr.shape[0]
    order = np.argsort(np.abs(centre), kind="mergesort")
    kept = np.empty(2 * n, dtype=np.int64)
    nk = 0
    runner = np.inf
    for o in range(count):
        i = order[o]
        copy = False
        for q in range(nk):
            j = kept[q]
            if _is_copy(complex(wr[i], wi[i]), complex(wr[j], wi[j]), omega, 1e-6):
                copy = True
                break
        if copy:
            continue
        if nk == 2 * n:
            runner = abs(centre[i])
            break
        kept[nk] = i
        nk += 1
    return kept[:nk], runner


@numba.njit(cache=False)
def _multipliers(lam, period, mu_re, mu_im):
    """``exp(lam T)`` into ``mu_re + i mu_im``; the number outside the unit circle (``|mu| > 1 + tol``)."""
    unstable = 0
    for q in range(lam.shape[0]):
        mag = math.exp(lam[q].real * period)
        mu_re[q] = mag * math.cos(lam[q].imag * period)
        mu_im[q] = mag * math.sin(lam[q].imag * period)
        if mag > 1.0 + STABILITY_TOL:
            unstable += 1
    return unstable


@numba.njit(cache=False)
def _hill_full(A21, A22, n, H, omega, lam_kept, vec_kept, centre_kept):
    """Hill's exponents by the full method: all eigenvalues of the companion matrix (:func:`eigenvalues`),
    the centre of every eigenvector, the selection. Into ``lam_kept`` (2n), their eigenvectors ``vec_kept``
    (2n, size) and centres; returns ``(ok, runner)`` (False if the QR iteration fails or fewer than ``2n``
    families; ``runner`` as :func:`_select`'s)."""
    size = n * (2 * H + 1)
    big = np.zeros((2 * size, 2 * size))
    for i in range(size):
        big[i, size + i] = 1.0
        for col in range(size):
            big[size + i, col] = A21[i, col]
            big[size + i, size + col] = A22[i, col]
    wr = np.empty(2 * size)
    wi = np.empty(2 * size)
    if not eigenvalues(big, wr, wi):
        return False, 0.0
    vectors = np.empty((2 * size, size), dtype=np.complex128)
    centre = _centres(A21, A22, wr, wi, n, H, vectors)
    kept, runner = _select(wr, wi, centre, n, omega)
    for q in range(kept.shape[0]):
        i = kept[q]
        lam_kept[q] = complex(wr[i], wi[i])
        vec_kept[q, :] = vectors[i]
        centre_kept[q] = centre[i]
    for q in range(kept.shape[0], 2 * n):
        lam_kept[q] = np.nan
    # a double eigenvalue kept twice has one null vector from complex_null_vector twice: for following, a second
    # one from another right-hand side (independent if the eigenvalue is semisimple; else following fails)
    G = np.empty((size, size), dtype=np.complex128)
    piv = np.empty(size, dtype=np.int64)
    for q in range(kept.shape[0]):
        for r in range(q):
            if (abs(lam_kept[q] - lam_kept[r]) <= 1e-8 * (abs(lam_kept[q]) + omega)
                    and _overlap(vec_kept[q], vec_kept[r]) > DOUBLE_OVERLAP):
                lam_q = lam_kept[q]
                for i in range(size):
                    for c in range(size):
                        G[i, c] = A21[i, c] + lam_q * A22[i, c]
                    G[i, i] -= lam_q * lam_q
                complex_lu(G, piv)
                x = np.empty(size, dtype=np.complex128)
                for i in range(size):
                    x[i] = (i + 1.0) * (-1.0) ** i
                lu_solve(G, piv, x, x)
                vec_kept[q, :] = x
                centre_kept[q] = _centre_of(x, n, H)
                break
    return kept.shape[0] == 2 * n, runner


@numba.njit(cache=False)
def _hill_tracked(A21, A22, n, H, omega, lam_prev, vec_prev, sigma, lam_kept, vec_kept, centre_kept):
    """Hill's exponents followed from the previous point's (``lam_prev``, ``vec_prev``) by shifted inverse
    iteration (:func:`quadratic_eigenpair`) from the shifts ``sigma`` (predicted exponents), a conjugate pair's
    second member by conjugation, into ``lam_kept``, ``vec_kept``, ``centre_kept``.

    False (then the full method runs instead) unless every exponent converged to an eigenvector close to its
    predecessor's (overlap ``TRACK_OVERLAP``) and is its family's most centred member (centred within
    ``TRACK_CENTRE``, or compared with its copy one harmonic nearer the centre, as the full method compares
    them), and the ``2n`` exponents are distinct (or a double eigenvalue with independent eigenvectors) and no
    copies of each other."""
    size = n * (2 * H + 1)
    count = 2 * n
    u = np.empty(size, dtype=np.complex128)
    used = np.zeros(count, dtype=np.bool_)
    for q in range(count):
        partner = -1
        if lam_prev[q].imag != 0.0:
            for r in range(q):
                if not used[r] and lam_prev[r] == lam_prev[q].conjugate():
                    partner = r
                    used[r] = True  # one partner each, and a mirrored exponent is no partner
                    used[q] = True
                    break
        if partner >= 0:
            lam_kept[q] = lam_kept[partner].conjugate()
            for r in range(size):
                vec_kept[q, r] = vec_kept[partner, r].conjugate()
            centre_kept[q] = -centre_kept[partner]
            continue
        u[:] = vec_prev[q]
        lam, ok = quadratic_eigenpair(A22, A21, sigma[q], u)
        if not ok:
            return False
        if _overlap(u, vec_prev[q]) < TRACK_OVERLAP:  # the eigenvector close to its predecessor's
            return False
        centre = _centre_of(u, n, H)
        if abs(centre) > TRACK_CENTRE:
            # the copy lam -+ i w one harmonic nearer the centre may be more centred (the full method keeps the
            # more centred of the two): follow it too, keep the more centred; not if the two are no exact copies
            # of each other or their centres do not lie about one harmonic apart (further copies could compete)
            x = u.copy()
            other, ok = quadratic_eigenpair(A22, A21, lam - math.copysign(1.0, centre) * 1j * omega, x)
            if not ok or not _is_copy(other, lam, omega, 1e-6):
                return False
            centre_other = _centre_of(x, n, H)
            if abs(centre - centre_other) < 1.0 - COPY_SPREAD or abs(centre - centre_other) > 1.0 + COPY_SPREAD:
                return False
            if abs(centre_other) < abs(centre):
                lam, centre = other, centre_other
                u[:] = x
            if abs(centre) > 0.5 + COPY_SPREAD / 2:
                return False
        lam_kept[q] = lam
        vec_kept[q, :] = u
        centre_kept[q] = centre
    for a in range(count):
        for b in range(a):
            if abs(lam_kept[a] - lam_kept[b]) <= 1e-8 * (abs(lam_kept[a]) + omega):
                # the same eigenvalue twice: a double eigenvalue (the full method keeps both) only if the two
                # eigenvectors are independent, else two exponents converged to one
                if _overlap(vec_kept[a], vec_kept[b]) > DOUBLE_OVERLAP:
                    return False
            elif _is_copy(lam_kept[a], lam_kept[b], omega, 1e-3):
                return False
    return True


@numba.njit(cache=False)
def _overlap(x, y):
    """``|<x, y>| / (|x| |y|)``."""
    dot = 0.0j
    nx = 0.0
    ny = 0.0
    for r in range(x.shape[0]):
        dot += x[r].conjugate() * y[r]
        nx += x[r].real ** 2 + x[r].imag ** 2
        ny += y[r].real ** 2 + y[r].imag ** 2
    return abs(dot) / max(math.sqrt(nx * ny), 1e-300)


@numba.njit(cache=False)
def _hill_step(z, lam, jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window, mu_re, mu_im, track,
               lam_state, vec_state, lam_older, info):
    """Hill's multipliers of one point of a branch into ``mu_re + i mu_im`` (2n): ``(ok, tracked)``.

    ``track``: follow the exponents of the previous point (``lam_state``, ``vec_state``, ``info``: whether
    they may be followed, points since the last full solve, the previous point's number of unstable
    multipliers, whether ``lam_older`` holds the exponents of the point before, to extrapolate from) where
    :func:`_hill_tracked` accepts them, at most ``ANCHOR_EVERY - 1`` points in a row and
    not where the number of unstable multipliers changes; else (and always at the first point) the full
    method :func:`_hill_full`, after which following is allowed only when its selection is clear-cut (every
    kept exponent centred within ``0.5 + COPY_SPREAD / 2``, every other exponent that is not a copy of a kept one at
    least ``RUNNER_CENTRE`` off centre)."""
    n, H = ints[0], ints[1]
    size = n * (2 * H + 1)
    A21, A22, omega, period = _hill_matrix(z, lam, jac, ints, fl, E, P, ED, M, Minv, base, varying, coef,
                                           window)
    count = 2 * n
    lam_new = np.empty(count, dtype=np.complex128)
    vec_new = np.empty((count, size), dtype=np.complex128)
    centre = np.empty(count)
    if track and info[0] == 1 and info[1] < ANCHOR_EVERY - 1:
        # the shifts: the previous exponents, moved on by their last change where the point before had them
        sigma = lam_state.copy()
        if info[3] == 1:
            for q in range(count):
                near = np.inf
                step = 0.0j
                for r in range(count):
                    if abs(lam_state[q] - lam_older[r]) < near:
                        near = abs(lam_state[q] - lam_older[r])
                        step = lam_state[q] - lam_older[r]
                apart = np.inf
                for r in range(count):
                    if r != q:
                        apart = min(apart, abs(lam_state[q] - lam_state[r]))
                if near < apart / 4:
                    sigma[q] = lam_state[q] + step
        if _hill_tracked(A21, A22, n, H, omega, lam_state, vec_state, sigma, lam_new, vec_new, centre):
            unstable = _multipliers(lam_new, period, mu_re, mu_im)
            if unstable == info[2]:
                lam_older[:] = lam_state
                lam_state[:] = lam_new
                vec_state[:, :] = vec_new
                info[1] += 1
                info[3] = 1
                return True, True
    ok, runner = _hill_full(A21, A22, n, H, omega, lam_new, vec_new, centre)
    unstable = _multipliers(lam_new, period, mu_re, mu_im)
    clear = ok and runner >= RUNNER_CENTRE
    for q in range(count):
        clear = clear and abs(centre[q]) <= 0.5 + COPY_SPREAD / 2
    lam_older[:] = lam_state
    info[3] = 1 if info[0] == 1 else 0  # the previous exponents are worth extrapolating from
    lam_state[:] = lam_new
    vec_state[:, :] = vec_new
    info[0] = 1 if clear else 0
    info[1] = 0
    info[2] = unstable
    return ok, False


@numba.njit(cache=False)
def hill_branch(jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window, lams, Zs, mu_re, mu_im, hill_ok,
                track, tracked):
    """Hill's multipliers of the points of a branch in order (:func:`_hill_step`): ``tracked[i]`` whether
    point ``i``'s were followed from point ``i - 1``'s (else the full method, ``hill_ok[i]`` False where it
    failed)."""
    n, H = ints[0], ints[1]
    size = n * (2 * H + 1)
    lam_state = np.empty(2 * n, dtype=np.complex128)
    vec_state = np.empty((2 * n, size), dtype=np.complex128)
    lam_older = np.empty(2 * n, dtype=np.complex128)
    info = np.zeros(4, dtype=np.int64)
    for pt in range(lams.shape[0]):
        hill_ok[pt], tracked[pt] = _hill_step(Zs[pt], lams[pt], jac, ints, fl, E, P, ED, M, Minv, base, varying,
                                              coef, window, mu_re[pt], mu_im[pt], track, lam_state, vec_state,
                                              lam_older, info)


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
    rest, rest_f = np.zeros(2 * n), np.empty((ints[2], n))  # the state at rest, the forces there per instant
    lam_state = np.empty(2 * n, dtype=np.complex128)
    vec_state = np.empty((2 * n, size), dtype=np.complex128)
    lam_older = np.empty(2 * n, dtype=np.complex128)
    info = np.zeros(4, dtype=np.int64)
    for pt in range(lams.shape[0]):
        lam = lams[pt]
        z = Zs[pt]
        omega = speed_frame(lam, jac, ints, fl, base, varying, coef, window, M, p, A0, L)
        scale = scale_at_rest(rhs, p, 2.0 * np.pi / omega, n, ints[2], M, P, rest, a, rest_f)  # this frame's
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
            hill_ok[pt] = _hill_step(z, lam, jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window,
                                     mu_re[pt], mu_im[pt], True, lam_state, vec_state, lam_older, info)[0]
