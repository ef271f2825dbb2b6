"""numba kernels of the compiled harmonic-balance path: Newton's method (:func:`rotorkit.periodic.hb.newton`).

Newton on the harmonic-balance residual at a fixed parameter (:func:`solve_fixed`) or on the continuation
corrector's bordered system (:func:`fun` mode 1), with the reference's damping, its
``lazy_jacobian`` (a trial point's Jacobian assembled from the states the last residual left in the workspace:
:func:`jacobian_at_trial`) and its convergence test on ``max |R| / scale``. Used by the continuation loop
(:mod:`rotorkit.periodic.compiled`) and the grazing-fold location (:mod:`rotorkit.periodic.compiled_folds`).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from .compiled_aft import force_scale_into, jacobian_at_states, residual
from .eigen import lu_factor, lu_solve

__all__ = ["buffers", "max_abs", "vector_norm", "bordered", "bordered_jacobian", "fun",
           "jacobian_at_trial", "newton", "solve_fixed"]


@numba.njit(cache=False)
def buffers(m, size):
    """Newton's work arrays for ``m`` unknowns (``size`` of them harmonic coefficients):
    ``(R_new, J_new, LU, piv, dz, x, trial, z, Rz, Jz, plus, column, B, b)``."""
    return (np.empty(m), np.empty((m, m)), np.empty((m, m)), np.empty(m, dtype=np.int64), np.empty(m), np.empty(m),
            np.empty(m), np.empty(size), np.empty(size), np.empty((size, size)), np.empty(size), np.empty(size),
            np.empty((size + 1, size + 1)), np.empty(size + 1))


@numba.njit(cache=False)
def max_abs(x):
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
def vector_norm(x):
    s = 0.0
    for i in range(x.shape[0]):
        s += x[i] * x[i]
    return math.sqrt(s)


@numba.njit(cache=False, inline="always")  # inlined: a call passing the work arrays costs ~0.2 us
def bordered(u, u_pred, tvec, column, scale, z_scale, Rz, Jz, want, F, JF):
    """The corrector's bordered system from the residual ``Rz`` (and Jacobian ``Jz``) at ``u``."""
    size = Rz.shape[0]
    s = 0.0
    for i in range(size + 1):
        s += tvec[i] * (u[i] - u_pred[i])
    for i in range(size):
        F[i] = Rz[i]
    F[size] = scale * s
    if want:
        bordered_jacobian(tvec, column, scale, z_scale, Jz, JF)


@numba.njit(cache=False, inline="always")  # inlined: a call passing the work arrays costs ~0.2 us
def bordered_jacobian(tvec, column, scale, z_scale, Jz, JF):
    """The corrector's Newton matrix ``[Jz z_s, dR/dlambda l_s; scale t^T]`` from the residual's Jacobian ``Jz``."""
    size = Jz.shape[0]
    for r in range(size):
        for c in range(size):
            JF[r, c] = Jz[r, c] * z_scale
        JF[r, size] = column[r]
    for c in range(size + 1):
        JF[size, c] = scale * tvec[c]


@numba.njit(cache=False, inline="always")  # inlined: a call passing the work arrays costs ~0.2 us
def fun(u, want, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac, ints, fl, E, P, ED, M, base, varying,
         coef, window, ws, nb, F, JF):
    """Newton's function: ``mode`` 0 the residual at ``lam_fixed``; 1 the corrector's bordered system."""
    if mode == 0:
        return residual(u, lam_fixed, want, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, F,
                         JF)
    z, Rz, Jz = nb[7], nb[8], nb[9]
    size = z.shape[0]
    z_scale, l_scale = fl[1], fl[2]
    for i in range(size):
        z[i] = u[i] * z_scale
    lam = u[size] * l_scale
    ok = residual(z, lam, want, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws, Rz, Jz)
    bordered(u, u_pred, tvec, column, scale, z_scale, Rz, Jz, want, F, JF)
    return ok


@numba.njit(cache=False, inline="always")  # inlined: a call passing the work arrays costs ~0.2 us
def jacobian_at_trial(mode, tvec, column, scale, jac, ints, fl, E, M, ws, nb, JF):
    """The Jacobian of Newton's function at the point of the last evaluation, from the states the workspace
    holds (:func:`~rotorkit.periodic.compiled_aft.jacobian_at_states`): the residual is not evaluated again."""
    if mode == 0:
        jacobian_at_states(jac, ints, E, M, ws, JF)
        return
    Jz = nb[9]
    jacobian_at_states(jac, ints, E, M, ws, Jz)
    bordered_jacobian(tvec, column, scale, fl[1], Jz, JF)


@numba.njit(cache=False)
def newton(u, mode, lam_fixed, u_pred, tvec, column, scale, max_iterations, evaluated, lazy, rhs, jac, ints, fl,
            E, P, ED, M, base, varying, coef, window, ws, nb, R, JF):
    """:func:`rotorkit.periodic.hb.newton` on ``u`` (in place); returns ``(converged, iterations, norm,
    factored)`` with the function in ``R`` and the Jacobian at the solution in ``JF`` (both given at ``u`` if
    ``evaluated``; with ``lazy`` (``lazy_jacobian``) the last Jacobian evaluated); ``factored``: whether
    ``nb[2]``, ``nb[3]`` hold the regular LU factors of that ``JF``."""
    m = u.shape[0]
    tol = fl[9]
    R_new, J_new, LU, piv, dz, x, trial = nb[0], nb[1], nb[2], nb[3], nb[4], nb[5], nb[6]
    if not evaluated and not fun(u, True, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac, ints, fl, E, P,
                                  ED, M, base, varying, coef, window, ws, nb, R, JF):
        return False, 0, np.inf, False
    current = True  # JF is the Jacobian at u
    factored = False
    norm = max_abs(R) / scale
    for iteration in range(max_iterations + 1):
        if norm <= tol:
            return True, iteration, norm, factored
        if iteration == max_iterations:
            break
        if not current:  # the workspace holds the states of u: the last evaluation was there
            jacobian_at_trial(mode, tvec, column, scale, jac, ints, fl, E, M, ws, nb, JF)
            current = True
        for r in range(m):
            for c in range(m):
                LU[r, c] = JF[r, c]
        factored = lu_factor(LU, piv)
        for i in range(m):
            x[i] = -R[i]
        lu_solve(LU, piv, x, dz)
        size = vector_norm(dz)
        step = 1.0
        ok = False
        while True:
            for i in range(m):
                trial[i] = u[i] + step * dz[i]
            finite = fun(trial, step == 1.0 and not lazy, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac,
                          ints, fl, E, P, ED, M, base, varying, coef, window, ws, nb, R_new, J_new)
            if finite:
                for i in range(m):
                    x[i] = -R_new[i]
                lu_solve(LU, piv, x, x)
                ok = vector_norm(x) <= (1.0 - step / 4.0) * size
            else:
                ok = False
            if ok or step < 1.0 / 128.0:
                break
            step *= 0.5
        for i in range(m):
            u[i] += step * dz[i]
        if ok and lazy:
            for r in range(m):
                R[r] = R_new[r]
            current = False
        elif ok and step == 1.0:
            for r in range(m):
                R[r] = R_new[r]
                for c in range(m):
                    JF[r, c] = J_new[r, c]
            factored = False
        else:
            factored = False
            if not fun(u, True, mode, lam_fixed, u_pred, tvec, column, scale, rhs, jac, ints, fl, E, P, ED, M,
                        base, varying, coef, window, ws, nb, R, JF):
                return False, iteration + 1, np.inf, False
            current = True
        norm = max_abs(R) / scale
    return False, max_iterations, norm, False


@numba.njit(cache=False)
def solve_fixed(z, lam, rhs, jac, ints, fl, E, P, ED, M, base, varying, coef, window, ws):
    """Newton at the fixed parameter ``lam`` from ``z`` (in place, unscaled): ``(converged, iterations, norm)``."""
    size = z.shape[0]
    scale = force_scale_into(lam, rhs, jac, ints, fl, E, P, M, base, varying, coef, window, ws)
    nb = buffers(size, size)
    R = np.empty(size)
    JF = np.empty((size, size))
    return newton(z, 0, lam, z, z, z, scale, ints[5], False, False, rhs, jac, ints, fl, E, P, ED, M, base, varying,
                   coef, window, ws, nb, R, JF)[:3]
