"""Right-hand side, analytic Jacobian and contact switches of a compiled system at many instants and parameter sets.

Harmonic balance evaluates the equations at the ``N`` instants of a period,
and continuation at a new parameter value every Newton iteration. With the
``c`` back end the generated Jacobian module (it holds ``rhs``, ``jac``,
``switches`` and ``prepare``, :func:`rotorkit.system.jacobian_module`) is
called through its C function addresses, and a new parameter value only
re-runs its ``prepare`` (microseconds, no new :class:`~rotorkit.System`).
With the ``numba`` back end the same module's jitted functions are called
by a jitted loop over the rows (compiled once per process and module), and a
new parameter value re-runs ``prepare`` likewise. The ``python`` back end goes
through :meth:`rotorkit.System.with_parameters` and the system's own methods.
"""

from __future__ import annotations

import ctypes
import math

import numpy as np

__all__ = ["Evaluator"]

_C_SIGNATURE = ctypes.CFUNCTYPE(None, ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)


#: one C call for all rows: ``f(times[j], Y[j], p, out[j])`` for j < rows (``out`` zeroed first: jac adds to it)
_BATCH_SOURCE = """
typedef void (*model_function)(double, const double *, const double *, double *);
void rotorkit_batch(model_function f, long rows, const double *times, const double *Y, long ny,
                    const double *p, double *out, long nout) {
    for (long j = 0; j < rows; ++j) {
        for (long k = 0; k < nout; ++k) out[j * nout + k] = 0.0;
        f(times[j], Y + j * ny, p, out + j * nout);
    }
}

/* rhs and Jacobian at the same rows in one call */
void rotorkit_batch_both(model_function f, model_function g, long rows, const double *times, const double *Y,
                         long ny, const double *p, double *out, double *jac) {
    long nj = ny * ny;
    for (long j = 0; j < rows; ++j) {
        for (long k = 0; k < ny; ++k) out[j * ny + k] = 0.0;
        for (long k = 0; k < nj; ++k) jac[j * nj + k] = 0.0;
        f(times[j], Y + j * ny, p, out + j * ny);
        g(times[j], Y + j * ny, p, jac + j * nj);
    }
}
"""
_BATCH = []


def _batch_function():
    """The C row loop (built once per cache), or None without a compiler (a Python loop then)."""
    if not _BATCH:
        try:
            from ..codegen import cache, cbuild

            library = cbuild.library(cache.shared_dir("periodic_batch2"), "periodic_batch2", _BATCH_SOURCE)
            function = library.rotorkit_batch
            function.argtypes = (ctypes.c_void_p, ctypes.c_long, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_long,
                                 ctypes.c_void_p, ctypes.c_void_p, ctypes.c_long)
            function.restype = None
            both = library.rotorkit_batch_both
            both.argtypes = (ctypes.c_void_p, ctypes.c_void_p, ctypes.c_long, ctypes.c_void_p, ctypes.c_void_p,
                             ctypes.c_long, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)
            both.restype = None
            _BATCH.append((library, function, both))
        except Exception:  # noqa: BLE001 - no compiler or no cache: the Python loop does the same
            _BATCH.append(None)
    return _BATCH[0][1] if _BATCH[0] else None


def _both_function():
    """The C row loop computing rhs and Jacobian together, or None."""
    _batch_function()
    return _BATCH[0][2] if _BATCH[0] else None


def _rows(times, Y):
    Y = np.ascontiguousarray(Y, dtype=float)
    rows = Y.shape[0]
    if np.ndim(times) == 0:
        times = np.full(rows, float(times))
    elif not (isinstance(times, np.ndarray) and times.shape == (rows,) and times.dtype == float
              and times.flags.c_contiguous):
        times = np.ascontiguousarray(np.broadcast_to(times, (rows,)), dtype=float)
    return times, Y


_NUMBA_LOOPS = {}


def _numba_loop(function):
    """A jitted ``loop(times, Y, p, out)`` calling the jitted ``function(t, y, p, out_row)`` per row."""
    found = _NUMBA_LOOPS.get(function)
    if found is None:
        import numba

        @numba.njit(cache=False)
        def loop(times, Y, p, out):
            for j in range(Y.shape[0]):
                function(times[j], Y[j], p, out[j])

        found = _NUMBA_LOOPS[function] = loop
    return found


def _numba_block_loop(function):
    """A jitted ``loop(times, Y, p, rows, cols, work, out)``: ``out[j] = J_j[rows][:, cols]`` for the jitted
    Jacobian ``function`` (one (m, m) work matrix, zeroed per row: the generated ``jac`` adds to it)."""
    key = ("block", function)
    found = _NUMBA_LOOPS.get(key)
    if found is None:
        import numba

        @numba.njit(cache=False)
        def loop(times, Y, p, rows, cols, work, out):
            for j in range(Y.shape[0]):
                work[:, :] = 0.0
                function(times[j], Y[j], p, work)
                for a in range(rows.shape[0]):
                    for b in range(cols.shape[0]):
                        out[j, a, b] = work[rows[a], cols[b]]

        found = _NUMBA_LOOPS[key] = loop
    return found


def _c_loop(function, address, prepared, times, Y, width):
    times, Y = _rows(times, Y)
    rows = Y.shape[0]
    batch = _batch_function()
    if batch is not None:
        out = np.empty((rows, width))  # the C loop zeroes each row first
        batch(address, rows, times.ctypes.data, Y.ctypes.data, Y.shape[1], prepared.ctypes.data, out.ctypes.data,
              width)
        return out
    out = np.zeros((rows, width))
    ry, ro = Y.shape[1] * 8, width * 8
    y0, o0, p = Y.ctypes.data, out.ctypes.data, prepared.ctypes.data
    for j, t in enumerate(times.tolist()):
        function(t, y0 + j * ry, p, o0 + j * ro)
    return out


class Evaluator:
    """Batch evaluations of a system's equations at parameter sets given as ``{name: value}``.

    Parameters
    ----------
    system : rotorkit.System
    """

    def __init__(self, system):
        self.system = system
        self.n_states = system.n_states
        self.n_switches = system.n_switches
        self.fast = system.backend == "c"
        self.jitted = system.backend == "numba"
        if self.jitted:
            from ..system import jacobian_module, numba_function

            self._module = module = jacobian_module(system.model, getattr(system._module, "CODEGEN", "unrolled"))
            self._loops = {name: _numba_loop(numba_function(module, name)) for name in ("rhs", "jac", "switches")
                           if hasattr(module, name)}
            self._block = _numba_block_loop(numba_function(module, "jac"))
            self._window = np.array(system.prepared_parameters[-2:], dtype=float)
        if self.fast:
            from ..codegen.cmodel import c_functions
            from ..system import jacobian_module

            self._module = module = jacobian_module(system.model, "unrolled")  # c covers unrolled code only
            functions = c_functions(module)
            self._functions = {name: _C_SIGNATURE(f.address) for name, f in functions.items()}
            self._addresses = {name: ctypes.cast(f, ctypes.c_void_p).value for name, f in self._functions.items()}
            self._window = np.array(system.prepared_parameters[-2:], dtype=float)

    def point(self, values):
        """An opaque handle of the equations at the system's parameters updated with ``values`` (SI)."""
        if not (self.fast or self.jitted):
            return self.system.with_parameters(**values) if values else self.system
        module = self._module
        if not hasattr(self, "_base"):
            base = self.system.parameters
            self._base = np.array([base[name] for name in module.PARAMETER_NAMES], dtype=float)
            self._index = {name: i for i, name in enumerate(module.PARAMETER_NAMES)}
        p = self._base.copy()
        for name, value in values.items():
            if name in self._index:
                p[self._index[name]] = value
        prepared = self._speed_polynomial(p)
        if prepared is None:
            prepared = self._prepare(p)
        prepared[-2:] = self._window
        return prepared

    def _prepare(self, p):
        module = self._module
        with np.errstate(all="ignore"):
            prepared = module.prepare(p, np.empty(module.N_PREPARED))
        return np.array(prepared, dtype=float)

    def _speed_polynomial(self, p):
        """The prepared vector at ``p`` without ``prepare`` when only one ``*_speed`` parameter changed.

        ``prepare`` (the constant mass matrix's inverse, derived parameters) depends on a spin speed only through
        gyroscopic (linear) and centrifugal (quadratic) terms. Per other parameter values, from the second new
        speed on, ``prepare`` is run at five speeds once, each entry fitted by a quadratic in the speed on three
        and checked on the other two (entries equal at all five are copied exactly); if any entry misses the
        check by more than 1e-12 of its size (a tabulated speed-dependent coefficient), ``prepare`` runs every
        time. None when not applicable (the first new speed included).
        """
        speeds = getattr(self, "_speed_slots", None)
        if speeds is None:
            names = self._module.PARAMETER_NAMES
            speeds = self._speed_slots = [i for i, name in enumerate(names) if name.endswith("_speed")]
            self._fits = {}
        changed = [i for i in speeds if p[i] != self._base[i]]
        if len(changed) != 1:
            return None
        slot = changed[0]
        key = (slot, tuple(np.delete(p, slot).tolist()))
        fit = self._fits.get(key)
        if fit is None:  # the first new speed: prepare alone (a single solution pays no fit)
            if len(self._fits) > 8:
                self._fits.clear()
            self._fits[key] = True
            return None
        if fit is True:
            fit = self._fits[key] = self._fit(p, slot)
        if fit is False:
            return None
        constant, varying, coefficients, s0 = fit
        s = float(p[slot]) / s0
        prepared = constant.copy()
        prepared[varying] = coefficients[0] + s * (coefficients[1] + s * coefficients[2])
        return prepared

    def _fit(self, p, slot):
        s0 = float(p[slot])
        if not (math.isfinite(s0) and s0 > 0.0):
            return False
        speeds = np.array([1.0, 0.5, 1.5, 0.75, 1.25])  # times s0
        samples = []
        for s in speeds:
            q = p.copy()
            q[slot] = s * s0
            samples.append(self._prepare(q))
        samples = np.array(samples)
        samples[:, -2:] = 0.0
        same = np.all((samples == samples[0]) | (np.isnan(samples) & np.isnan(samples[0])), axis=0)
        varying = np.flatnonzero(~same)
        if not np.all(np.isfinite(samples[:, varying])):
            return False
        V = np.vander(speeds[:3], 3, increasing=True)  # rows (1, s, s^2)
        coefficients = np.linalg.solve(V, samples[:3, varying])
        check = np.vander(speeds[3:], 3, increasing=True) @ coefficients
        size = np.max(np.abs(samples[:, varying]), axis=0) if varying.size else np.zeros(0)
        if np.any(np.abs(check - samples[3:, varying]) > 1e-12 * size):
            return False
        return samples[0].copy(), varying, coefficients, s0

    def _jitted(self, name, point, times, Y, *shape):
        times, Y = _rows(times, Y)
        out = np.zeros((Y.shape[0],) + shape)
        self._loops[name](times, Y, point, out)
        return out

    def rhs(self, point, times, Y):
        """``dy/dt`` at each row of ``Y`` (m, 2n) and time in ``times`` (s): shape (m, 2n)."""
        if self.jitted:
            return self._jitted("rhs", point, times, Y, self.n_states)
        if self.fast:
            return _c_loop(self._functions["rhs"], self._addresses["rhs"], point, times, Y, self.n_states)
        times = np.broadcast_to(times, (len(Y),))
        return np.array([point.rhs(t, y) for t, y in zip(times.tolist(), Y)])

    def jacobian(self, point, times, Y):
        """The analytic ``d(dy/dt)/dy`` at each row: shape (m, 2n, 2n)."""
        m = self.n_states
        if self.jitted:
            return self._jitted("jac", point, times, Y, m, m)
        if self.fast:
            return _c_loop(self._functions["jac"], self._addresses["jac"], point, times, Y, m * m).reshape(-1, m, m)
        times = np.broadcast_to(times, (len(Y),))
        return np.array([point.jacobian(t, y) for t, y in zip(times.tolist(), Y)])

    def rhs_and_jacobian(self, point, times, Y):
        """:meth:`rhs` and :meth:`jacobian` at the same rows (one C call with the ``c`` back end)."""
        both = _both_function() if self.fast else None
        if both is None:
            return self.rhs(point, times, Y), self.jacobian(point, times, Y)
        times, Y = _rows(times, Y)
        rows, m = Y.shape
        out, jac = np.empty((rows, m)), np.empty((rows, m, m))
        both(self._addresses["rhs"], self._addresses["jac"], rows, times.ctypes.data, Y.ctypes.data, m,
             point.ctypes.data, out.ctypes.data, jac.ctypes.data)
        return out, jac

    def jacobian_block(self, point, times, Y, rows, cols):
        """The rows ``rows`` and columns ``cols`` of the analytic Jacobian at each row: (m, len(rows), len(cols))."""
        rows, cols = np.asarray(rows, dtype=np.int64), np.asarray(cols, dtype=np.int64)
        if self.jitted:
            times, Y = _rows(times, Y)
            m = self.n_states
            out = np.empty((Y.shape[0], len(rows), len(cols)))
            self._block(times, Y, point, rows, cols, np.zeros((m, m)), out)
            return out
        return self.jacobian(point, times, Y)[:, rows][:, :, cols]

    def switches(self, point, times, Y):
        """The contact switch functions at each row: shape (m, n_switches)."""
        if not self.n_switches:
            return np.zeros((len(Y), 0))
        if self.jitted:
            return self._jitted("switches", point, times, Y, self.n_switches)
        if self.fast:
            return _c_loop(self._functions["switches"], self._addresses["switches"], point, times, Y,
                           self.n_switches)
        times = np.broadcast_to(times, (len(Y),))
        return np.array([point.switch_values(t, y) for t, y in zip(times.tolist(), Y)])
