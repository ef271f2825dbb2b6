"""The numba kernels of the compiled Runge-Kutta loop (rotorkit.engines.rk_numba): stages, error norms, the
initial step, dense output and the step-size factor.

Each mirrors its piece of scipy's ``rk.py``/``common.py`` and of the C loop
(``rk_loop.c``); the loop compiles them into itself (``cache=False`` here: they
are cached as part of the loop, whose cache name hashes this file too).
``error_model="numpy"`` gives IEEE semantics (inf/nan instead of
ZeroDivisionError) and no division checks.
"""

from __future__ import annotations

import math

from numba import njit

from .rk_common import DIVERGED, DOP853_N_STAGES, DOP853_N_STAGES_EXTENDED, MAX_FACTOR, MIN_FACTOR, SAFETY

__all__ = ["all_finite", "all_finite_and_bounded", "weighted_sum", "rms", "error_scale", "select_initial_step", "rk_step", "rk45_error_norm", "dop853_error_norm", "rk45_dense_prepare", "rk45_dense_eval", "dop853_dense_prepare", "dop853_dense_eval", "copy_column", "step_factor"]

_JIT = dict(cache=False, nogil=True, error_model="numpy")


@njit(**_JIT)
def all_finite(x):
    """Return True when every entry of `x` is finite."""
    for v in x:
        if not math.isfinite(v):
            return False
    return True


@njit(**_JIT)
def all_finite_and_bounded(x):
    """Return True when every entry of `x` is finite and below DIVERGED in magnitude."""
    for v in x:
        if not math.isfinite(v) or abs(v) > DIVERGED:
            return False
    return True


@njit(**_JIT)
def weighted_sum(rows, weights, n_terms, out):
    """Write ``sum(weights[j] * rows[j] for j < n_terms)`` into `out`.

    Zero weights are skipped (this does not change the rounded result).
    """
    n = out.size
    for i in range(n):
        out[i] = 0.0
    for j in range(n_terms):
        w = weights[j]
        if w != 0.0:
            for i in range(n):
                out[i] += rows[j, i] * w


@njit(**_JIT)
def rms(x, scale):
    """RMS norm of ``x / scale`` as scipy's ``norm`` computes it."""
    acc = 0.0
    for i in range(x.size):
        v = x[i] / scale[i]
        acc += v * v
    return math.sqrt(acc) / x.size ** 0.5


@njit(**_JIT)
def error_scale(y, y_new, rtol, atol, out):
    """``atol + rtol * max(|y|, |y_new|)`` into `out`."""
    for i in range(y.size):
        out[i] = atol[i] + max(abs(y[i]), abs(y_new[i])) * rtol


@njit(**_JIT)
def select_initial_step(core, t0, y0, f0, p, t1, max_step, order, rtol,
                         atol, y1, f1, scale):
    """scipy's ``select_initial_step`` (forward direction, one evaluation).

    Returns
    -------
    h_abs : float
        Suggested first step.
    """
    interval_length = abs(t1 - t0)
    if interval_length == 0.0:
        return 0.0
    n = y0.size
    for i in range(n):
        scale[i] = atol[i] + abs(y0[i]) * rtol
    d0 = rms(y0, scale)
    d1 = rms(f0, scale)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, interval_length)
    for i in range(n):
        y1[i] = y0[i] + h0 * f0[i]
    core(t0 + h0, y1, p, f1)
    for i in range(n):
        y1[i] = f1[i] - f0[i]
    d2 = rms(y1, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        # Python's max/min semantics: a NaN candidate is ignored.
        d_max = d2 if d2 > d1 else d1
        h1 = (0.01 / d_max) ** (1.0 / (order + 1))
    h = 100.0 * h0
    for candidate in (h1, interval_length, max_step):
        if candidate < h:
            h = candidate
    return h


@njit(**_JIT)
def rk_step(core, t, y, h, p, a, b, c, n_stages, k, y_new, y_stage, work):
    """One explicit RK step; ``k[0]`` must hold ``f(t, y)`` on entry.

    Fills ``k[1:n_stages]`` with the stages, `y_new` with the propagated
    state and ``k[n_stages]`` with ``f(t + h, y_new)``.

    Returns
    -------
    n_evals : int
        Number of core evaluations made.
    ok : bool
        False when a stage, the new state or its derivative is not finite
        (the step then stops early).
    """
    n = y.size
    for s in range(1, n_stages):
        weighted_sum(k, a[s], s, work)
        for i in range(n):
            y_stage[i] = y[i] + work[i] * h
        core(t + c[s] * h, y_stage, p, k[s])
        if not all_finite(k[s]):
            return s, False
    weighted_sum(k, b, n_stages, work)
    for i in range(n):
        y_new[i] = y[i] + h * work[i]
    if not all_finite_and_bounded(y_new):
        return n_stages - 1, False
    core(t + h, y_new, p, k[n_stages])
    if not all_finite(k[n_stages]):
        return n_stages, False
    return n_stages, True


@njit(**_JIT)
def rk45_error_norm(k, e, h, scale, work):
    """scipy's RK45 error norm ``norm(h * K.T @ E / scale)``."""
    weighted_sum(k, e, e.size, work)
    for i in range(work.size):
        work[i] *= h
    return rms(work, scale)


@njit(**_JIT)
def dop853_error_norm(k, e5, e3, h, scale, work5, work3):
    """scipy's DOP853 error norm blending the 5th- and 3rd-order estimates."""
    weighted_sum(k, e5, e5.size, work5)
    weighted_sum(k, e3, e3.size, work3)
    n = scale.size
    err5_sq = 0.0
    err3_sq = 0.0
    for i in range(n):
        v5 = work5[i] / scale[i]
        v3 = work3[i] / scale[i]
        err5_sq += v5 * v5
        err3_sq += v3 * v3
    if err5_sq == 0.0 and err3_sq == 0.0:
        return 0.0
    denom = err5_sq + 0.01 * err3_sq
    return abs(h) * err5_sq / math.sqrt(denom * n)


@njit(**_JIT)
def rk45_dense_prepare(k, pt, q):
    """Dense-output weights ``q[j] = (K.T @ P)[:, j]`` of the last step."""
    for j in range(pt.shape[0]):
        weighted_sum(k, pt[j], pt.shape[1], q[j])


@njit(**_JIT)
def rk45_dense_eval(q, y_old, t_old, h, t, out, col):
    """Quartic interpolant at `t` written into ``out[:, col]``."""
    x = (t - t_old) / h
    p1 = x
    p2 = p1 * x
    p3 = p2 * x
    p4 = p3 * x
    for i in range(y_old.size):
        acc = q[0, i] * p1 + q[1, i] * p2 + q[2, i] * p3 + q[3, i] * p4
        out[i, col] = h * acc + y_old[i]


@njit(**_JIT)
def dop853_dense_prepare(core, t_old, h, y_old, y_new, p, a, c, d, k, f,
                          y_stage, work):
    """Three extra stages and the 7 interpolant rows `f` of the last step.

    Returns
    -------
    n_evals : int
        Number of core evaluations made.
    ok : bool
        False when an extra stage is not finite.
    """
    n = y_old.size
    n_base = DOP853_N_STAGES + 1
    for s in range(n_base, DOP853_N_STAGES_EXTENDED):
        weighted_sum(k, a[s], s, work)
        for i in range(n):
            y_stage[i] = y_old[i] + work[i] * h
        core(t_old + c[s] * h, y_stage, p, k[s])
        if not all_finite(k[s]):
            return s - n_base + 1, False
    f_old = k[0]
    f_new = k[DOP853_N_STAGES]
    for i in range(n):
        delta = y_new[i] - y_old[i]
        f[0, i] = delta
        f[1, i] = h * f_old[i] - delta
        f[2, i] = 2.0 * delta - h * (f_new[i] + f_old[i])
    for r in range(d.shape[0]):
        weighted_sum(k, d[r], d.shape[1], work)
        for i in range(n):
            f[3 + r, i] = h * work[i]
    return DOP853_N_STAGES_EXTENDED - n_base, True


@njit(**_JIT)
def dop853_dense_eval(f, y_old, t_old, h, t, out, col):
    """7th-order interpolant at `t` written into ``out[:, col]``."""
    x = (t - t_old) / h
    n_rows = f.shape[0]
    for i in range(y_old.size):
        acc = 0.0
        for r in range(n_rows):
            acc += f[n_rows - 1 - r, i]
            if r % 2 == 0:
                acc *= x
            else:
                acc *= 1.0 - x
        out[i, col] = acc + y_old[i]


@njit(**_JIT)
def copy_column(src, out, col):
    """``out[:, col] = src``."""
    for i in range(src.size):
        out[i, col] = src[i]


@njit(**_JIT)
def step_factor(error_norm, error_exponent, rejected_before):
    """scipy's step-size factor for an error norm (accepted or not)."""
    if error_norm < 1.0:
        if error_norm == 0.0:
            factor = MAX_FACTOR
        else:
            factor = SAFETY * error_norm ** error_exponent
            if not factor < MAX_FACTOR:
                factor = MAX_FACTOR
        if rejected_before and factor > 1.0:
            factor = 1.0
        return factor
    factor = SAFETY * error_norm ** error_exponent
    if not factor > MIN_FACTOR:  # also catches NaN, like Python's max()
        factor = MIN_FACTOR
    return factor
