"""Compiled adaptive explicit Runge-Kutta integrator in C (the ``c`` back end's loop).

The same loop as :mod:`rotorkit.engines.rk_numba` (scipy's RK45 and DOP853
with their error norms, step-size controller, initial-step heuristic and
dense output; pauses with ``h_next``; sample buffers; non-finite stages
retried with a step divided by 5), ported step by step to C99 in
``rk_loop.c`` with the arithmetic in the same order: on smooth problems it
takes the same steps (``nfev``, accepted, rejected) and gives the same
samples to rounding (~1e-13 relative). The coefficient tables and constants
are written into the C source from :mod:`rotorkit.engines.rk_common`, the
tables the numba loop uses.

Why C
-----
numba takes 5-6 s to compile its loop once per cache and 0.5-0.8 s per
process to load it (numba's import and target set-up). gcc builds
``rk_loop.c`` in about a second, once per cache
(:func:`rotorkit.codegen.cbuild.library`: ``<cache>/shared/rk_c_loop``,
signed), and loading the built library costs ~30 ms beyond numpy's import.
This module never imports numba. Per step the C loop is as fast or faster
(0.7-0.8 x numba's time on 2 and 64 states): gcc builds it for any x86-64
and for AVX2, the loader picking the version the processor runs
(``bench/bench_c_loop.py``).

Right-hand side contract
------------------------
The core is a C function, passed as its address (an ``int``, e.g.
``ctypes.cast(lib.rhs, ctypes.c_void_p).value``; a ctypes function pointer
is accepted too)::

    void rhs(double t, const double *y, const double *p, double *dydt);

It must write all ``n`` entries of ``dydt``, must not keep the pointers,
and must be safe to call from any thread. A C core cannot raise: a failure
it wants reported should write a NaN (the run then stops with status -2 at
the time the core stopped being finite).

The loop runs without the GIL (ctypes releases it), so independent runs can
execute in threads; it keeps no global state. Statuses and the result are
those of :func:`rotorkit.engines.rk_numba.integrate`, plus -5 when the
loop's scratch memory cannot be allocated.
"""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path

import numpy as np

from rotorkit.errors import RotorkitError

from . import rk_common as common
from .rk_common import (
    METHODS,
    STATUS_MAX_STEPS,
    STATUS_NO_MEMORY,
    STATUS_NON_FINITE,
    STATUS_PAUSED,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
    CoreSignatureError,
    RKSolution,
    loop_method_id,
)
from .rk_arguments import check_arguments, run_loop

__all__ = [
    "METHODS",
    "STATUS_SUCCESS",
    "STATUS_STEP_TOO_SMALL",
    "STATUS_NON_FINITE",
    "STATUS_MAX_STEPS",
    "STATUS_PAUSED",
    "STATUS_NO_MEMORY",
    "CoreSignatureError",
    "RKSolution",
    "integrate",
    "source",
]

#: the C source template (its ``/* @GENERATED@ */`` line is replaced by `_generated`)
TEMPLATE = Path(__file__).with_name("rk_loop.c")
_MARKER = "/* @GENERATED@ */"
#: C-only status: an argument the Python front end never passes (a bug if seen)
_STATUS_BAD_ARGUMENT = -6
#: ``<cache>/shared/<folder>`` holds the built loop
_FOLDER = "rk_c_loop"
_NAME = "rk_loop"


def _c_double(value):
    """A C literal for the double `value`: repr() round-trips, so the compiler reads the same double."""
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"a coefficient must be finite; got {value!r}")
    return repr(value)


def _c_table(name, values):
    """``static const double name[..][..] = {...};`` with `values`' shape."""
    arr = np.asarray(values, dtype=np.float64)

    def body(a):
        if a.ndim == 1:
            return "{" + ", ".join(_c_double(v) for v in a) + "}"
        return "{\n    " + ",\n    ".join(body(row) for row in a) + "}"

    dims = "".join(f"[{d}]" for d in arr.shape)
    return f"static const double {name}{dims} = {body(arr)};"


def _generated():
    """The constants and tables of `rk_common` as C (the text that replaces the template's marker)."""
    c = common
    rk45_rows = c.RK45_N_STAGES + 1
    assert c.RK45_A_SQ.shape == (rk45_rows, rk45_rows) and c.RK45_C_EXT.shape == (rk45_rows,)
    assert c.RK45_B.shape == (c.RK45_N_STAGES,) and c.RK45_E.shape == (rk45_rows,)
    assert c.RK45_PT.shape[1] == rk45_rows
    ext = c.DOP853_N_STAGES_EXTENDED
    assert c.DOP853_A.shape == (ext, ext) and c.DOP853_C.shape == (ext,)
    assert c.DOP853_B.shape == (c.DOP853_N_STAGES,)
    assert c.DOP853_E3.shape == c.DOP853_E5.shape == (c.DOP853_N_STAGES + 1,)
    assert c.DOP853_D.shape == (c.DOP853_INTERPOLATOR_POWER - 3, ext)
    integers = {
        "STATUS_SUCCESS": c.STATUS_SUCCESS,
        "STATUS_STEP_TOO_SMALL": c.STATUS_STEP_TOO_SMALL,
        "STATUS_NON_FINITE": c.STATUS_NON_FINITE,
        "STATUS_MAX_STEPS": c.STATUS_MAX_STEPS,
        "STATUS_PAUSED": c.STATUS_PAUSED,
        "STATUS_NO_MEMORY": c.STATUS_NO_MEMORY,
        "STATUS_BAD_ARGUMENT": _STATUS_BAD_ARGUMENT,
        "METHOD_RK45": c.RK45_ID,
        "METHOD_DOP853": c.DOP853_ID,
        "RK45_N_STAGES": c.RK45_N_STAGES,
        "RK45_ERROR_ORDER": c.RK45_ERROR_ORDER,
        "RK45_DENSE_ROWS": c.RK45_PT.shape[0],
        "DOP853_N_STAGES": c.DOP853_N_STAGES,
        "DOP853_N_STAGES_EXTENDED": ext,
        "DOP853_ERROR_ORDER": c.DOP853_ERROR_ORDER,
        "DOP853_INTERPOLATOR_POWER": c.DOP853_INTERPOLATOR_POWER,
        "DOP853_DENSE_ROWS": c.DOP853_D.shape[0],
    }
    assert integers["STATUS_SUCCESS"] != 1  # 1 is the loop's "running"
    reals = {"SAFETY": c.SAFETY, "MIN_FACTOR": c.MIN_FACTOR, "MAX_FACTOR": c.MAX_FACTOR, "DIVERGED": c.DIVERGED}
    tables = {
        "RK45_A": c.RK45_A_SQ, "RK45_B": c.RK45_B, "RK45_C": c.RK45_C_EXT, "RK45_E": c.RK45_E,
        "RK45_PT": c.RK45_PT,
        "DOP853_A": c.DOP853_A, "DOP853_B": c.DOP853_B, "DOP853_C": c.DOP853_C, "DOP853_E3": c.DOP853_E3,
        "DOP853_E5": c.DOP853_E5, "DOP853_D": c.DOP853_D,
    }
    lines = ["/* generated by rotorkit.engines.rk_c from rotorkit/engines/rk_common.py: do not edit */"]
    lines += [f"#define {name} ({int(value)})" for name, value in integers.items()]
    lines += [f"#define {name} ({_c_double(value)})" for name, value in reals.items()]
    lines += [_c_table(name, value) for name, value in tables.items()]
    return "\n".join(lines)


def source():
    """The complete C source of the loop: the template with rk_common's constants and tables filled in.

    Returns
    -------
    str
    """
    template = TEMPLATE.read_text(encoding="utf-8")
    if template.count(_MARKER) != 1:
        raise RotorkitError(f"{TEMPLATE} must hold the line {_MARKER} exactly once (a damaged installation)")
    return template.replace(_MARKER, _generated())


def _folder():
    """``<cache>/shared/rk_c_loop``, private; None (a temporary folder) if the cache cannot be used."""
    from ..codegen import cache

    try:
        return cache.shared_dir(_FOLDER)
    except OSError as exc:
        cache.warn_once(f"rotorkit cache: the C integration loop cannot be kept in the cache ({exc}); "
                        "building it in a temporary folder", topic=("c-loop", _FOLDER))
        return None


class _Loop:
    """The built library and its ``rk_integrate`` with ctypes argument types (the library stays loaded)."""

    def __init__(self, library):
        self.library = library
        fn = library.rk_integrate
        fn.restype = ctypes.c_int64
        i64, f64, ptr = ctypes.c_int64, ctypes.c_double, ctypes.c_void_p
        fn.argtypes = [ptr, i64, f64, f64, ptr, i64, ptr, ptr, i64, f64, ptr, f64, f64, i64, i64, ptr, i64, ptr,
                       ptr, ptr]
        self.rk_integrate = fn


@functools.lru_cache(maxsize=None)
def _loop():
    """Build (or load from the cache) the C loop, once per process.

    Raises
    ------
    rotorkit.codegen.cbuild.CompilerError
        No C compiler (use :mod:`rotorkit.engines.rk_numba`), or it failed.
    """
    from ..codegen import cbuild
    from ..progress import announce_if_slow

    text = source()
    with announce_if_slow("building the C integration loop (once per cache, about a second)"):
        return _Loop(cbuild.library(_folder(), _NAME, text))


def build_in_background():
    """Start building (or loading) the C loop in a thread of this process; returns the thread, or None if loaded.

    gcc runs as a child process, so the thread holds no GIL while it waits: a caller that will integrate soon but
    has other work first (``rotorkit run`` derives and compiles its model) gets the loop built on another core in
    the meantime. Errors are left for the first :func:`integrate` to raise (it builds the loop again).
    """
    import threading

    if _loop.cache_info().currsize:
        return None

    def build():
        try:
            _loop()
        except Exception:  # noqa: BLE001 - integrate() builds it again and raises with the compiler's message
            _loop.cache_clear()

    thread = threading.Thread(target=build, name="rotorkit-c-loop", daemon=True)
    thread.start()
    return thread


def _core_address(core):
    """The address of the C right-hand side (an int or a ctypes function pointer); CoreSignatureError if not one."""
    if isinstance(core, ctypes._CFuncPtr):
        core = ctypes.cast(core, ctypes.c_void_p).value
    if isinstance(core, bool) or not isinstance(core, (int, np.integer)) or not 0 < int(core) < 2 ** 64:
        raise CoreSignatureError(
            f"core={core!r} must be the address (an int) of a C function "
            f"void core(double t, const double *y, const double *p, double *dydt), "
            f"e.g. ctypes.cast(library.rhs, ctypes.c_void_p).value; got {type(core).__name__}.")
    return int(core)


def integrate(core, t0, t1, y0, p, t_eval, *, method="DOP853", rtol=1e-6,
              atol=1e-9, first_step=None, max_step=np.inf,
              max_steps=50_000_000, pause_after=None, sample_capacity=None):
    """Integrate ``dy/dt = core(t, y, p)`` from `t0` to `t1` in the C loop.

    Exactly :func:`rotorkit.engines.rk_numba.integrate` (same arguments,
    checks, messages, statuses, steps and `RKSolution`) except for `core`.

    Parameters
    ----------
    core : int or ctypes function pointer
        Address of ``void core(double t, const double *y, const double *p,
        double *dydt)`` writing the derivative into ``dydt``.
    t0, t1, y0, p, t_eval, method, rtol, atol, first_step, max_step, max_steps, pause_after, sample_capacity
        As for :func:`rotorkit.engines.rk_numba.integrate`.

    Returns
    -------
    RKSolution
        Samples, final state, status, counters and message. Failures are
        reported through ``status``/``message``, never raised (-5: the
        loop's scratch memory could not be allocated).

    Raises
    ------
    ParameterError
        An argument has a bad value (as rk_numba's).
    CoreSignatureError
        `core` is not an address.
    rotorkit.codegen.cbuild.CompilerError
        No C compiler to build the loop (:func:`rotorkit.codegen.cbuild.compiler`), or it failed.

    Examples
    --------
    >>> import ctypes
    >>> from rotorkit.codegen import cbuild
    >>> lib = cbuild.library(None, "decay", "void rhs(double t, const double *y, const double *p, double *d)"
    ...                      "{ d[0] = -p[0] * y[0]; }")
    >>> sol = integrate(ctypes.cast(lib.rhs, ctypes.c_void_p).value, 0.0, 1.0, [1.0], [2.0], [0.5, 1.0])
    >>> sol.status, bool(abs(sol.y[0, -1] - np.exp(-2.0)) < 1e-7)
    (0, True)
    """
    method_id = loop_method_id(method)
    address = _core_address(core)
    args = check_arguments(t0, t1, y0, p, t_eval, rtol, atol, first_step, max_step, max_steps, pause_after,
                           sample_capacity)
    rk_integrate = _loop().rk_integrate
    n = args.y0.size
    counters = np.zeros(4, dtype=np.int64)  # n_samples_done, nfev, n_accepted, n_rejected
    reals = np.zeros(2)  # t_reached, h_next

    def run(first_step, samples, y_reached):
        status = rk_integrate(
            address, method_id, args.t0, args.t1, args.y0.ctypes.data, n, args.p.ctypes.data,
            args.t_eval.ctypes.data, args.t_eval.size, args.rtol, args.atol.ctypes.data, first_step,
            args.max_step, args.max_steps, args.pause_after, samples.ctypes.data, samples.shape[1],
            y_reached.ctypes.data, counters.ctypes.data, reals.ctypes.data)
        if status == STATUS_NO_MEMORY:  # nothing integrated: the state at t_reached = t0 is y0
            y_reached[:] = args.y0
        elif status == _STATUS_BAD_ARGUMENT:  # pragma: no cover - the checks above exclude it
            raise RotorkitError(f"the C integration loop refused its arguments (n={n}, columns={samples.shape[1]}, "
                                f"t_eval size {args.t_eval.size}, method id {method_id}): a bug in rotorkit")
        return (int(status), int(counters[0]), float(reals[0]), int(counters[1]), int(counters[2]),
                int(counters[3]), float(reals[1]))

    return run_loop(run, args)
