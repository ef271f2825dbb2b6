"""The compiled path of small speed branches: when it applies, its set-up, and the fallback to the Python path.

A speed branch of a small system costs the Python path a few milliseconds
per point, nearly all of it call overhead around arrays of a few dozen
entries. The numba kernels of :mod:`rotorkit.periodic.compiled` and
:mod:`~rotorkit.periodic.compiled_points` run the same
algorithm (the continuation loop with its corrector, tangents, step control,
grazing corners and the end at a bound; then per point the error estimate
and Hill's multipliers) in one call each.

When it is used (automatically; all must hold)
    * numba is installed, the kernels are compiled (:func:`compile_kernels`
      once per cache folder: a minute or two; afterwards they load in about
      a second) or ``$ROTORKIT_PERIODIC_COMPILED`` is ``1`` (compile them on
      first use), and ``$ROTORKIT_PERIODIC_COMPILED`` is not ``0``
      (:attr:`~rotorkit.periodic.continuation.ContinuationOptions.compiled`
      is not False). A first branch never waits for the compilation unless
      asked to: the Python path answers it in seconds;
    * the system is compiled with the ``c`` or ``numba`` back end (the
      model's generated ``rhs``/``jac``/``switches`` are jitted by numba
      once per model structure, cached on disk);
    * the plain (not condensed) harmonic balance with ``n <= MAX_COORDINATES``
      coordinates and ``n (2H + 1) <= MAX_UNKNOWNS`` unknowns;
    * the continuation parameter is the spin speed that sets the base
      frequency, and the prepared parameters are quadratic in it (the
      :class:`~rotorkit.periodic.evaluate.Evaluator`'s speed fit succeeds; a
      tabulated speed-dependent coefficient makes it fail) and the mass
      matrix does not depend on it;
    * for the per-point data: stability ``"hill"`` or ``"none"``.

Otherwise, or if the kernel cannot start (a singular start tangent), the
Python path runs. The kernels are compiled once (numba's disk cache in
rotorkit's cache folder, :func:`rotorkit.codegen.cache.jit_shared`): about
two minutes cold on this project's 2-core machine (longer under load), about a
second to load afterwards.
"""

from __future__ import annotations

import functools
import math
import os

import numpy as np

__all__ = ["MAX_COORDINATES", "MAX_UNKNOWNS", "compile_kernels", "kernels_compiled", "compiled_setup",
           "continue_compiled", "solve_compiled", "linear_scale_compiled", "switches_compiled", "grazing_compiled",
           "point_data"]

#: points per call of the continuation kernel when a progress callback is given; each call starts the predictor
#: afresh (no quadratic term at its first step), and so does the Python reference
#: (:func:`rotorkit.periodic.continuation.continue_branch`) there
CHUNK = 16
#: the compiled path applies to systems with at most this many coordinates ...
MAX_COORDINATES = 10
#: ... and at most this many harmonic-balance unknowns n (2H + 1) (Hill's matrix is twice that)
MAX_UNKNOWNS = 48


@functools.cache
def _numba_available():
    import importlib.util

    return importlib.util.find_spec("numba") is not None


class CompiledSetup:
    """Arrays and functions the kernels take for one harmonic balance (see :func:`compiled_setup`)."""

    def __init__(self, hb, functions, fit, window, mass, addresses):
        self.hb = hb
        #: the model's jitted functions (dispatchers), for harnesses that call the kernels' parts
        self.rhs, self.jac, self.switches = functions
        #: the kernels' model functions: their addresses (int64, 6), found once per model structure
        self.addresses = addresses
        constant, varying, coefficients, s0 = fit
        self.base = np.ascontiguousarray(constant, dtype=float)
        self.varying = np.ascontiguousarray(varying, dtype=np.int64)
        self.coef = np.ascontiguousarray(coefficients, dtype=float).reshape(3, -1)
        self.s0 = float(s0)
        self.window = np.ascontiguousarray(window, dtype=float)
        self.mass = np.ascontiguousarray(mass, dtype=float)
        self.E = np.ascontiguousarray(hb.E)
        self.P = np.ascontiguousarray(hb.P)
        self.ED = np.ascontiguousarray(hb.ED)
        self.size = hb.size
        self.n_switches = hb.system.n_switches
        from .compiled_aft import aft_tables

        #: the AFT Jacobian's tables, made once per size (the kernels only read them)
        self.trig, self.terms, self.weights = aft_tables(2 * hb.harmonics + 1, hb.samples)
        self._zero = np.zeros(self.size + 1)  # read-only input of the small calls' unused arguments
        self._switches_seen = {}  # (lambda, z bytes) -> (gap, state) of the last few points asked
        self._ints = np.zeros(11, dtype=np.int64)
        self._ints[:5] = hb.n, hb.harmonics, hb.samples, hb.subharmonic, self.n_switches

    def ints(self, **values):
        ints = self._ints.copy()
        for name, value in values.items():
            ints[_INTS[name]] = value
        return ints


_INTS = {"max_iterations": 5, "max_new": 6, "count": 7, "max_points": 8, "start": 9, "hill": 10}


def compiled_setup(problem):
    """The :class:`CompiledSetup` of ``problem`` if the compiled path applies (module notes), else None."""
    found = getattr(problem, "_compiled_setup", False)
    if found is not False:
        return found
    setup = None
    try:
        setup = _new_setup(problem)
    finally:
        problem._compiled_setup = setup
    return setup


def _new_setup(problem):
    from .hb import HarmonicBalance

    hb = problem.hb
    mode = os.environ.get("ROTORKIT_PERIODIC_COMPILED", "auto")
    if mode == "0" or not _numba_available() or (mode != "1" and not kernels_compiled()):
        return None
    if type(hb) is not HarmonicBalance or problem.parameter != hb.speed_parameter:
        return None
    kept = getattr(hb, "_compiled_setup", None)  # made for an earlier problem on this harmonic balance
    if kept is not None:
        return kept
    if hb.n > MAX_COORDINATES or hb.size > MAX_UNKNOWNS:
        return None
    evaluator = hb.evaluator
    if not (evaluator.fast or evaluator.jitted):
        return None
    module = evaluator._module
    if not all(hasattr(module, name) for name in ("rhs", "jac", "prepare", "PARAMETER_NAMES")):
        return None
    names = list(module.PARAMETER_NAMES)
    if hb.speed_parameter not in names:
        return None
    parameters = hb.system.parameters
    speed = float(parameters[hb.speed_parameter])
    if not (math.isfinite(speed) and speed > 0.0):
        return None
    p = np.array([parameters[name] for name in names], dtype=float)
    fit = _speed_fit(evaluator, module, p, names.index(hb.speed_parameter))
    if fit is False:
        return None
    merged = dict(parameters)
    mass = hb.mass_matrix(merged)
    merged[hb.speed_parameter] = 1.37 * speed
    if not np.array_equal(mass, hb.mass_matrix(merged)):
        return None
    from ..system import numba_function

    switches = numba_function(module, "switches") if hasattr(module, "switches") else _no_switches()
    functions = (numba_function(module, "rhs"), numba_function(module, "jac"), switches)
    addresses = _function_addresses(functions)
    if addresses is None:
        return None
    hb._compiled_setup = setup = CompiledSetup(hb, functions, fit, evaluator._window, mass, addresses)
    return setup


def _function_addresses(functions):
    """:func:`~rotorkit.periodic.compiled_functions.function_addresses` of the model's functions, found once per
    set of functions (kept with them)."""
    key = ("addresses",) + tuple(id(f) for f in functions)
    found = _ADDRESSED.get(key)
    if found is None or any(a is not b for a, b in zip(found[0], functions)):
        from .compiled_functions import function_addresses

        found = _ADDRESSED[key] = (tuple(functions), function_addresses(functions))
    return found[1]


_FITS = {}


def _speed_fit(evaluator, module, p, slot):
    """The evaluator's quadratic speed fit of the prepared parameters at ``p`` (five ``prepare`` calls), kept
    per generated module and parameter values (a few): a new branch of the same model (a new harmonic balance,
    a new evaluator) reuses it. The fit depends on nothing else."""
    key = (id(module), p.tobytes(), slot)
    found = _FITS.get(key)
    if found is None or found[0] is not module:
        if len(_FITS) >= 16:
            _FITS.pop(next(iter(_FITS)))
        found = _FITS[key] = (module, evaluator._fit(p, slot))
    return found[1]


_ADDRESSED = {}


@functools.lru_cache(maxsize=None)
def _no_switches():
    import numba

    @numba.njit(cache=False)
    def switches(t, y, p, out):
        pass

    return switches


@functools.lru_cache(maxsize=None)
def _cache_name(kind):
    import hashlib
    from pathlib import Path

    from . import (compiled, compiled_aft, compiled_borrow, compiled_folds, compiled_functions, compiled_hill,
                   compiled_hill_matrix, compiled_newton, compiled_points, eigen, stability)

    digest = hashlib.sha256()  # every module whose code or constants (stability.STABILITY_TOL) the kernels bake in
    for path in (compiled.__file__, compiled_aft.__file__, compiled_borrow.__file__, compiled_folds.__file__,
                 compiled_functions.__file__, compiled_hill.__file__, compiled_hill_matrix.__file__,
                 compiled_newton.__file__, compiled_points.__file__, eigen.__file__, stability.__file__):
        digest.update(Path(path).read_bytes())
    return f"periodic_{kind}-{digest.hexdigest()[:12]}"


def _signature(kind):
    from numba import types

    vec, mat = types.float64[::1], types.float64[:, ::1]
    ivec = types.int64[::1]
    common = (ivec, vec, mat, mat, mat, mat)  # ints, fl, E, P, ED, M
    fit = (vec, ivec, mat, vec)  # base, varying, coef, window
    cube = types.float64[:, :, ::1]
    if kind == "continue":
        tables = (mat, types.int64[:, :, ::1], cube)  # trig, terms, weights
        return types.Tuple((types.int64, types.int64))(ivec, *common, *fit, *tables, vec, vec, mat, mat, vec, vec,
                                                       cube, types.boolean[::1])
    return types.void(ivec, *common, *fit, mat, mat, mat, vec, mat, vec, cube, vec, mat, mat, types.boolean[::1])


KINDS = ("continue", "points")


def kernels_compiled():
    """Whether both kernels are in the disk cache (or loaded in this process): the compiled path is then used
    automatically where it applies."""
    if _kernel.cache_info().currsize == len(KINDS):
        return True
    from pathlib import Path

    from ..codegen.cache import shared_dir

    try:
        return all(any(Path(shared_dir(_cache_name(kind))).rglob("*.nbc")) for kind in KINDS)
    except OSError:
        return False


def compile_kernels(verbose=True):
    """Compile the kernels of the compiled path into rotorkit's cache folder (once per cache folder).

    A minute or two; afterwards every process loads them in about a second
    and small speed branches take the compiled path automatically (module
    notes). ``python -c "import rotorkit.periodic.fastpath as f; f.compile_kernels()"``.

    Raises
    ------
    ImportError
        numba is not installed (the Python path needs nothing).
    """
    import time

    if not _numba_available():
        raise ImportError("compile_kernels: numba is not installed; the compiled path of the harmonic balance "
                          "needs it (pip install numba); the Python path works without")
    t0 = time.perf_counter()
    if verbose:
        print("rotorkit: compiling the harmonic-balance kernels (once per cache folder, a minute or two) ...",
              flush=True)
    for kind in KINDS:
        _kernel(kind)
    if verbose:
        print(f"rotorkit: harmonic-balance kernels ready in {time.perf_counter() - t0:.1f} s", flush=True)


def _entry(kind):
    """The callable that runs kernel ``kind``: the compiled overload's entry point, which takes the arguments
    as they are, else (another numba's internals) the dispatcher.

    The dispatcher types every argument at each call to pick the overload; the kernels have a single
    overload, compiled for :func:`_signature`, so the choice is known. The entry point checks no argument
    type: every array passed is built here with the signature's dtype and C order. Both kernels take the
    model's functions as their addresses (:attr:`CompiledSetup.addresses`), arrays like the others."""
    kernel = _kernel(kind)
    found = _ENTRIES.get(kind)
    if found is None or found[0] is not kernel:
        try:
            entry = kernel.overloads[_signature(kind).args].entry_point
        except (AttributeError, KeyError, TypeError):  # another numba's internals: the dispatcher
            entry = kernel
        found = _ENTRIES[kind] = (kernel, entry)
    return found[1]


_ENTRIES = {}
#: the continuation kernel's accelerations output where a call does not use it (its small services)
_NO_ACCELERATIONS = np.empty((1, 1, 1))


@functools.lru_cache(maxsize=None)
def _kernel(kind):
    """The kernel ``kind`` ("continue" or "points"), compiled for its signature (numba's verified disk cache)."""
    from ..codegen.cache import jit_shared, shared_lock
    from . import compiled, compiled_points

    function = compiled.continue_kernel if kind == "continue" else compiled_points.point_data_kernel
    name = _cache_name(kind)
    with shared_lock(name):
        return jit_shared(function.py_func, name, _signature(kind), error_model="numpy")


def continue_compiled(problem, z0, lam0, bounds, *, z_scale, options, out, progress=None):
    """:func:`~rotorkit.periodic.continuation.continue_branch` by the compiled kernel into ``out`` (an empty
    :class:`~rotorkit.periodic.continuation.BranchPoints`): True, or False where it does not apply (then the
    caller runs the Python loop).

    The points go into arrays of ``max_points + 1`` rows made once: each kernel call writes its points into
    their rows from the first free one on (views of them), the first call the start point too (row 0, its
    tangent the start tangent); the branch's fields are views of the rows written."""
    from .compiled import BOUND, BUDGET, MIN_STEP

    setup = compiled_setup(problem)
    if setup is None:
        return False
    opts = options
    start, stop = float(bounds[0]), float(bounds[1])
    lo, hi = min(start, stop), max(start, stop)
    l_scale = abs(stop - start)
    size = len(z0)
    d_lam = 1e-7 * max(l_scale, abs(lam0))
    direction = 1.0 if stop >= start else -1.0
    fl = np.array([setup.s0, z_scale, l_scale, lo, hi, d_lam, opts.step, opts.min_step, opts.max_step, opts.tol,
                   direction, 0.0])
    rows = opts.max_points + 1  # the kernel stops at max_points points; one row to spare
    U, T = np.empty((rows, size + 1)), np.empty((rows, size + 1))
    norms, scales, corner = np.empty(rows), np.empty(rows), np.empty(rows, dtype=np.bool_)
    acc = np.empty((rows, setup.hb.samples, setup.hb.n))
    u0 = np.empty(size + 1)
    u0[:size] = z0
    u0[:size] /= z_scale
    u0[size] = lam0 / l_scale
    U[0, :size], U[0, size] = z0, lam0  # the start as given (the kernel writes the rest of its row)
    t0 = np.zeros(size + 1)
    kernel = _entry("continue")
    chunk = CHUNK if progress is not None else opts.max_points
    count = 0  # rows written
    while True:
        first = count == 0
        ints = setup.ints(max_iterations=opts.max_iterations, max_new=chunk + first, count=count,
                          max_points=opts.max_points, start=first)
        status, new = kernel(setup.addresses, ints, fl, setup.E, setup.P, setup.ED, setup.mass, setup.base,
                             setup.varying, setup.coef, setup.window, setup.trig, setup.terms, setup.weights, u0, t0,
                             U[count:], T[count:], norms[count:], scales[count:], acc[count:], corner[count:])
        if status < 0:
            return False  # a singular start tangent: the Python path raises its error
        if progress is not None:
            for k in range(max(count, 1), count + new - (status == BOUND)):
                progress(k + 1, float(U[k, size]))
        count += new
        if status in (BUDGET, BOUND, MIN_STEP):
            break
    T = T[:count]
    T[:, :size] *= z_scale
    T[:, size] *= l_scale
    out.parameter = U[:count, size].copy()
    out.coefficients = U[:count, :size]
    out.tangents = T
    out.residuals = norms[:count]
    out.scales = scales[:count]
    out.accelerations = acc[:count]
    out.corners = np.flatnonzero(corner[:count]).tolist()
    if status == BUDGET:
        out.reason = f"point budget of {opts.max_points} points reached"
    elif status == BOUND:
        out.reason = f"parameter bound {problem.parameter}={fl[11]:g} reached"
    else:
        out.reason = (f"no convergence at the minimum step {opts.min_step:g} at {problem.parameter}="
                      f"{out.parameter[-1]:.6g} (a branch point or a non-smooth point the corner rule does not "
                      "pass)")
    return True


def solve_compiled(problem, guess, lam, *, tol, max_iterations):
    """:func:`~rotorkit.periodic.hb.newton` at ``parameter = lam`` from ``guess`` by the compiled kernel:
    ``(z, converged)``, or None where the compiled path does not apply."""
    setup = compiled_setup(problem)
    if setup is None:
        return None
    u0 = np.zeros(setup.size + 1)
    u0[:-1] = np.ravel(guess)
    fl = np.zeros(12)
    fl[0], fl[9], fl[11] = setup.s0, tol, lam
    (converged, _), z, _, _ = _call(setup, 2, u0, setup._zero, fl, max_iterations=max_iterations)
    return z.copy(), bool(converged)


def _call(setup, mode, u0, t0, fl, *, max_iterations=0, corner_size=1, out_u=None, **ints):
    """One call of the continuation kernel in mode ``mode`` (its small services): ``(result, z, norm,
    out_corner)``, ``z`` the first row of ``out_u`` (a view)."""
    size = setup.size
    if u0.shape != (size + 1,) or u0.dtype != np.float64:  # the entry point checks nothing (see _entry)
        raise ValueError(f"expected {size} harmonic-balance unknowns, got shape {u0.shape[:1]}")
    if out_u is None:
        out_u = np.zeros((1, size + 1))
    out_norm = np.zeros(1)
    out_corner = np.zeros(max(corner_size, 1), dtype=np.bool_)
    result = _entry("continue")(setup.addresses, setup.ints(max_iterations=max_iterations, start=mode, **ints), fl,
                                setup.E, setup.P, setup.ED, setup.mass, setup.base, setup.varying, setup.coef,
                                setup.window, setup.trig, setup.terms, setup.weights, u0, t0, out_u, out_u, out_norm,
                                out_norm, _NO_ACCELERATIONS, out_corner)
    return result, out_u[0, :size], out_norm[0], out_corner


def linear_scale_compiled(problem, values):
    """The largest amplitude of the response with the nonlinear forces as at rest over the parameter ``values``
    (:func:`rotorkit.analysis.periodic`'s amplitude scale) by the compiled kernel, or None."""
    setup = compiled_setup(problem)
    if setup is None:
        return None
    fl = np.zeros(12)
    fl[0] = setup.s0
    biggest = _call(setup, 3, np.zeros(setup.size + 1), np.ascontiguousarray(values, dtype=float), fl)[2]
    return float(biggest)


def switches_compiled(problem, z, lam):
    """``(gap, contact state)`` of :meth:`~rotorkit.periodic.continuation.ContinuationProblem.gap` and
    ``contact_state`` by the compiled kernel, or None."""
    setup = compiled_setup(problem)
    if setup is None:
        return None
    u0 = np.zeros(setup.size + 1)
    u0[:-1] = z
    lam = float(lam)
    key = (lam, u0.tobytes())
    seen = setup._switches_seen
    found = seen.get(key)
    if found is not None:  # gap and contact_state are asked at the same points in turn
        return found
    fl = np.zeros(12)
    fl[0], fl[11] = setup.s0, lam
    ns = setup.n_switches
    _, _, gap, state = _call(setup, 4, u0, setup._zero, fl, corner_size=ns)
    found = float(gap), state[:ns].copy()
    if len(seen) >= 8:
        seen.pop(next(iter(seen)))
    seen[key] = found
    return found


def grazing_compiled(problem, lam, Z, i, *, tol, max_iterations, steps, tries):
    """:func:`~rotorkit.periodic.folds.grazing_point` between the points ``i`` and ``i + 1`` of a branch
    (parameters ``lam``, coefficients ``Z``) in one kernel call
    (:func:`~rotorkit.periodic.compiled_folds.grazing_value`): Newton to ``tol`` in at most
    ``max_iterations`` iterations, ``steps`` steps per piece, ``tries`` aims per step; None where the compiled
    path does not apply."""
    setup = compiled_setup(problem)
    if setup is None:
        return None
    size = setup.size
    points = np.zeros((6, size + 1))
    valid = np.zeros(max(6, setup.n_switches), dtype=np.bool_)
    for row, k in enumerate(range(i - 2, i + 4)):
        if 0 <= k < len(lam):
            points[row, :size] = np.ravel(Z[k])
            points[row, size] = lam[k]
            valid[row] = True
    fl = np.zeros(12)
    fl[0], fl[9] = setup.s0, tol
    out_norm = np.zeros(1)
    _entry("continue")(setup.addresses, setup.ints(max_iterations=max_iterations, max_new=steps, max_points=tries,
                                                   start=5), fl, setup.E, setup.P, setup.ED, setup.mass, setup.base,
                       setup.varying, setup.coef, setup.window, setup.trig, setup.terms, setup.weights, setup._zero,
                       setup._zero, points, points, out_norm, out_norm, _NO_ACCELERATIONS, valid)
    return float(out_norm[0])


def point_data(problem, parameter, coefficients, stability, grid_factor, scales=None, accelerations=None):
    """Per point ``(omega, residual_error, multipliers or None)`` by the compiled kernel, or None where it does
    not apply (module notes) or a Hill QR iteration failed at every point.

    ``coefficients`` (n_points, 2H + 1, n); the error grid has ``grid_factor`` times the AFT samples;
    ``scales``: the points' residual scales where known (the continuation kernel's
    :attr:`~rotorkit.periodic.continuation.BranchPoints.scales`; zero or None: computed here);
    ``accelerations`` (n_points, N, n): the accelerations at each point's AFT samples where known (the kernel's
    ``BranchPoints.accelerations``; nan first, or None: evaluated here). A point whose QR iteration fails gets its
    multipliers from :func:`~rotorkit.periodic.stability.hill_multipliers`.
    """
    if stability not in ("hill", "none"):
        return None
    setup = compiled_setup(problem)
    if setup is None:
        return None
    hb = setup.hb
    lam = np.ascontiguousarray(parameter, dtype=float)
    Z = np.ascontiguousarray(np.reshape(coefficients, (len(lam), hb.size)), dtype=float)
    EG, EDG, EDDG = _error_grid(hb.harmonics, grid_factor * hb.samples)
    hill = stability == "hill"
    count = len(lam)
    errors = np.empty(count)  # the kernel writes every entry (mu_*, ok: with Hill's multipliers)
    mu_re, mu_im = np.empty((count, 2 * hb.n)), np.empty((count, 2 * hb.n))
    ok = np.empty(count, dtype=np.bool_)
    known = np.zeros(count) if scales is None else np.ascontiguousarray(scales, dtype=float)
    if known.shape != (count,):
        raise ValueError(f"expected {count} residual scales, got shape {known.shape}")
    shape = (count, hb.samples, hb.n)
    if accelerations is None:
        accs = np.full(shape, np.nan)
    else:
        accs = np.ascontiguousarray(accelerations, dtype=float)
        if accs.shape != shape:
            raise ValueError(f"expected accelerations of shape {shape}, got {accs.shape}")
    fl = np.array([setup.s0])
    _entry("points")(setup.addresses, setup.ints(hill=hill), fl, setup.E, setup.P, setup.ED, setup.mass, setup.base,
                     setup.varying, setup.coef, setup.window, EG, EDG, EDDG, lam, Z, known, accs, errors, mu_re, mu_im,
                     ok)
    omega = lam / hb.subharmonic
    if not hill:
        return omega, errors, None
    multipliers = mu_re + 1j * mu_im
    if not ok.all():
        from .stability import hill_multipliers

        for i in np.flatnonzero(~ok):
            multipliers[i] = hill_multipliers(hb, Z[i], problem.frame(lam[i]))
    return omega, errors, multipliers


@functools.lru_cache(maxsize=16)
def _error_grid(harmonics, samples):
    """The synthesis of ``q``, ``q'`` and ``q''`` (over ``w``, ``w^2``) on the error estimate's grid of ``samples``
    instants, each (samples, 2H + 1), C order; shared by every call with these sizes (the kernel only reads them;
    writeable, as the kernel's signature types them)."""
    from .hb import fourier_basis

    EG, _, D = fourier_basis(harmonics, samples)
    EDG = EG @ D
    EDDG = EDG @ D
    return tuple(np.ascontiguousarray(A) for A in (EG, EDG, EDDG))
