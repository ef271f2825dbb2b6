"""numba kernel of the compiled harmonic-balance path's per-point data: the error estimate and Hill's multipliers.

It repeats what the Python reference does (the truncation-error estimate of
:mod:`rotorkit.analysis.periodic` and
:func:`~rotorkit.periodic.stability.hill_multipliers`), with the frame at each
point's speed rebuilt (prepared parameters and Jacobian at rest, as
:func:`rotorkit.periodic.compiled_aft.speed_frame` without the linear operator; once
per point: the error estimate, the force scale and Hill's matrix share it); the
settings ``ints``/``fl`` are those of :mod:`rotorkit.periodic.compiled`
(``ints[10]``: whether Hill's multipliers are computed). Hill's multipliers
along the branch (followed from point to point, a full solve where following
cannot vouch for the full method's selection) are
:mod:`rotorkit.periodic.compiled_hill`'s. The glue is in
:mod:`rotorkit.periodic.fastpath`.
"""

from __future__ import annotations

import numba
import numpy as np

from .compiled_aft import prepared_parameters, scale_at_rest
from .compiled_borrow import borrowed
from .compiled_functions import core_function, jac_function
from .compiled_hill import ANCHOR_EVERY, hill_branch, hill_step, hill_workspace

__all__ = ["point_data_kernel", "hill_branch", "ANCHOR_EVERY"]


@numba.njit(cache=False)
def _frame(lam, jac, ints, fl, base, varying, coef, window, p, A0, rest):
    """The part of :func:`~rotorkit.periodic.compiled_aft.speed_frame` the per-point data uses (not the linear
    operator): the prepared parameters ``p`` and the Jacobian at rest ``A0`` at speed ``lam`` (``rest``: the zero
    state, 2n); returns the base frequency."""
    prepared_parameters(lam, fl, base, varying, coef, window, p)
    A0[:, :] = 0.0
    jac(0.0, rest, p, A0)
    return lam / ints[3]


@numba.njit(cache=False)
def point_data_kernel(functions, ints, fl, E, P, ED, M, base, varying, coef, window, EG, EDG, EDDG, lams, Zs,
                      scales, accs, errors, mu_re, mu_im, hill_ok):
    """Per point: the truncation-error estimate (max |M (q'' - a)| on the grid of ``EG``'s rows over the residual
    scale, ``scales[i]`` where positive (the continuation kernel's), else computed here; at the grid's AFT
    samples, every ``G / N``-th instant, ``a`` is ``accs[i]`` (N, n: the continuation's last residual's) unless
    ``accs[i, 0, 0]`` is nan) and, with ``ints[10]``, Hill's multipliers (``hill_ok[i]`` False where the QR
    iteration failed).
    ``functions``: the addresses of the model's ``rhs`` and ``jac`` (the first four of
    :func:`~rotorkit.periodic.compiled_functions.function_addresses`), called as the continuation kernel calls them."""
    n = ints[0]
    G = EG.shape[0]
    rest, rest_f = np.zeros(2 * n), np.empty((ints[2], n))  # the state at rest, the forces there per instant
    # the synthesis of q, q', q'' on the grid per coordinate, the grid's instants contiguous (each entry summed
    # over the harmonics in their order, as a sum per instant would)
    work = (np.empty(base.shape[0]), np.empty((2 * n, 2 * n)), np.empty(2 * n), np.empty(2 * n), np.empty(n), rest,
            rest_f, EG.T.copy(), EDG.T.copy(), EDDG.T.copy(), np.empty((n, G)), np.empty((n, G)), np.empty((n, G)))
    _points(core_function(functions[0], functions[1]), jac_function(functions[2], functions[3]), ints, fl, E, P, ED,
            M, base, varying, coef, window, lams, Zs, scales, accs, errors, mu_re, mu_im, hill_ok, work,
            hill_workspace(n, ints[1]))


@numba.njit(cache=False)
def _points(rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, lams, Zs, scales, accs, errors, mu_re,
            mu_im, hill_ok, work, ws):
    """The loop over the points of :func:`point_data_kernel` on the work arrays it made (``work``: ``p, A0, y,
    a, acc, rest, rest_f``, the transposed synthesis matrices, ``Yq, Yv, Ya``; ``ws`` Hill's), every array
    borrowed for the call (:func:`~rotorkit.periodic.compiled_borrow.borrowed`)."""
    ints, fl, E, P, ED, M, base, varying, coef, window = borrowed((ints, fl, E, P, ED, M, base, varying, coef,
                                                                     window))
    lams, Zs, scales, accs, errors, mu_re, mu_im, hill_ok, work, ws = borrowed((lams, Zs, scales, accs, errors, mu_re,
                                                                                mu_im, hill_ok, work, ws))
    p, A0, y, a, acc, rest, rest_f, EGt, EDGt, EDDGt, Yq, Yv, Ya = work
    n = ints[0]
    H2 = E.shape[1]
    G = EGt.shape[1]
    for pt in range(lams.shape[0]):
        lam = lams[pt]
        z = Zs[pt]
        omega = _frame(lam, jac, ints, fl, base, varying, coef, window, p, A0, rest)
        scale = scales[pt]
        if not scale > 0.0:
            scale = scale_at_rest(rhs, p, 2.0 * np.pi / omega, n, ints[2], M, P, rest, a, rest_f)  # this frame's
        for i in range(n):
            rq, rv, ra = Yq[i], Yv[i], Ya[i]
            rq[:] = 0.0
            rv[:] = 0.0
            ra[:] = 0.0
            for h in range(H2):
                c = z[h * n + i]
                eq, ev, ea = EGt[h], EDGt[h], EDDGt[h]
                for j in range(G):
                    rq[j] += eq[j] * c
                    rv[j] += ev[j] * c
                    ra[j] += ea[j] * c
        worst = 0.0
        given = accs[pt]
        step = G // given.shape[0] if given.shape[0] > 0 and not np.isnan(given[0, 0]) else 0  # G: a multiple of N
        for j in range(G):
            for i in range(n):
                acc[i] = omega * omega * Ya[i, j]
            if step > 0 and j % step == 0:  # an AFT sample: the continuation evaluated a there
                for i in range(n):
                    a[n + i] = given[j // step, i]
            else:
                t = 2.0 * np.pi * j / (G * omega)
                for i in range(n):
                    y[i] = Yq[i, j]
                    y[n + i] = omega * Yv[i, j]
                a[:] = 0.0
                rhs(t, y, p, a)
            for i in range(n):
                s = 0.0
                for k in range(n):
                    s += (acc[k] - a[n + k]) * M[i, k]
                worst = max(worst, abs(s))
        errors[pt] = worst / scale
        if ints[10]:
            hill_ok[pt] = hill_step(z, omega, p, A0, jac, ints, E, ED, mu_re[pt], mu_im[pt], True, ws)[0]
