"""Compiled adaptive explicit Runge-Kutta integrator (numba back end).

The whole adaptive loop (stages, error control, step-size selection and
dense output at the requested times) runs in one numba-compiled function, so
the only per-step cost is the arithmetic and the calls of the compiled
right-hand side.

Right-hand side contract
------------------------
The right-hand side ("core") is a numba ``@njit`` function::

    @numba.njit
    def core(t, y, p, dydt):
        dydt[0] = y[1]
        dydt[1] = -p[0] * y[0]

``t`` is a float, ``y`` the state (read only by convention), ``p`` the
parameter vector and ``dydt`` the output array; all arrays are C-contiguous
``float64`` vectors (see `CORE_SIGNATURE`).  The core must write every entry
of ``dydt`` and must not keep references to the arrays.

Methods and error control
-------------------------
``"RK45"`` (Dormand-Prince 5(4), quartic dense output) and ``"DOP853"``
(Hairer's 8(5,3) with the 7th-order dense output) use the coefficients, the
error norms, the initial-step heuristic and the step-size controller of
:func:`scipy.integrate.solve_ivp` (scipy's ``rk.py``, ``common.py``,
``dop853_coefficients.py``), so step sequences and ``nfev`` match scipy up to
floating-point summation order.  One deliberate difference: a sample at ``t0``
is the initial state itself, so DOP853 skips the three dense-output stages
scipy spends on it (``nfev`` 3 lower when ``t_eval`` starts at ``t0`` and the
first step holds no other sample).  Samples that fall exactly on a step end
are that step's state, not an interpolated value.

Non-finite values
-----------------
A stage that yields a non-finite state or derivative is treated as a failed
step: it is retried with the step divided by 5 (the controller's minimum
factor, which is also what scipy does with a NaN error estimate).  The run
stops with status ``-2`` when the step can no longer shrink, so ``t_reached``
converges onto the time at which the core stops being finite.  A non-finite
initial derivative stops the run immediately.

Compilation and caching
-----------------------
The core is passed to the compiled loop as a first-class function
(``numba.types.FunctionType(CORE_SIGNATURE)``), not as a dispatcher type.  The
loop is therefore compiled once for all cores and both methods, and it can be
cached on disk: a new core only costs its own compilation. The disk cache is
kept in rotorkit's private cache folder, verified and signed like a model's
(:func:`rotorkit.codegen.cache.jit_shared`), never beside the package.
Passing the dispatcher itself (the alternative pattern) would make every core
a distinct type, recompile the loop for each model and defeat on-disk caching
because dispatcher types do not survive the process.  The loop is compiled (or
loaded from the cache) on the first call of `integrate`, not at import
(seconds cold, a fraction of that from the cache; ``bench/bench_core.py``).

Pieces
------
With ``pause_after`` the loop returns between two steps (status -4) with the
step size its controller proposes next (``h_next``); a caller continuing from
there with ``first_step=h_next`` takes exactly the steps of an uninterrupted
run. :func:`rotorkit.simulate` runs every compiled segment this way, in
pieces of about a quarter second of wall time, to look at Ctrl-C, the wall
time limit and the displacement bound between them.

The price of the function-pointer call is small (0-10 % per step against a
loop specialised on one core), plus ~30 us per `integrate` call for numba to
look up the core's address.  A core decorated with an explicit signature must
use exactly `CORE_SIGNATURE`.  Exceptions raised inside the core propagate to
the caller.  The loop releases the GIL (``nogil=True``), so independent runs
can execute in threads.
"""

from __future__ import annotations

import functools

import numba
import numpy as np
from numba import types
from numba.core.dispatcher import Dispatcher

# Statuses, controller constants, scipy's coefficients, the result type and the
# argument checks are shared with the C loop and re-exported from here.
from .rk_common import (  # noqa: F401  (re-exported; globals of the compiled loop)
    DIVERGED,
    DOP853_A,
    DOP853_B,
    DOP853_C,
    DOP853_D,
    DOP853_E3,
    DOP853_E5,
    DOP853_ERROR_ORDER,
    DOP853_INTERPOLATOR_POWER,
    DOP853_N_STAGES,
    DOP853_N_STAGES_EXTENDED,
    MAX_FACTOR,
    METHODS,
    MIN_FACTOR,
    RK45_A_SQ,
    RK45_B,
    RK45_C_EXT,
    RK45_E,
    RK45_ERROR_ORDER,
    RK45_ID,
    RK45_N_STAGES,
    RK45_PT,
    SAFETY,
    STATUS_MAX_STEPS,
    STATUS_NON_FINITE,
    STATUS_NO_MEMORY,
    STATUS_PAUSED,
    STATUS_RUNNING,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
    CoreSignatureError,
    RKSolution,
    loop_method_id,
)
from .rk_arguments import check_arguments, run_loop

from .rk_kernels import (
    all_finite,
    copy_column,
    dop853_dense_eval,
    dop853_dense_prepare,
    dop853_error_norm,
    error_scale,
    rk45_dense_eval,
    rk45_dense_prepare,
    rk45_error_norm,
    rk_step,
    select_initial_step,
    step_factor,
)

__all__ = [
    "CORE_SIGNATURE",
    "METHODS",
    "STATUS_SUCCESS",
    "STATUS_STEP_TOO_SMALL",
    "STATUS_NON_FINITE",
    "STATUS_MAX_STEPS",
    "STATUS_PAUSED",
    "DIVERGED",
    "CoreSignatureError",
    "RKSolution",
    "compile_loop_in_background",
    "integrate",
]


# ---------------------------------------------------------------------------
# Numba types
# ---------------------------------------------------------------------------

_VEC = types.float64[::1]
_MAT = types.float64[:, ::1]

#: Numba signature every core must accept: ``core(t, y, p, dydt) -> None``.
CORE_SIGNATURE = types.void(types.float64, _VEC, _VEC, _VEC)

_CORE_TYPE = types.FunctionType(CORE_SIGNATURE)
_LOOP_RESULT = types.Tuple((types.int64, types.int64, types.float64,
                            types.int64, types.int64, types.int64, types.float64))
_LOOP_SIGNATURE = _LOOP_RESULT(
    _CORE_TYPE,      # core
    types.int64,     # method id
    types.float64,   # t0
    types.float64,   # t1
    _VEC,            # y0
    _VEC,            # p
    _VEC,            # t_eval
    types.float64,   # rtol
    _VEC,            # atol (length n)
    types.float64,   # first step (<= 0: automatic)
    types.float64,   # max step
    types.int64,     # max steps
    types.int64,     # pause after this many accepted steps (0: never)
    _MAT,            # samples out (n, len(t_eval))
    _VEC,            # last accepted state out
)


def _rk_loop(core, method, t0, t1, y0, p, t_eval, rtol, atol, first_step,
             max_step, max_steps, pause_after, samples, y_out):
    """Adaptive loop; compiled lazily by `_compiled_loop` (see there).

    Mirrors scipy's ``solve_ivp`` driver and ``RungeKutta._step_impl``.  The
    step-attempt and sampling logic stays inline on purpose: moving it into
    helper functions measured 5-15 % slower per step (numba passes every
    array as a multi-field struct across calls LLVM does not inline).

    Returns
    -------
    tuple
        ``(status, n_samples_done, t_reached, nfev, n_accepted,
        n_rejected, h_next)``; the samples and the last accepted state are
        written into `samples` and `y_out`. ``h_next`` is the step size the
        controller proposes next: a paused run (``pause_after``) continued
        from ``t_reached`` with ``first_step=h_next`` takes the same steps
        as one that was never paused.
    """
    n = y0.size
    n_eval = t_eval.size
    if method == RK45_ID:
        a = RK45_A_SQ
        b = RK45_B
        c = RK45_C_EXT
        n_stages = RK45_N_STAGES
        n_rows = RK45_N_STAGES + 1
        error_order = RK45_ERROR_ORDER
    else:
        a = DOP853_A
        b = DOP853_B
        c = DOP853_C
        n_stages = DOP853_N_STAGES
        n_rows = DOP853_N_STAGES_EXTENDED
        error_order = DOP853_ERROR_ORDER
    error_exponent = -1.0 / (error_order + 1)

    k = np.empty((n_rows, n))  # stages; row n_stages is f(t_new, y_new)
    dense = np.empty((DOP853_INTERPOLATOR_POWER, n))
    y = y0.copy()
    y_new = np.empty(n)
    f = np.empty(n)
    y_stage = np.empty(n)
    work = np.empty(n)
    work2 = np.empty(n)
    scale = np.empty(n)

    # Samples at t0 are the initial state itself.
    capacity = samples.shape[1]  # == n_eval unless pausing: then a step whose samples overflow it is redone later
    i_eval = 0
    while i_eval < n_eval and i_eval < capacity and t_eval[i_eval] <= t0:
        copy_column(y0, samples, i_eval)
        i_eval += 1

    t = t0
    n_accepted = 0
    n_rejected = 0
    status = STATUS_RUNNING
    core(t, y, p, f)
    nfev = 1
    if not all_finite(f):
        status = STATUS_NON_FINITE
    h_abs = first_step
    if status == STATUS_RUNNING and first_step <= 0.0:
        h_abs = select_initial_step(core, t0, y0, f, p, t1, max_step,
                                     error_order, rtol, atol, y_stage, work,
                                     scale)
        nfev += 1

    while status == STATUS_RUNNING:
        if t >= t1:
            status = STATUS_SUCCESS
            break
        if pause_after > 0 and n_accepted >= pause_after:
            status = STATUS_PAUSED  # between two steps: nothing of the controller's state is lost
            break
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        # the next step ends at most at t + its first attempt (clipped to [min_step, max_step]; it only shrinks)
        if capacity < n_eval and t_eval[capacity] <= t + max(min(h_abs, max_step), min_step):
            status = STATUS_PAUSED  # it might sample past the buffer
            break

        # --- one accepted step (scipy's _step_impl) ---------------------
        if h_abs > max_step:
            h_abs = max_step
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        non_finite = False
        t_new = t
        h = 0.0
        while True:
            if not h_abs >= min_step:  # also stops on a NaN step size
                if non_finite:
                    status = STATUS_NON_FINITE
                else:
                    status = STATUS_STEP_TOO_SMALL
                break
            if n_accepted + n_rejected >= max_steps:
                status = STATUS_MAX_STEPS
                break
            t_new = t + h_abs
            if t_new > t1:
                t_new = t1
            h = t_new - t
            h_abs = abs(h)

            for i in range(n):
                k[0, i] = f[i]
            n_evals, ok = rk_step(core, t, y, h, p, a, b, c, n_stages, k,
                                   y_new, y_stage, work)
            nfev += n_evals
            if not ok:  # non-finite stage: retry with a smaller step
                non_finite = True
                rejected = True
                n_rejected += 1
                h_abs *= MIN_FACTOR
                continue
            non_finite = False

            error_scale(y, y_new, rtol, atol, scale)
            if method == RK45_ID:
                error_norm = rk45_error_norm(k, RK45_E, h, scale, work)
            else:
                error_norm = dop853_error_norm(k, DOP853_E5, DOP853_E3, h,
                                                scale, work, work2)
            h_abs *= step_factor(error_norm, error_exponent, rejected)
            if error_norm < 1.0:
                break
            rejected = True
            n_rejected += 1
        if status != STATUS_RUNNING:
            break
        n_accepted += 1

        # --- samples inside (t, t_new] from the step's dense output -----
        if i_eval < n_eval and t_eval[i_eval] <= t_new:
            if method == RK45_ID:
                rk45_dense_prepare(k, RK45_PT, dense)
            else:
                n_evals, ok = dop853_dense_prepare(
                    core, t, h, y, y_new, p, a, c, DOP853_D, k, dense,
                    y_stage, work)
                nfev += n_evals
                if not ok:  # keep t, y at the last step fully sampled
                    status = STATUS_NON_FINITE
                    break
            while i_eval < n_eval and t_eval[i_eval] <= t_new:
                t_sample = t_eval[i_eval]
                if t_sample == t_new:
                    copy_column(y_new, samples, i_eval)
                elif method == RK45_ID:
                    rk45_dense_eval(dense, y, t, h, t_sample, samples, i_eval)
                else:
                    dop853_dense_eval(dense, y, t, h, t_sample, samples,
                                       i_eval)
                i_eval += 1

        t = t_new
        y, y_new = y_new, y
        for i in range(n):
            f[i] = k[n_stages, i]

    for i in range(n):
        y_out[i] = y[i]
    return status, i_eval, t, nfev, n_accepted, n_rejected, h_abs


@functools.lru_cache(maxsize=None)
def cache_name():
    """The loop's folder in ``<cache>/shared``: ``rk_loop-<digest of rk_numba.py, rk_common.py, rk_kernels.py>``.

    numba's cache index only checks this file's time stamp, but the loop also
    freezes rk_kernels' functions and rk_common's constants and tables (statuses, controller factors,
    scipy's coefficients) into its machine code: with both files' contents in
    the name, changing either compiles the loop again instead of loading a
    stale one.
    """
    import hashlib
    from pathlib import Path

    from . import rk_common, rk_kernels

    digest = hashlib.sha256()
    for path in (__file__, rk_common.__file__, rk_kernels.__file__):
        digest.update(Path(path).read_bytes())
    return f"rk_loop-{digest.hexdigest()[:12]}"


def _build_loop():
    """Compile (or load from numba's on-disk cache) the adaptive loop; the caller holds the cache's lock."""
    from ..codegen.cache import jit_shared

    return jit_shared(_rk_loop, cache_name(), _LOOP_SIGNATURE, nogil=True, error_model="numpy")


@functools.lru_cache(maxsize=None)
def _compiled_loop():
    """Compile (or load from numba's on-disk cache) the adaptive loop.

    Waits, holding the cache's lock, for another process compiling it into
    the same cache (`compile_loop_in_background`), then loads its result.

    Returns
    -------
    numba.core.dispatcher.Dispatcher
        The loop, compiled for `_LOOP_SIGNATURE` only.
    """
    from ..codegen.cache import shared_lock

    with shared_lock("rk_loop") as lock:
        if lock is not None:
            _reap_background()
        return _build_loop()


def _reap_background():
    """Collect the processes `compile_loop_in_background` started: holding the lock, they have finished or are exiting."""
    import subprocess

    for process in _BACKGROUND:
        try:
            process.wait(timeout=5)
        except subprocess.TimeoutExpired:  # pragma: no cover - it released the lock, so it is on its way out
            pass


#: set ROTORKIT_BACKGROUND_COMPILE=0 to never compile the loop in another process
BACKGROUND_VARIABLE = "ROTORKIT_BACKGROUND_COMPILE"
_BACKGROUND = []  # processes this one started (kept so they are not reaped as garbage while running)


def compile_loop_in_background():
    """Start compiling the integration loop into rotorkit's cache in another process, if it needs compiling.

    The loop takes seconds to compile the first time (it is cached on disk
    afterwards). A caller that knows it will integrate soon, but has other
    work first (``rotorkit run`` derives and compiles its model), starts it
    here so the two compilations run on two cores at once. The other process
    holds the cache's lock from before it starts until it has written and
    signed the cache; the first `integrate` of this process waits for that
    lock and loads the result (if the other process failed, it compiles the
    loop itself, as without this call). The other process runs in its own
    session (Ctrl-C here does not interrupt it half-way through writing the
    cache) and finishes even if this one ends first.

    Nothing is started when the loop is already loaded in this process or
    compiled in the cache, when another process holds the lock, on a single
    core, or with ``ROTORKIT_BACKGROUND_COMPILE=0``.

    Returns
    -------
    subprocess.Popen or None
        The process started, if any.
    """
    import os
    import subprocess
    import sys
    from pathlib import Path

    from ..codegen import cache

    if os.environ.get(BACKGROUND_VARIABLE, "").strip() == "0" or _compiled_loop.cache_info().currsize:
        return None
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    if cores < 2 or cache.shared_is_current(cache_name(), __file__):
        return None
    root = str(Path(__file__).resolve().parents[2])  # the folder holding the rotorkit package
    code = f"import sys; sys.path.insert(0, {root!r}); from rotorkit.engines import rk_numba; rk_numba._build_loop()"
    with cache.shared_lock("rk_loop", blocking=False) as lock:
        if lock is None:
            return None  # locking unavailable, or another process is compiling it right now
        try:
            process = subprocess.Popen(
                [sys.executable, "-c", code], stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
                stderr=subprocess.DEVNULL, pass_fds=(lock.fileno(),), start_new_session=True,
                env=dict(os.environ, ROTORKIT_CACHE_DIR=str(cache.cache_dir())))
        except OSError:
            return None
    # the child holds the lock through the inherited descriptor until it exits
    _BACKGROUND.append(process)
    return process


# ---------------------------------------------------------------------------
# Python front end
# ---------------------------------------------------------------------------


def _check_core(core):
    """Reject cores that are not numba dispatchers."""
    if not isinstance(core, Dispatcher):
        raise CoreSignatureError(
            f"core={core!r} must be a numba @njit function "
            f"core(t, y, p, dydt) -> None; got {type(core).__name__}.")


def _raise_if_bad_signature(core):
    """Raise CoreSignatureError when `core` cannot compile for CORE_SIGNATURE.

    Only called after the loop failed, so the happy path pays nothing.
    """
    try:
        core.get_compile_result(CORE_SIGNATURE)
    except (numba.core.errors.NumbaError, TypeError) as exc:
        raise CoreSignatureError(
            f"core={core!r} cannot be compiled as core(t: float64, "
            f"y: float64[::1], p: float64[::1], dydt: float64[::1]) -> None: "
            f"{exc}") from exc


def integrate(core, t0, t1, y0, p, t_eval, *, method="DOP853", rtol=1e-6,
              atol=1e-9, first_step=None, max_step=np.inf,
              max_steps=50_000_000, pause_after=None, sample_capacity=None):
    """Integrate ``dy/dt = core(t, y, p)`` from `t0` to `t1` in compiled code.

    Parameters
    ----------
    core : numba dispatcher
        ``@njit`` function ``core(t, y, p, dydt) -> None`` writing the
        derivative into ``dydt`` (see `CORE_SIGNATURE`).
    t0, t1 : float
        Start and end time, ``t1 >= t0``.  The last step is clipped to land
        exactly on `t1`.
    y0 : array_like, shape (n,)
        Initial state (finite, non-empty).
    p : array_like, shape (n_p,) or None
        Parameter vector passed unchanged to `core` (``None``: empty).
    t_eval : array_like, shape (m,)
        Sorted output times inside ``[t0, t1]`` (endpoints allowed, may be
        empty).  Samples come from the dense output of each accepted step;
        they never shorten steps.  A sample at a step end is the step's state.
    method : {"DOP853", "RK45"}, optional
        Runge-Kutta pair, with scipy's coefficients and dense output.
    rtol : float, optional
        Relative tolerance (raised to ``100 * eps`` with a warning like scipy).
    atol : float or array_like, shape (n,), optional
        Absolute tolerance, scalar or per state.  With ``atol = 0`` a state
        component that is (or passes through) zero makes the error norm
        undefined and the run stops with status -1.
    first_step : float, optional
        Initial step; by default chosen with scipy's heuristic.
    max_step : float, optional
        Largest allowed step (default unbounded).
    max_steps : int, optional
        Largest number of step attempts (accepted plus rejected).
    pause_after : int, optional
        Return (status -4) after this many accepted steps, between two
        steps. Continuing from ``t_reached``/``y_reached`` with
        ``first_step=h_next`` takes the same steps as an unpaused run, so a
        caller can look at the clock, its samples or Ctrl-C between pieces
        without changing the result.
    sample_capacity : int, optional
        With ``pause_after``: allocate samples for at most this many of the
        ``t_eval`` (a long run's later samples are taken by later pieces).
        The run also pauses, between two steps, when the next step might
        sample past the buffer; a buffer too small for the first step alone
        is enlarged here.

    Returns
    -------
    RKSolution
        Samples, final state, status, counters and message.  Failures are
        reported through ``status``/``message``, never raised.

    Raises
    ------
    ParameterError
        An argument has a bad value (unknown method, t1 < t0, t_eval outside
        the interval, bad tolerance, ...).  It derives from ``ValueError``.
    CoreSignatureError
        `core` is not a numba function accepting `CORE_SIGNATURE`.

    Notes
    -----
    The error control is scipy's: error norm = RMS of
    ``err / (atol + rtol * max(|y|, |y_new|))``, step factor
    ``0.9 * norm ** (-1 / (q + 1))`` clipped to ``[0.2, 10]`` with ``q`` the
    error-estimator order (4 for RK45, 7 for DOP853), no growth right after a
    rejection.  The compiled loop is built on the first call (a few seconds,
    or ~0.1 s when numba's on-disk cache is warm); every later call, with any
    core, reuses it.

    Examples
    --------
    >>> import numba, numpy as np
    >>> @numba.njit
    ... def decay(t, y, p, dydt):
    ...     dydt[0] = -p[0] * y[0]
    >>> sol = integrate(decay, 0.0, 1.0, [1.0], [2.0], [0.5, 1.0])
    >>> sol.status, bool(abs(sol.y[0, -1] - np.exp(-2.0)) < 1e-7)
    (0, True)
    """
    method_id = loop_method_id(method)
    _check_core(core)
    args = check_arguments(t0, t1, y0, p, t_eval, rtol, atol, first_step, max_step, max_steps, pause_after,
                           sample_capacity)
    if _compiled_loop.cache_info().currsize:
        loop = _compiled_loop()
    else:
        from ..progress import announce_if_slow

        with announce_if_slow("waiting for the integrator being compiled in another process (once per cache)"
                              if any(p.poll() is None for p in _BACKGROUND) else
                              "loading the compiled integrator (compiled once per installation, ~5-10 s; "
                              "numba caches it on disk)"):
            loop = _compiled_loop()

    def run(first_step, samples, y_reached):
        try:
            return loop(core, method_id, args.t0, args.t1, args.y0, args.p, args.t_eval, args.rtol, args.atol,
                        first_step, args.max_step, args.max_steps, args.pause_after, samples, y_reached)
        except (numba.core.errors.NumbaError, TypeError):
            _raise_if_bad_signature(core)
            raise  # the core compiled fine: the error is its own, keep it as is

    return run_loop(run, args)
