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
to rounding. The algorithm's own economies are the reference's (the corrector's Newton with
``lazy_jacobian``, the tangent from the corrector's last Newton matrix); here the lazy Jacobian is
assembled from the sampled states the last residual left in the workspace (no second residual), and the
tangent reuses that matrix's LU factors where Newton made them. The predictor's quadratic and cubic terms live in
the call: as the kernel runs in calls of 16 points when a progress callback is given, each call starts
without it (the reference does the same).

Integer settings ``ints``: ``n, H, N, nu, n_switches, max_iterations, max_new, count, max_points, start``;
float settings ``fl``: ``s0, z_scale, l_scale, lo, hi, d_lam, h, min_step, max_step, tol, direction, bound``;
``ints[10]``: whether :func:`~rotorkit.periodic.compiled_points.point_data_kernel` computes Hill's multipliers.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .compiled_aft import force_scale_into, residual, residual_same_states, same_state, switches_of, workspace
from .compiled_borrow import borrowed
from .compiled_folds import grazing_value
from .compiled_functions import core_function, jac_function
from .compiled_newton import bordered, buffers, newton, solve_fixed, vector_norm
from .eigen import lu_factor, lu_solve

__all__ = ["continue_kernel"]

#: the reference's CURVATURE_SHARE (rotorkit.periodic.continuation)
CURVATURE_SHARE = 0.03

# statuses of continue_kernel
PAUSED, BUDGET, BOUND, MIN_STEP = 0, 1, 2, 3


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
    norm = vector_norm(t)
    if not math.isfinite(norm) or norm == 0.0:
        return False
    for i in range(m + 1):
        t[i] /= norm
    return True


@numba.njit(cache=False)
def _corrected_tangent(factored, JF, t, nb):
    """The reference's ``_corrected_tangent``: unit ``t = JF^-1 [0; 1]`` from the corrector's Newton matrix
    ``JF = [A; scale t_0^T]`` (its LU factors in ``nb[2]``, ``nb[3]`` if ``factored``, else factored here);
    False if singular or not finite."""
    LU, piv, b = nb[2], nb[3], nb[13]
    m = LU.shape[0]
    if not factored:
        for r in range(m):
            for c in range(m):
                LU[r, c] = JF[r, c]
        if not lu_factor(LU, piv):
            return False
    for c in range(m):
        b[c] = 0.0
    b[m - 1] = 1.0
    lu_solve(LU, piv, b, t)
    norm = vector_norm(t)
    if not math.isfinite(norm) or norm == 0.0:
        return False
    for i in range(m):
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
    if not residual(z, lam + d, False, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, plus, J):
        return False
    if not residual(z, lam, True, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R, J):
        return False
    for r in range(size):
        for c in range(size):
            A[r, c] = J[r, c] * z_scale
        A[r, size] = (plus[r] - R[r]) / d * l_scale
    return True


@numba.njit(cache=False, inline="always")  # inlined: a call passing the work arrays costs ~0.2 us
def _correct(u_pred, tvec, u, scale, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, F, JF):
    """The corrector of :func:`~rotorkit.periodic.continuation.continue_branch`: ``(converged, iterations,
    norm, factored)``, the solution in ``u`` and Newton's matrix in ``JF`` (the last evaluated: Newton's
    ``lazy_jacobian``), ``factored`` as :func:`newton`'s; ``scale`` the residual scale of the last point.

    ``dR/dlambda`` (frozen at the prediction) is the forward difference of step ``d_lam`` from the residual
    at the prediction, which is also Newton's first evaluation."""
    zp, Rz, Jz, plus, column = nb[7], nb[8], nb[9], nb[10], nb[11]
    size = zp.shape[0]
    z_scale, l_scale = fl[1], fl[2]
    for i in range(size):
        zp[i] = u_pred[i] * z_scale
    lp = u_pred[size] * l_scale
    if not residual(zp, lp, True, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, Rz, Jz):
        return False, 0, np.inf, False
    if not residual_same_states(zp, lp + fl[5], rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws,
                                plus):  # the same zp: its sampled states reused
        return False, 0, np.inf, False
    for i in range(size):
        column[i] = (plus[i] - Rz[i]) / fl[5]
    for i in range(size):
        column[i] *= l_scale
    for i in range(size + 1):
        u[i] = u_pred[i]
    bordered(u, u_pred, tvec, column, scale, z_scale, Rz, Jz, True, F, JF)
    ok, iterations, norm, factored = newton(u, 1, 0.0, u_pred, tvec, column, scale, ints[5], True, True, rhs, jac,
                                             ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, F, JF)
    return ok, iterations, norm, factored


@numba.njit(cache=False, inline="always")
def _accelerations(ws, lam, out):
    """The last residual's accelerations at the AFT samples into ``out`` (N, n) if it was evaluated at ``lam``
    (Newton's last evaluation is its solution), else ``nan`` in ``out[0, 0]``."""
    if ws[18][0] != lam:
        out[0, 0] = np.nan
        return
    acc = ws[17]
    for j in range(acc.shape[0]):
        for i in range(acc.shape[1]):
            out[j, i] = acc[j, i]


@numba.njit(cache=False)
def _curvature(u_prev, u0, t0, t_prev, smooth, curve):
    """The predictor's quadratic term (the reference's ``_curvature``): ``(t0 - t_prev) / (2 d)``,
    ``d = |u0 - u_prev|``; zero unless ``smooth`` (zero: the tangent alone)."""
    m = u0.shape[0]
    d = 0.0
    if smooth:
        for i in range(m):
            e = u0[i] - u_prev[i]
            d += e * e
        d = math.sqrt(d)
    if not smooth or d == 0.0:
        for i in range(m):
            curve[i] = 0.0
        return
    for i in range(m):
        curve[i] = (t0[i] - t_prev[i]) / (2.0 * d)


@numba.njit(cache=False)
def _distance(a, b, h, c):
    """``|a - (b + h c)|``."""
    s = 0.0
    for i in range(a.shape[0]):
        d = a[i] - (b[i] + h * c[i])
        s += d * d
    return math.sqrt(s)


@numba.njit(cache=False)
def _corner(u0, t0, h, u1, t_new, scale, rhs, jac, sw, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb,
            F, JF):
    """:func:`rotorkit.periodic.continuation._corner`: ``(accepted, iterations, norm)``."""
    m = u0.shape[0]
    size = m - 1
    z_scale, l_scale = fl[1], fl[2]
    ns = max(ints[4], 1)
    u_pred = u0 + h * t0
    s0 = np.zeros(ns, dtype=np.bool_)
    sp = np.zeros(ns, dtype=np.bool_)
    g0 = switches_of(u0[:size] * z_scale, u0[size] * l_scale, s0, rhs, jac, sw, ints, fl, E, ED, M, base, varying,
                      coef, window)
    gp = switches_of(u_pred[:size] * z_scale, u_pred[size] * l_scale, sp, rhs, jac, sw, ints, fl, E, ED, M, base,
                      varying, coef, window)
    if same_state(s0, sp):
        return False, 0, 0.0
    A = np.empty((size, m))
    t1 = np.empty(m)
    if not _full_jacobian(u_pred, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, A):
        return False, 0, 0.0
    if not _tangent(A, t0, t1, nb):
        return False, 0, 0.0
    into = gp - g0
    ua = u0 + h * t1
    along = switches_of(ua[:size] * z_scale, ua[size] * l_scale, sp, rhs, jac, sw, ints, fl, E, ED, M, base,
                         varying, coef, window) - g0
    if along * into < 0:
        for i in range(m):
            t1[i] = -t1[i]
    u_pred = u0 + h * t1
    ok, iterations, norm, factored = _correct(u_pred, t1, u1, scale, rhs, jac, ints, fl, E, P, ED, M, base, varying,
                                              coef, window, ws, nb, F, JF)
    if not ok:
        return False, 0, 0.0
    if _distance(u1, u0, h, t1) > h:
        return False, 0, 0.0
    s1 = np.zeros(ns, dtype=np.bool_)
    switches_of(u1[:size] * z_scale, u1[size] * l_scale, s1, rhs, jac, sw, ints, fl, E, ED, M, base, varying, coef,
                 window)
    if same_state(s1, s0):
        return False, 0, 0.0
    if not _corrected_tangent(factored, JF, t_new, nb):
        return False, 0, 0.0
    return True, iterations, norm


@numba.njit(cache=False)
def continue_kernel(functions, ints, fl, E, P, ED, M, base, varying, coef, window, trig, terms, weights, u0, t0,
                    out_u, out_t, out_norm, out_scale, out_acc, out_corner):
    """The loop of :func:`~rotorkit.periodic.continuation.continue_branch` from ``(u0, t0)`` (scaled; updated to
    resume) for at most ``ints[6]`` new points; ``ints[7]`` points exist. With ``ints[9] == 1`` the start tangent is
    computed first (along ``fl[10]``) and the start point is the first row written (counted among the new points;
    its tangent, its scale the residual scale there, its accelerations unknown: ``nan``; ``out_u[0]``, the start
    itself, is the caller's); ``ints[9] == 2``: only Newton at
    ``fl[11]`` (tolerance ``fl[9]``) from ``u0[:-1]`` (unscaled) into ``out_u[0]``, returning ``(converged,
    iterations)``; ``ints[9] == 3``: the largest amplitude of the linear response (one Newton step from zero) over
    the parameter values in ``t0``, into ``out_norm[0]``; ``ints[9] == 4``: the contact switches at ``(u0[:-1],
    fl[11])``, the largest value into ``out_norm[0]`` and per switch whether it is positive at some sample into
    ``out_corner``; ``ints[9] == 5``: the grazing fold between the points ``out_u`` (6 rows,
    :func:`~rotorkit.periodic.compiled_folds.grazing_value`; ``out_corner[:6]`` which exist, ``ints[6]`` steps per
    piece, ``ints[8]`` aims per step) into ``out_norm[0]``. Returns ``(status, new points)``; ``fl[6]`` holds the
    next step; ``out_scale`` each new point's residual scale (:func:`~rotorkit.periodic.compiled_aft.scale_at_rest`
    at its parameter: the corrector's for the next step, and the per-point data's), ``out_acc`` (rows, N, n) its
    accelerations at the AFT samples (the last residual's, at the point: the per-point error estimate's there;
    ``nan`` first where the last residual was elsewhere). ``trig``, ``terms``, ``weights``: the AFT Jacobian's
    tables (:func:`~rotorkit.periodic.compiled_aft.aft_tables`); ``functions`` the addresses of the model's ``rhs``,
    ``jac`` and ``switches`` (:func:`~rotorkit.periodic.compiled_functions.function_addresses`)."""
    rhs = core_function(functions[0], functions[1])
    jac = jac_function(functions[2], functions[3])
    sw = core_function(functions[4], functions[5])
    m = u0.shape[0]
    size = m - 1
    # the work arrays, made here and lent to _continue (which borrows them: compiled_borrow)
    scratch = (np.empty((size, m)), np.zeros(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m),
               np.zeros(m), np.zeros(m))
    return _continue(rhs, jac, sw, ints, fl, E, P, ED, M, base, varying, coef, window,
                     workspace(ints, base, trig, terms, weights), buffers(m, size), np.empty(m), np.empty((m, m)),
                     scratch, u0, t0, out_u, out_t, out_norm, out_scale, out_acc, out_corner)


@numba.njit(cache=False)
def _continue(rhs, jac, sw, ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, F, JF, scratch, u0, t0,
              out_u, out_t, out_norm, out_scale, out_acc, out_corner):
    """:func:`continue_kernel`'s work (its modes) on the work arrays it made
    (``scratch``: the start tangent's matrix and reference, then ``u1, t1, u_pred, u_prev, t_prev, curve,
    cubic``), every array borrowed for the call (:func:`~rotorkit.periodic.compiled_borrow.borrowed`: the hot
    calls below pass them without reference counts)."""
    ints, fl, E, P, ED, M, base, varying, coef, window = borrowed((ints, fl, E, P, ED, M, base, varying, coef,
                                                                     window))
    ws, nb, F, JF, scratch, u0, t0 = borrowed((ws, nb, F, JF, scratch, u0, t0))
    out_u, out_t, out_norm, out_scale, out_acc, out_corner = borrowed((out_u, out_t, out_norm, out_scale, out_acc,
                                                                       out_corner))
    A, reference, u1, t1, u_pred, u_prev, t_prev, curve, cubic = scratch
    m = u0.shape[0]
    size = m - 1
    if ints[9] == 2:  # Newton at the fixed parameter fl[11] from u0[:size] (unscaled): (converged, iterations)
        z = u0[:size].copy()
        ok, iterations, norm = solve_fixed(z, fl[11], rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window,
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
            if not residual(z, t0[k], True, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, R,
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
        out_norm[0] = switches_of(u0[:size], fl[11], state, rhs, jac, sw, ints, fl, E, ED, M, base, varying, coef,
                                   window)
        for k in range(ints[4]):
            out_corner[k] = state[k]
        return 0, 0
    if ints[9] == 5:  # the grazing fold between the points out_u (unscaled), out_corner which exist
        out_norm[0] = grazing_value(out_u, out_corner, ints[6], ints[8], rhs, jac, sw, ints, fl, E, P, ED, M, base,
                                    varying, coef, window, ws)
        return 0, 0
    lo, hi = fl[3], fl[4]
    min_step, max_step = fl[7], fl[8]
    contact = ints[4] > 0
    max_new, count, max_points = ints[6], ints[7], ints[8]
    if ints[9]:
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
    # the residual scale of the last point (of u0 first): the corrector's, and the per-point data's of each new point
    scale = force_scale_into(u0[size] * fl[2], rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws)
    if ints[9]:  # the start point is the first row (its tangent the one just computed; no residual there)
        out_t[0] = t0
        out_norm[0] = 0.0
        out_scale[0] = scale
        out_acc[0, 0, 0] = np.nan
        out_corner[0] = False
        new = 1
    # curve: the predictor's quadratic term (_curvature), zero at the first step of a call; cubic: its cubic term b
    # (_cubic), where have_cubic; d_cubic its d_1
    curve_set = False  # the reference's curve is not None
    have_cubic = False
    d_cubic = 0.0
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
        quadratic = h * h * vector_norm(curve) <= CURVATURE_SHARE * h  # zero: the same prediction either way
        with_cubic = quadratic and have_cubic and h * h * h * vector_norm(cubic) <= CURVATURE_SHARE * h
        for i in range(m):
            u_pred[i] = u0[i] + h * t0[i]
            if quadratic:
                u_pred[i] += h * h * curve[i]
        if with_cubic:
            for i in range(m):
                u_pred[i] += h * h * cubic[i] * d_cubic / 2.0
            for i in range(m):
                u_pred[i] += h * h * h * cubic[i] / 3.0
        ok, iterations, norm, factored = _correct(u_pred, t0, u1, scale, rhs, jac, ints, fl, E, P, ED, M, base,
                                                  varying, coef, window, ws, nb, F, JF)
        if ok and _distance(u1, u_pred, 0.0, u_pred) <= h:
            if _corrected_tangent(factored, JF, t1, nb):
                cosine = 0.0
                for i in range(m):
                    cosine += t1[i] * t0[i]
                if cosine > 0.7 or h <= 4.0 * min_step:
                    accepted = True
        if not accepted and contact:
            accepted, iterations, norm = _corner(u0, t0, h, u1, t1, scale, rhs, jac, sw, ints, fl, E, P, ED, M, base,
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
            ok, its, nrm = solve_fixed(z, bound, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws)
            if ok and np.all(np.isfinite(z)):
                for i in range(size):
                    out_u[new, i] = z[i]
                out_u[new, size] = bound
                out_t[new] = t1
                out_norm[new] = nrm
                _accelerations(ws, bound, out_acc[new])
                out_scale[new] = force_scale_into(bound, rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws)
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
        _accelerations(ws, lam1, out_acc[new])
        scale = force_scale_into(lam1, rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws)
        out_scale[new] = scale
        new += 1
        d01 = 0.0 if corner else _distance(u1, u0, 0.0, u0)  # |u1 - u0|
        have_cubic = False
        if not corner and curve_set:  # _cubic(u_prev, t_prev, u0, t0, u1, t1)
            d_cubic = d01
            if d_cubic != 0.0:
                d2 = _distance(u0, u_prev, 0.0, u0)
                for i in range(m):
                    cubic[i] = ((t1[i] - t0[i]) / d_cubic - (t0[i] - t_prev[i]) / d2) / (d_cubic + d2)
                have_cubic = True
        curve_set = not corner and d01 != 0.0
        u_prev[:] = u0
        t_prev[:] = t0
        u0[:] = u1
        t0[:] = t1
        _curvature(u_prev, u0, t0, t_prev, not corner, curve)
        if iterations <= 3:
            h = min(max_step, h * 1.5)
        elif iterations >= 7:
            h = h * 0.6
