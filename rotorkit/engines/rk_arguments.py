"""The contract of the compiled loops' ``integrate``: its argument checks and the runner around a loop.

Both loops (:mod:`rotorkit.engines.rk_numba` and :mod:`rotorkit.engines.rk_c`) check their arguments here, with
the same messages, and run through :func:`run_loop`. numpy only.
"""

from __future__ import annotations

import math
import warnings
from typing import NamedTuple

import numpy as np

from rotorkit.errors import ParameterError

from .rk_common import EPS, STATUS_PAUSED, RKSolution, status_message

__all__ = ["as_float", "as_vector", "as_state", "as_t_eval", "as_rtol", "as_atol", "as_first_step", "as_max_step",
           "as_max_steps", "Arguments", "check_arguments", "run_loop"]


def as_float(value, name):
    """A finite float, else ParameterError naming `name`."""
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}={value!r} must be a real number.") from None
    if not math.isfinite(out):
        raise ParameterError(f"{name}={value!r} must be finite.")
    return out


def as_vector(value, name, *, allow_empty):
    """A fresh C-contiguous float64 1-D copy of `value`."""
    try:
        out = np.array(value, dtype=np.float64, ndmin=1)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{name} must be a 1-D array of real numbers; got {value!r}.") from None
    if out.ndim != 1:
        raise ParameterError(
            f"{name} must be 1-D; got an array of shape {out.shape}.")
    if not allow_empty and out.size == 0:
        raise ParameterError(f"{name} must not be empty.")
    return np.ascontiguousarray(out)


def as_state(y0):
    """Validated initial state."""
    y0 = as_vector(y0, "y0", allow_empty=False)
    if not np.all(np.isfinite(y0)):
        raise ParameterError(f"y0 must be finite; got {y0!r}.")
    return y0


def as_t_eval(t_eval, t0, t1):
    """Validated output times (sorted, inside [t0, t1])."""
    t_eval = as_vector(t_eval, "t_eval", allow_empty=True)
    if t_eval.size and (np.any(np.isnan(t_eval)) or t_eval[0] < t0
                        or t_eval[-1] > t1):
        raise ParameterError(
            f"t_eval values must lie inside [t0, t1] = [{t0!r}, {t1!r}]; got "
            f"range [{t_eval.min()!r}, {t_eval.max()!r}].")
    if np.any(np.diff(t_eval) < 0):
        raise ParameterError("t_eval must be sorted in increasing order.")
    return t_eval


def as_rtol(rtol, stacklevel=3):
    """Validated scalar rtol, raised to 100*eps like scipy (with a warning pointing `stacklevel` frames up)."""
    rtol = as_float(rtol, "rtol")
    if rtol < 0:
        raise ParameterError(f"rtol={rtol!r} must be non-negative.")
    if rtol < 100 * EPS:
        warnings.warn(f"rtol={rtol!r} is too small; using rtol={100 * EPS!r}.",
                      stacklevel=stacklevel)
        rtol = 100 * EPS
    return rtol


def as_atol(atol, n):
    """Validated atol as a length-`n` vector."""
    try:
        arr = np.array(atol, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(
            f"atol must be a real scalar or a 1-D array; got {atol!r}.") from None
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    elif arr.shape != (n,):
        raise ParameterError(
            f"atol must be a scalar or have shape ({n},) like y0; got shape "
            f"{arr.shape}.")
    if not np.all(np.isfinite(arr)) or np.any(arr < 0):
        raise ParameterError(f"atol must be finite and non-negative; got {atol!r}.")
    return np.ascontiguousarray(arr)


def as_first_step(first_step, t0, t1):
    """First step as a float; 0.0 means "select automatically"."""
    if first_step is None:
        return 0.0
    first_step = as_float(first_step, "first_step")
    if first_step <= 0:
        raise ParameterError(f"first_step={first_step!r} must be positive.")
    if first_step > t1 - t0:
        raise ParameterError(
            f"first_step={first_step!r} exceeds the interval length "
            f"t1 - t0 = {t1 - t0!r}.")
    return first_step


def as_max_step(max_step):
    """Validated max_step (positive, may be inf)."""
    try:
        max_step = float(max_step)
    except (TypeError, ValueError):
        raise ParameterError(f"max_step={max_step!r} must be a real number.") from None
    if not max_step > 0:
        raise ParameterError(f"max_step={max_step!r} must be positive (inf allowed).")
    return max_step


def as_max_steps(max_steps, name="max_steps"):
    """Validated positive integer (max_steps, pause_after, sample_capacity), else ParameterError naming `name`."""
    if isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer)) or max_steps <= 0:
        raise ParameterError(f"{name}={max_steps!r} must be a positive integer.")
    return int(max_steps)



class Arguments(NamedTuple):
    """The checked arguments of ``integrate`` (see `check_arguments`)."""

    t0: float
    t1: float
    y0: np.ndarray
    p: np.ndarray
    t_eval: np.ndarray
    rtol: float
    atol: np.ndarray
    first_step: float
    max_step: float
    max_steps: int
    pause_after: int
    columns: int


def check_arguments(t0, t1, y0, p, t_eval, rtol, atol, first_step, max_step, max_steps, pause_after,
                    sample_capacity):
    """``integrate``'s arguments checked and converted (ParameterError naming the bad one).

    Called directly from an ``integrate`` (the rtol warning points at its
    caller), after it checked the method and the core.
    """
    t0 = as_float(t0, "t0")
    t1 = as_float(t1, "t1")
    if t1 < t0:
        raise ParameterError(
            f"t1={t1!r} must not be smaller than t0={t0!r} (only forward "
            f"integration is supported).")
    y0 = as_state(y0)
    p = as_vector([] if p is None else p, "p", allow_empty=True)
    t_eval = as_t_eval(t_eval, t0, t1)
    rtol = as_rtol(rtol, stacklevel=4)
    atol = as_atol(atol, y0.size)
    first_step = as_first_step(first_step, t0, t1)
    max_step = as_max_step(max_step)
    max_steps = as_max_steps(max_steps)
    pause_after = 0 if pause_after is None else as_max_steps(pause_after, "pause_after")
    columns = t_eval.size
    if pause_after and sample_capacity is not None:
        columns = min(columns, as_max_steps(sample_capacity, "sample_capacity"))
    return Arguments(t0, t1, y0, p, t_eval, rtol, atol, first_step, max_step, max_steps, pause_after, columns)


def run_loop(loop, args):
    """Run a compiled loop on checked arguments, enlarging a sample buffer its first step overflows.

    Parameters
    ----------
    loop : callable
        ``loop(first_step, samples, y_reached) -> (status, n_samples_done,
        t_reached, nfev, n_accepted, n_rejected, h_next)``, the other
        arguments bound; it writes the samples and the last accepted state.
    args : Arguments

    Returns
    -------
    RKSolution
    """
    columns, first_step = args.columns, args.first_step
    n_eval = args.t_eval.size
    y_reached = np.empty_like(args.y0)
    spent = 0  # core evaluations and rejected attempts of starts whose first step did not fit the buffer
    rejected_before = 0
    while True:
        samples = np.full((args.y0.size, columns), np.nan)
        status, n_done, t_reached, nfev, n_acc, n_rej, h_next = loop(first_step, samples, y_reached)
        if not (status == STATUS_PAUSED and n_acc == 0 and columns < n_eval):
            break
        # the first step's samples alone overflow the buffer: redo it with a larger one
        columns, first_step = min(n_eval, 2 * columns), h_next
        spent, rejected_before = spent + nfev, rejected_before + n_rej
    nfev, n_rej = nfev + spent, n_rej + rejected_before
    return RKSolution(
        t=args.t_eval[:samples.shape[1]], y=samples, n_samples_done=int(n_done), status=int(status),
        t_reached=float(t_reached), y_reached=y_reached, nfev=int(nfev),
        n_accepted=int(n_acc), n_rejected=int(n_rej),
        message=status_message(status, t_reached, args.max_steps), h_next=float(h_next))
