"""numba kernel of Hill's multipliers along a branch for the compiled harmonic-balance path.

It repeats :func:`~rotorkit.periodic.stability.hill_multipliers` on the frame of each point (prepared
parameters and Jacobian at rest of :func:`rotorkit.periodic.compiled_aft.speed_frame`, built once per point
by the caller); the work arrays are made once per branch (:func:`hill_workspace`). Its caller is
:func:`rotorkit.periodic.compiled_points.point_data_kernel`; :func:`hill_branch` runs it alone (tests).

Hill's multipliers along a branch
    The full method (:func:`_hill_full`) is the Python one: all eigenvalues of Hill's companion matrix
    (:func:`~rotorkit.periodic.eigen.eigenvalues`, per group of coupled harmonics:
    :func:`~rotorkit.periodic.compiled_hill_matrix.harmonic_groups`), the centre of each eigenvector the
    selection reaches (:func:`_select_lazy`; tests/test_periodic_hill_full.py compares it with every centre's),
    the selection. Consecutive points of a branch have close exponents, so the kernel follows the previous
    point's ``2n`` kept exponents instead (:func:`_hill_tracked`: shifted inverse iteration on the quadratic
    eigenproblem from the previous exponents, extrapolated, and their eigenvectors; a conjugate by conjugation;
    a real exponent followed in real arithmetic, the same values), a few solves of size ``n (2H + 1)`` instead
    of a QR iteration of twice that size, or of the size of the one group of coupled harmonics that holds the
    previous eigenvector (:func:`~rotorkit.periodic.compiled_hill_matrix.follow_exponent`). It keeps a followed
    set only where it is the full method's selection
    on the evidence at hand: each exponent converged to an eigenvector close to its predecessor's and is its
    family's most centred member (within ``TRACK_CENTRE`` of harmonic 0, or the more centred of it and its copy
    one harmonic nearer the centre, their centres about one harmonic apart), the ``2n`` are distinct families
    (or a double eigenvalue with independent eigenvectors), and the number of multipliers outside the unit
    circle is the previous point's (a stability change is always decided by the full method). Otherwise, at
    the first point and at least every ``ANCHOR_EVERY`` points, the full method runs; following resumes only
    from a full solve whose selection is clear-cut (the other exponents, not copies of the kept ones, at least
    ``RUNNER_CENTRE`` off centre). tests/test_periodic_hill_tracking.py compares both at every point of
    branches through folds.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .compiled_aft import speed_frame
from .compiled_hill_matrix import (block_table, follow_exponent, group_eigenvalues, group_workspace, harmonic_groups,
                                   hill_matrix)
from .eigen import complex_lu, eigenvalues, lu_solve, null_vector_into, row_norms
from .stability import STABILITY_TOL

__all__ = ["hill_workspace", "hill_step", "hill_branch", "ANCHOR_EVERY", "TRACK_CENTRE", "RUNNER_CENTRE",
           "TRACK_OVERLAP", "COPY_SPREAD", "DOUBLE_OVERLAP", "CENTRE_MARGIN"]

#: a full solve of Hill's eigenproblem at least every ANCHOR_EVERY points of a branch
ANCHOR_EVERY = 64
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
#: the full method computes the centre of a copy lambda + i s w of an exponent of centre c (about c - s) only
#: where |c - s| - CENTRE_MARGIN could come before the selection's end (:func:`_select_lazy`)
CENTRE_MARGIN = 0.25


@numba.njit(cache=False)
def hill_workspace(n, H):
    """The work arrays of Hill's multipliers along a branch (n coordinates, H harmonics), made once:
    ``(y, Aj, f, F, cs, used, A21, A22, Gr, ur, wr, br, piv, G, u, x, w, b, big, re, im, vectors,
    centres, lam_new, vec_new, centre, sigma, lam_state, vec_state, lam_older, info, invr, inv, lam_oldest, kk,
    cc, groups)`` (``kk``, ``cc``: :func:`~rotorkit.periodic.compiled_hill_matrix.block_table`; ``groups``: the
    :func:`~rotorkit.periodic.compiled_hill_matrix.group_workspace`);
    ``lam_state``, ``vec_state``, ``lam_older``, ``info``, ``lam_oldest``: the state carried from point to point
    (:func:`hill_step`), ``info`` zeroed (no previous point)."""
    H2 = 2 * H + 1
    size = n * H2
    nn = n * n
    c16 = np.complex128
    kk, cc = block_table(H)
    return (np.empty(2 * n), np.empty((2 * n, 2 * n)),
            np.empty(2 * nn), np.empty((2 * nn, 2 * H2)), np.empty(2 * H2), np.empty(2 * nn, dtype=np.bool_),
            np.empty((size, size)), np.empty((size, size)),
            np.empty((size, size)), np.empty(size), np.empty(size), np.empty(size), np.empty(size, dtype=np.int64),
            np.empty((size, size), dtype=c16), np.empty(size, dtype=c16), np.empty(size, dtype=c16),
            np.empty(size, dtype=c16), np.empty(size, dtype=c16),
            np.empty((2 * size, 2 * size)), np.empty(2 * size), np.empty(2 * size),
            np.empty((2 * size, size), dtype=c16),
            np.empty(2 * size),
            np.empty(2 * n, dtype=c16), np.empty((2 * n, size), dtype=c16), np.empty(2 * n), np.empty(2 * n, dtype=c16),
            np.empty(2 * n, dtype=c16), np.empty((2 * n, size), dtype=c16), np.empty(2 * n, dtype=c16),
            np.zeros(5, dtype=np.int64), np.empty(size), np.empty(size, dtype=c16), np.empty(2 * n, dtype=c16), kk, cc,
            group_workspace(n, H))


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
def _harmonic(x, n, i, k):
    """The complex harmonic ``c_k`` (``k = -H ... H``) of coordinate ``i`` of the real-basis coefficients ``x``:
    ``c_0 = x_0``, ``c_+-k = (a_k -+ i b_k) / 2``."""
    if k == 0:
        return x[i] + 0.0j
    a = x[(2 * abs(k) - 1) * n + i]
    b = x[2 * abs(k) * n + i]
    return (a - 1j * b) / 2.0 if k > 0 else (a + 1j * b) / 2.0


@numba.njit(cache=False)
def _shifted(x, n, H, s, out):
    """The real-basis coefficients of ``x`` with every complex harmonic moved down by ``s`` (``c'_k = c_{k+s}``,
    zero beyond ``H``): the eigenvector's estimate of the copy ``lambda + i s w`` (centre minus ``s``), a start
    vector of the copy's inverse iteration."""
    for i in range(n):
        out[i] = _harmonic(x, n, i, s)
        for k in range(1, H + 1):
            plus = _harmonic(x, n, i, k + s) if abs(k + s) <= H else 0.0j
            minus = _harmonic(x, n, i, -k + s) if abs(-k + s) <= H else 0.0j
            out[(2 * k - 1) * n + i] = plus + minus  # a_k = c_k + c_-k, b_k = i (c_k - c_-k)
            out[2 * k * n + i] = 1j * (plus - minus)


@numba.njit(cache=False)
def _null_vector(A21, A22, lam, Gr, ur, piv, G, x):
    """The null vector ``x`` of ``A21 + lam A22 - lam^2 I`` (:func:`~rotorkit.periodic.eigen.null_vector_into`),
    in real arithmetic for a real ``lam`` (the complex computation's values)."""
    size = A21.shape[0]
    if lam.imag == 0.0:
        s = lam.real
        for r in range(size):
            for c in range(size):
                Gr[r, c] = A21[r, c] + s * A22[r, c]
            Gr[r, r] -= s * s
        null_vector_into(Gr, piv, ur)
        for r in range(size):
            x[r] = ur[r]
        return
    for r in range(size):
        for c in range(size):
            G[r, c] = A21[r, c] + lam * A22[r, c]
        G[r, r] -= lam * lam
    null_vector_into(G, piv, x)


@numba.njit(cache=False)
def _is_copy(a, b, omega, tol):
    """Whether ``(a - b) / (i w)`` is a nonzero integer to ``tol`` (the same Floquet multiplier)."""
    d = (a - b) / (1j * omega)
    rd = math.floor(d.real + 0.5)
    return abs(d.imag) < tol and rd != 0 and abs(d.real - rd) < tol


@numba.njit(cache=False, inline="always")
def _copy_of_kept(wr, wi, i, kept, nk, omega):
    """Whether exponent ``i`` is a copy (:func:`_is_copy`) of one of the ``nk`` kept so far."""
    for q in range(nk):
        j = kept[q]
        if _is_copy(complex(wr[i], wi[i]), complex(wr[j], wi[j]), omega, 1e-6):
            return True
    return False


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
        if _copy_of_kept(wr, wi, i, kept, nk, omega):
            continue
        if nk == 2 * n:
            runner = abs(centre[i])
            break
        kept[nk] = i
        nk += 1
    return kept[:nk], runner


@numba.njit(cache=False)
def _centre_at(A21, A22, wr, wi, e, n, H, vectors, centre, exact, Gr, ur, piv, G, x):
    """The centre (:func:`_centre_of`) and eigenvector of eigenvalue ``e`` (and of its equals and conjugates)
    into ``centre``, ``vectors`` (``exact`` set): the null vector of ``A21 + lam A22 - lam^2 I`` for the member
    with ``wi <= 0`` (:func:`_null_vector`; the first of a pair as the QR iteration stores them), the conjugate
    vector and minus the centre for ``wi > 0`` (its harmonics mirrored): the same values in any order."""
    size = n * (2 * H + 1)
    _null_vector(A21, A22, complex(wr[e], -abs(wi[e])), Gr, ur, piv, G, x)
    c = _centre_of(x, n, H)
    for f in range(wr.shape[0]):
        if f == e or (not exact[f] and wr[f] == wr[e] and abs(wi[f]) == abs(wi[e])):
            exact[f] = True
            if wi[f] > 0.0:
                centre[f] = -c
                for r in range(size):
                    vectors[f, r] = x[r].conjugate()
            else:
                centre[f] = c
                vectors[f, :] = x


@numba.njit(cache=False)
def _offset(wr, wi, j, e, omega, tol):
    """``s`` if exponent ``j`` is ``e + i s w`` to ``tol`` (``s`` a nonzero integer; :func:`_is_copy` in real
    arithmetic, to rounding), else 0."""
    d = (wi[j] - wi[e]) / omega
    s = math.floor(d + 0.5)
    if abs(wr[j] - wr[e]) < tol * omega and abs(d - s) < tol:
        return int(s)
    return 0


@numba.njit(cache=False)
def _select_lazy(A21, A22, wr, wi, n, H, omega, vectors, centre, Gr, ur, piv, G, x):
    """The centre of every eigenvector (:func:`_centre_at`) and :func:`_select` (the same ``kept``, the kept
    eigenvectors and centres the same values; ``runner`` the same below ``RUNNER_CENTRE``, else a bound from
    below, at least ``RUNNER_CENTRE``: all :func:`hill_step` asks), a null vector computed only for the
    eigenvalues the selection reaches.

    The selection walks the exponents in the order of ``|centre|`` and stops after the ``2n``-th family and
    its runner. A copy ``lambda + i s w`` of an exponent whose centre ``c`` is known has the centre ``c - s``
    (its eigenvector the shifted one; to 1e-10 on the bench's branch): until its centre is needed, a lower
    bound ``|c - s| - CENTRE_MARGIN``; an exponent is walked only when no unknown one's bound reaches its
    ``|centre|``. An exponent of no known family is computed first, the middle one of its copies (the most
    centred if the copies are). Every prediction is checked where a centre is computed, and two predictions
    of one exponent against each other: one off by ``CENTRE_MARGIN / 2``, or a centre not finite, and every
    centre is computed, then :func:`_select`. A copy (:func:`_is_copy`) of a kept exponent comes
    after it in the walk, which skips it: its centre is not needed either."""
    count = wr.shape[0]
    exact = np.zeros(count, dtype=np.bool_)
    walked = np.zeros(count, dtype=np.bool_)
    known = np.zeros(count, dtype=np.bool_)  # a predicted centre
    guess = np.zeros(count)
    kept = np.empty(2 * n, dtype=np.int64)
    nk = 0
    runner = np.inf
    trusted = True
    while trusted:
        best, far = -1, np.inf  # the next of the walk among the known centres (ties: the lower index)
        for e in range(count):
            if exact[e] and not walked[e] and abs(centre[e]) < far:
                best, far = e, abs(centre[e])
        low, bound = -1, np.inf  # the unknown centre that could come first
        for e in range(count):
            if not exact[e] and not walked[e]:
                b = abs(guess[e]) - CENTRE_MARGIN if known[e] else -1.0
                if b < bound:
                    low, bound = e, b
        if nk == 2 * n and min(far, bound) >= RUNNER_CENTRE:  # the runner is at least that: clear-cut
            runner = min(far, bound)
            break
        if low >= 0 and bound <= far:
            if not known[low]:  # a new family: its middle member (copies s_lo ... s_hi of low)
                lo = hi = 0
                for j in range(count):
                    if not exact[j] and not walked[j] and not known[j]:
                        s = _offset(wr, wi, j, low, omega, 1e-6)
                        lo, hi = min(lo, s), max(hi, s)
                middle = (lo + hi) // 2
                if middle != 0:
                    for j in range(count):
                        if not exact[j] and not walked[j] and not known[j] and \
                                _offset(wr, wi, j, low, omega, 1e-6) == middle:
                            low = j
                            break
            _centre_at(A21, A22, wr, wi, low, n, H, vectors, centre, exact, Gr, ur, piv, G, x)
            for e in range(count):
                if exact[e] and not walked[e] and not math.isfinite(centre[e]):
                    trusted = False
                if exact[e] and known[e] and abs(centre[e] - guess[e]) > CENTRE_MARGIN / 2:
                    trusted = False
                if not exact[e] or wr[e] != wr[low] or abs(wi[e]) != abs(wi[low]):
                    continue
                for j in range(count):  # the copies of the new exact ones
                    s = 0 if exact[j] else _offset(wr, wi, j, e, omega, 1e-6)
                    if s != 0:
                        g = centre[e] - s
                        if known[j] and abs(g - guess[j]) > CENTRE_MARGIN / 2:
                            trusted = False
                        guess[j] = g
                        known[j] = True
            continue
        if best < 0:
            break
        walked[best] = True
        if _copy_of_kept(wr, wi, best, kept, nk, omega):
            continue
        if nk == 2 * n:
            runner = far
            break
        kept[nk] = best
        nk += 1
        for e in range(count):  # its copies come later in the walk, and it skips them: no centre needed
            if (not walked[e] and _offset(wr, wi, e, best, omega, 1e-4) != 0
                    and _is_copy(complex(wr[e], wi[e]), complex(wr[best], wi[best]), omega, 1e-6)):
                walked[e] = True
    if not trusted:
        for e in range(count):
            if not exact[e]:
                _centre_at(A21, A22, wr, wi, e, n, H, vectors, centre, exact, Gr, ur, piv, G, x)
        return _select(wr, wi, centre, n, omega)
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
def _hill_full(A21, A22, n, H, omega, lam_kept, vec_kept, centre_kept, big, wr, wi, vectors, centre, Gr, ur, piv, G,
               x):
    """Hill's exponents by the full method: all eigenvalues of the companion matrix (:func:`eigenvalues`; per
    group of coupled harmonics where there are several,
    :func:`~rotorkit.periodic.compiled_hill_matrix.harmonic_groups`),
    the centre of every eigenvector the selection reaches, the selection (:func:`_select_lazy`). Into
    ``lam_kept`` (2n), their eigenvectors ``vec_kept`` (2n, size) and centres; returns ``(ok, runner)`` (False
    if the QR iteration fails or fewer than ``2n`` families; ``runner`` as :func:`_select_lazy`'s)."""
    size = n * (2 * H + 1)
    group = np.empty(H + 1, dtype=np.int64)
    if harmonic_groups(A21, A22, n, H, group) > 1:
        if not group_eigenvalues(A21, A22, n, H, group, wr, wi):
            return False, 0.0
    else:
        big[:, :] = 0.0
        for i in range(size):
            big[i, size + i] = 1.0
            for col in range(size):
                big[size + i, col] = A21[i, col]
                big[size + i, size + col] = A22[i, col]
        if not eigenvalues(big, wr, wi):
            return False, 0.0
    kept, runner = _select_lazy(A21, A22, wr, wi, n, H, omega, vectors, centre, Gr, ur, piv, G, x)
    for q in range(kept.shape[0]):
        i = kept[q]
        lam_kept[q] = complex(wr[i], wi[i])
        vec_kept[q, :] = vectors[i]
        centre_kept[q] = centre[i]
    for q in range(kept.shape[0], 2 * n):
        lam_kept[q] = np.nan
    # a double eigenvalue kept twice has one null vector from complex_null_vector twice: for following, a second
    # one from another right-hand side (independent if the eigenvalue is semisimple; else following fails)
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
                for i in range(size):
                    x[i] = (i + 1.0) * (-1.0) ** i
                lu_solve(G, piv, x, x)
                vec_kept[q, :] = x
                centre_kept[q] = _centre_of(x, n, H)
                break
    return kept.shape[0] == 2 * n, runner


@numba.njit(cache=False)
def _hill_tracked(A21, A22, n, H, omega, lam_prev, vec_prev, sigma, lam_kept, vec_kept, centre_kept, u, x, Gr, ur, wr,
                  br, invr, piv, G, w, b, inv, gws):
    """Hill's exponents followed from the previous point's (``lam_prev``, ``vec_prev``) by shifted inverse
    iteration (:func:`~rotorkit.periodic.compiled_hill_matrix.follow_exponent`: on one group of coupled
    harmonics where the start vector lies in one, work arrays ``gws``) from the shifts ``sigma`` (predicted
    exponents), a conjugate pair's second member by conjugation, into ``lam_kept``, ``vec_kept``, ``centre_kept``.

    False (then the full method runs instead) unless every exponent converged to an eigenvector close to its
    predecessor's (overlap ``TRACK_OVERLAP``) and is its family's most centred member (centred within
    ``TRACK_CENTRE``, or compared with its copy one harmonic nearer the centre, as the full method compares
    them), and the ``2n`` exponents are distinct (or a double eigenvalue with independent eigenvectors) and no
    copies of each other."""
    size = n * (2 * H + 1)
    count = 2 * n
    n0, n1 = row_norms(A22, A21)
    group, rows, f21, f22, fGr, fG, v = gws
    groups = harmonic_groups(A21, A22, n, H, group)
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
        lam, ok = follow_exponent(A21, A22, n, groups, group, rows, f21, f22, fGr, fG, v, n0, n1, sigma[q], u, Gr, ur,
                                  wr, br, invr, piv, G, w, b, inv)
        if not ok:
            return False
        if _overlap(u, vec_prev[q]) < TRACK_OVERLAP:  # the eigenvector close to its predecessor's
            return False
        centre = _centre_of(u, n, H)
        if abs(centre) > TRACK_CENTRE:
            # the copy lam + i s w (s the sign of the centre: its eigenvector shifted by -s harmonics) may be
            # more centred (the full method keeps the more centred of the two): follow it too, from u shifted,
            # keep the more centred; not if the two are no exact copies of each other or their centres do not
            # lie about one harmonic apart (further copies could compete)
            s = 1 if centre > 0.0 else -1
            _shifted(u, n, H, s, x)
            other, ok = follow_exponent(A21, A22, n, groups, group, rows, f21, f22, fGr, fG, v, n0, n1,
                                        lam + s * 1j * omega, x, Gr, ur, wr, br, invr, piv, G, w, b, inv)
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
def _nearest(x, values, skip):
    """The index of the entry of ``values`` nearest ``x`` (not ``skip``) and the squared distance."""
    best, near = -1, np.inf
    for r in range(values.shape[0]):
        if r != skip:
            d = x - values[r]
            d2 = d.real * d.real + d.imag * d.imag
            if d2 < near:
                best, near = r, d2
    return best, near


@numba.njit(cache=False)
def _shifts(lam_state, lam_older, lam_oldest, info, sigma):
    """The predicted exponents ``sigma``: the previous ones, extrapolated where the points before had them
    (each matched to its nearest predecessor, within a quarter of the distance to its own nearest neighbour):
    linearly from the point before (``info[3]``), quadratically from the two before (``info[4]``) unless the
    second difference is not the smaller (then linearly)."""
    count = lam_state.shape[0]
    sigma[:] = lam_state
    if info[3] != 1:
        return
    for q in range(count):
        a = lam_state[q]
        r, near = _nearest(a, lam_older, -1)
        apart = _nearest(a, lam_state, q)[1]
        if not near < apart / 16:  # squared distances: near < apart / 4
            continue
        b = lam_older[r]
        sigma[q] = a + (a - b)
        if info[4] == 1:
            c_at, near_c = _nearest(b, lam_oldest, -1)
            if near_c < _nearest(b, lam_older, r)[1] / 16:
                curve = (a - b) - (b - lam_oldest[c_at])
                if abs(curve) < abs(a - b):
                    sigma[q] += curve


@numba.njit(cache=False)
def hill_step(z, omega, p, A0, jac, ints, E, ED, mu_re, mu_im, track, ws):
    """Hill's multipliers of one point of a branch into ``mu_re + i mu_im`` (2n): ``(ok, tracked)``; the frame
    at the point's speed ``p``, ``A0``, ``omega`` (:func:`~rotorkit.periodic.compiled_aft.speed_frame`), the
    work arrays and the state carried from the previous point ``ws`` (:func:`hill_workspace`).

    ``track``: follow the exponents of the previous point (``lam_state``, ``vec_state``, ``info``: whether
    they may be followed, points since the last full solve, the previous point's number of unstable
    multipliers, whether ``lam_older`` and ``lam_oldest`` hold the exponents of the two points before, to
    extrapolate from: :func:`_shifts`) where :func:`_hill_tracked` accepts them, at most ``ANCHOR_EVERY - 1``
    points in a row and not where the number of unstable multipliers changes; else (and always at the first
    point) the full method :func:`_hill_full`, after which following is allowed only when its selection is
    clear-cut (every kept exponent centred within ``0.5 + COPY_SPREAD / 2``, every other exponent that is not
    a copy of a kept one at least ``RUNNER_CENTRE`` off centre)."""
    n, H = ints[0], ints[1]
    period = 2.0 * np.pi / omega
    # the work arrays unpacked once: a tuple passed to a function costs a reference count per member
    y, Aj, f, F, cs, used, A21, A22, Gr, ur, wr, br, piv, G, u, x, w, b, big, re, im, vectors, centres = ws[:23]
    lam_new, vec_new, centre, sigma, lam_state, vec_state, lam_older, info, invr, inv, lam_oldest, kk, cc = ws[23:36]
    hill_matrix(z, omega, period, p, A0, jac, ints, E, ED, y, Aj, f, F, cs, used, kk, cc, A21, A22)
    count = 2 * n
    if track and info[0] == 1 and info[1] < ANCHOR_EVERY - 1:
        _shifts(lam_state, lam_older, lam_oldest, info, sigma)
        if _hill_tracked(A21, A22, n, H, omega, lam_state, vec_state, sigma, lam_new, vec_new, centre, u, x, Gr, ur, wr,
                         br, invr, piv, G, w, b, inv, ws[36]):
            unstable = _multipliers(lam_new, period, mu_re, mu_im)
            if unstable == info[2]:
                lam_oldest[:] = lam_older
                lam_older[:] = lam_state
                lam_state[:] = lam_new
                vec_state[:, :] = vec_new
                info[1] += 1
                info[4] = info[3]
                info[3] = 1
                return True, True
    ok, runner = _hill_full(A21, A22, n, H, omega, lam_new, vec_new, centre, big, re, im, vectors, centres, Gr, ur, piv,
                            G, x)
    unstable = _multipliers(lam_new, period, mu_re, mu_im)
    clear = ok and runner >= RUNNER_CENTRE
    for q in range(count):
        clear = clear and abs(centre[q]) <= 0.5 + COPY_SPREAD / 2
    lam_oldest[:] = lam_older
    lam_older[:] = lam_state
    # the previous exponents are worth extrapolating from if they were a followed set, and so the ones before
    info[4] = info[3] if info[0] == 1 else 0
    info[3] = 1 if info[0] == 1 else 0
    lam_state[:] = lam_new
    vec_state[:, :] = vec_new
    info[0] = 1 if clear else 0
    info[1] = 0
    info[2] = unstable
    return ok, False


@numba.njit(cache=False)
def hill_branch(jac, ints, fl, E, P, ED, M, Minv, base, varying, coef, window, lams, Zs, mu_re, mu_im, hill_ok,
                track, tracked):
    """Hill's multipliers of the points of a branch in order (:func:`hill_step`): ``tracked[i]`` whether
    point ``i``'s were followed from point ``i - 1``'s (else the full method, ``hill_ok[i]`` False where it
    failed)."""
    n, H = ints[0], ints[1]
    size = n * (2 * H + 1)
    p = np.empty(base.shape[0])
    A0 = np.empty((2 * n, 2 * n))
    L = np.empty((size, size))
    ws = hill_workspace(n, H)
    for pt in range(lams.shape[0]):
        omega = speed_frame(lams[pt], jac, ints, fl, base, varying, coef, window, M, p, A0, L)
        hill_ok[pt], tracked[pt] = hill_step(Zs[pt], omega, p, A0, jac, ints, E, ED, mu_re[pt], mu_im[pt], track, ws)
