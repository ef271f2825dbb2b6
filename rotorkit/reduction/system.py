"""``reduce()``: a compiled system with fewer coordinates, the nonlinear ones physical (Craig-Bampton)."""

import difflib
import numbers
import re
from dataclasses import dataclass, replace

import numpy as np

from ..errors import ParameterError
from ..system import System, numba_function, resolve_backend
from .basis import craig_bampton

__all__ = ["reduce", "ReducedSystem", "ReductionError"]

_MODULES = {}
GENERATOR_VERSION = 2  # part of the cache key: a changed generator never loads an older module


def _module(model):
    """The generated reduced module of ``model``'s structure (disk-cached like the full model's)."""
    from ..codegen import cache

    key = model.structure_key + f"_reduced{GENERATOR_VERSION}"
    module = _MODULES.get(key) or cache.load(key)
    if module is None:
        from ..progress import announce_if_slow
        from .codegen import generate_reduced

        eom = model.equations()
        with announce_if_slow(f"generating the reduced code of {model.name} (cached on disk afterwards)"):
            module = cache.store(key, generate_reduced(eom, key))
    _MODULES[key] = module
    return module


@dataclass(frozen=True)
class ReductionError:
    """How far a reduced system is from the full one (see :meth:`ReducedSystem.error_estimate`).

    Attributes
    ----------
    first_dropped_frequency : float
        Lowest fixed-interface frequency left out (rad/s; inf with every mode kept).
    highest_kept_frequency : float
        Highest fixed-interface frequency kept (rad/s; 0 with none).
    band : (float, float)
        Frequency band of the FRF comparison (rad/s).
    frf_error : float
        ``max_w max_ij |H_r(w) - H(w)|_ij / max_w max_ij |H(w)|_ij`` over the
        band: receptances between the boundary coordinates of the reduced and
        the full linear part (contacts open), relative to the largest.
    frequencies : numpy.ndarray
        The frequencies compared (rad/s).
    """

    first_dropped_frequency: float
    highest_kept_frequency: float
    band: tuple
    frf_error: float
    frequencies: np.ndarray

    def __str__(self):
        return (f"first dropped fixed-interface frequency {self.first_dropped_frequency:.6g} rad/s (highest kept "
                f"{self.highest_kept_frequency:.6g}); boundary FRF error over {self.band[0]:g}-{self.band[1]:g} "
                f"rad/s: {self.frf_error:.3g} of the peak")


class ReducedSystem(System):
    """A :class:`~rotorkit.System` in Craig-Bampton coordinates (build it with :func:`reduce`).

    States: the boundary coordinates (physical, named as in the model), then
    ``eta1 ... etam`` (modal amplitudes, m: each fixed-interface mode scaled
    to a largest displacement of 1) and ``eta_static`` when the model has a
    constant interior load, then their rates. Works wherever a system does:
    :func:`rotorkit.simulate` (both engines), :meth:`with_parameters` (the
    basis is rebuilt for the new values, nothing is re-derived or
    recompiled), the modal analyses. :meth:`expand` maps results back.

    Attributes
    ----------
    full_coordinate_names : tuple of str
    boundary : tuple of str
        The physical coordinates kept (local terms' rows and arguments, then ``keep``).
    modes : int
    basis : numpy.ndarray, shape (n, R)
        ``q = basis @ z``.
    fixed_interface_frequencies : numpy.ndarray
        All the interior's fixed-interface frequencies (rad/s).
    """

    def __init__(self, model, module, backend, core, modes, keep):
        self.model, self.name, self.structure_key = model, model.name, model.structure_key
        self.backend, self.core, self._module = backend, core, module
        self.parameter_names = tuple(module.PARAMETER_NAMES)
        self._values = model.parameters
        full = tuple(module.STATE_NAMES[: module.N_COORDINATES])
        self.full_coordinate_names = full
        boundary = tuple(module.BOUNDARY) + tuple(k for k in keep if k not in module.BOUNDARY)
        self._boundary_index, self._keep = boundary, tuple(keep)
        self.boundary = tuple(full[i] for i in boundary)
        n_interior = len(full) - len(boundary)
        self.modes = modes
        p = np.array([self._values[k] for k in self.parameter_names], dtype=float)
        with np.errstate(all="ignore"):
            base, m0, g, f0 = module.linear_parts(p)
        if not (np.all(np.isfinite(base)) and np.all(np.isfinite(m0)) and np.all(np.isfinite(g))):
            raise ParameterError(f"{self.name}: the parameters give non-finite matrices (a length or mass zero?)")
        interior = np.setdiff1d(np.arange(len(full)), boundary)
        translational = np.array([k for k, i in enumerate(interior) if full[i][:1] in ("x", "y")], dtype=int)
        cb = craig_bampton(m0, -g[0][:, : len(full)], f0, boundary, modes, translational, self.name)
        T = cb.T
        self.basis, self.fixed_interface_frequencies = T, cb.frequencies
        names = self.boundary + tuple(f"eta{k + 1}" for k in range(modes)) + (("eta_static",) if cb.static_vector
                                                                             else ())
        self.coordinate_names = names
        self.state_names = names + tuple(f"{k}_dot" for k in names)
        R = T.shape[1]
        mr = T.T @ m0 @ T
        mr = 0.5 * (mr + mr.T)
        try:
            minv = np.linalg.inv(np.linalg.cholesky(mr))
            minv = minv.T @ minv
        except np.linalg.LinAlgError:
            raise ParameterError(f"{self.name}: the reduced mass matrix is not positive definite") from None
        self._m0, self._g, self._f0, self._mr = m0, g, f0, mr
        n = len(full)
        blocks = [minv @ T.T @ np.hstack([gk[:, :n] @ T, gk[:, n:] @ T]) for gk in g]
        rows = list(module.LOCAL_ROWS)
        q_mat = minv @ T[rows, :].T if rows else np.zeros((R, 0))
        prepared = np.concatenate([base, [float(R)], *[b.T.ravel() for b in blocks], minv @ (T.T @ f0), q_mat.T.ravel(),
                                   [-1e300, 1e300]])
        self.prepared_parameters = prepared
        self._plist = prepared.tolist()
        self._n_interior = n_interior

    def with_parameters(self, **overrides):
        """A copy with some parameter values changed: the basis is rebuilt for them (no re-derivation)."""
        changed = ReducedSystem(self.model.with_values(**overrides), self._module, self.backend, self.core,
                                self.modes, self._keep)
        window = self.prepared_parameters[-2:]
        if window[0] > -1e300 or window[1] < 1e300:
            return changed.within(np.nextafter(window[0], -np.inf), np.nextafter(window[1], np.inf))
        return changed

    def expand(self, result):
        """A :class:`~rotorkit.result.Result` of this system in the full model's physical coordinates."""
        if tuple(result.state_names) != self.state_names:
            raise ParameterError(f"expand: the result's states {result.state_names[:4]}... are not this reduced "
                                 f"system's ({self.state_names[:4]}...)")
        R = self.basis.shape[1]
        y = np.vstack([self.basis @ result.y[:R], self.basis @ result.y[R:]])
        full = self.full_coordinate_names
        return replace(result, y=y, state_names=full + tuple(f"{k}_dot" for k in full),
                       stats=dict(result.stats, reduced=f"{self.modes} modes, boundary {', '.join(self.boundary)}"))

    def physical_state(self, z):
        """Full physical state (2n,) of a reduced state ``z`` (2R,)."""
        z = np.asarray(z, dtype=float)
        R = self.basis.shape[1]
        return np.concatenate([self.basis @ z[:R], self.basis @ z[R:]])

    def reduced_state(self, y):
        """Reduced state (2R,) of a full physical state ``y`` (2n,), least squares in the mass metric.

        Exact for states in the basis' span (every state with every mode kept).
        """
        y = np.asarray(y, dtype=float)
        n = self.basis.shape[0]
        proj = np.linalg.solve(self._mr, self.basis.T @ self._m0)
        return np.concatenate([proj @ y[:n], proj @ y[n:]])

    def error_estimate(self, band=None, points=2000, t=0.0):
        """:class:`ReductionError`: the first dropped frequency and the boundary receptances' difference.

        Parameters
        ----------
        band : (float, float), optional
            Frequencies of interest (rad/s); default ``(0, first dropped / 2)``
            (``(0, 2 x highest fixed-interface frequency)`` with every mode kept).
        points : int
            Frequencies compared (evenly spaced, plus the reduced model's
            undamped natural frequencies in the band, where the peaks are).
        t : float
            Time of the time factors (speed profiles), s.
        """
        freqs = self.fixed_interface_frequencies
        dropped = float(freqs[self.modes]) if self.modes < freqs.size else float("inf")
        kept = float(freqs[self.modes - 1]) if self.modes else 0.0
        if band is None:
            band = (0.0, dropped / 2 if np.isfinite(dropped) else 2 * float(freqs.max(initial=1.0)))
        lo, hi = (float(b) for b in band)
        if not (np.isfinite(lo) and np.isfinite(hi) and 0 <= lo < hi):
            raise ParameterError(f"band={band!r}: expected (low, high) frequencies in rad/s, 0 <= low < high")
        if isinstance(points, bool) or not isinstance(points, numbers.Integral) or points < 2:
            raise ParameterError(f"points={points!r}: expected an integer >= 2")
        n, T = self.basis.shape
        s = np.ones(self._g.shape[0])
        if self._g.shape[0] > 1:
            self._module.time_factors(float(t), np.zeros(2 * T), self._plist, s[1:])
        g = np.tensordot(s, self._g, axes=1)
        K, C = -g[:, :n], -g[:, n:]
        b = list(self._boundary_index)
        nb = len(b)
        Kr, Cr = self.basis.T @ K @ self.basis, self.basis.T @ C @ self.basis
        w2 = np.linalg.eigvals(np.linalg.solve(self._mr, Kr)).real
        peaks = np.sqrt(w2[(w2 >= lo * lo) & (w2 <= hi * hi)])
        omega = np.unique(np.concatenate([np.linspace(lo, hi, int(points)), peaks]))
        e = np.zeros((n, nb))
        e[b, np.arange(nb)] = 1.0
        worst, peak = 0.0, 0.0
        for w in omega:
            h = np.linalg.solve(K - w * w * self._m0 + 1j * w * C, e)[b]
            hr = np.linalg.solve(Kr - w * w * self._mr + 1j * w * Cr, np.eye(T)[:, :nb])[:nb]
            worst, peak = max(worst, float(np.abs(hr - h).max())), max(peak, float(np.abs(h).max()))
        return ReductionError(dropped, kept, (lo, hi), worst / peak if peak > 0 else 0.0, omega)

    def __repr__(self):
        return (f"ReducedSystem({self.name!r}, {self.modes} modes + {len(self.boundary)} physical coordinates of "
                f"{len(self.full_coordinate_names)}, backend={self.backend!r})")


_STATION = re.compile(r"[A-Za-z_]+(\d+)")


def _keep_indices(keep, names):
    """Coordinate indices of ``keep``: coordinate names, or station numbers (all of their coordinates)."""
    if keep is None:
        return ()
    if isinstance(keep, (str, numbers.Integral)):
        keep = [keep]
    out = []
    for item in keep:
        if isinstance(item, bool):
            raise ParameterError(f"keep: {item!r} is not a coordinate name or a station number")
        if isinstance(item, numbers.Integral):
            found = [k for k, name in enumerate(names)
                     if (m := _STATION.fullmatch(name)) and int(m.group(1)) == int(item)]
            if not found:
                raise ParameterError(f"keep: the model has no coordinates at station {item!r}")
            out += found
        elif isinstance(item, str):
            if item not in names:
                near = difflib.get_close_matches(item, names, n=3)
                hint = f"; did you mean {', '.join(near)}?" if near else ""
                raise ParameterError(f"keep: unknown coordinate {item!r}{hint}")
            out.append(names.index(item))
        else:
            raise ParameterError(f"keep: {item!r} is not a coordinate name or a station number")
    return tuple(dict.fromkeys(out))


def reduce(system_or_model, modes, *, keep=None, backend=None):
    """Reduce a rotor to ``modes`` interior modes, the coordinates of its local terms physical (Craig-Bampton).

    Parameters
    ----------
    system_or_model : rotorkit.System or rotorkit.Model
    modes : int
        Fixed-interface modes of the interior kept (0 ... number of interior
        coordinates; all of them gives the full model in other coordinates).
    keep : sequence of str or int, optional
        More coordinates to keep physical: names (``"x7"``) or station
        numbers (all their coordinates), e.g. where a sensor sits.
    backend : {"auto", "c", "numba", "python"}, optional
        Default: the system's, or ``auto`` for a model.

    Returns
    -------
    ReducedSystem

    Examples
    --------
    A three-station rotor with a rub stator at its disk: the rub coordinates
    stay physical, the four interior ones become two modes. (A disk's
    unbalance is a local term: every disk's station stays physical.)

    >>> import rotorkit as rk
    >>> model = rk.Model([rk.Rotor(name="R", stations=(1, 2, 3), speed=100.0),
    ...                   rk.Disk(station=2, mass=2.0, radius=0.1)]
    ...                  + [rk.LumpedMass(station=s, mass=1.0) for s in (1, 3)]
    ...                  + [rk.ShaftSegment(start=s, end=s + 1, bending_stiffness=1e6) for s in (1, 2)]
    ...                  + [rk.ElasticSupport(station=s, stiffness=1e5, damping=10.0) for s in (1, 3)]
    ...                  + [rk.RubStator(station=2, clearance=1e-4, contact_stiffness=1e6)], name="doc_rub")
    >>> reduced = reduce(model.compile(backend="python"), modes=2)
    >>> reduced.boundary, reduced.coordinate_names
    (('x2', 'y2'), ('x2', 'y2', 'eta1', 'eta2'))
    >>> result = reduced.expand(rk.simulate(reduced, (0.0, 0.01), y0=reduced.initial_state(x2=2e-4),
    ...                                     engine="scipy"))
    >>> result.state_names[:6]
    ('x1', 'x2', 'x3', 'y1', 'y2', 'y3')
    """
    model = getattr(system_or_model, "model", system_or_model)
    if not hasattr(model, "structure_key") or not hasattr(model, "equations"):
        from ..errors import ArgumentTypeError

        raise ArgumentTypeError(f"reduce: expected a rotorkit System or Model, got {type(system_or_model).__name__}")
    if backend is None:
        backend = getattr(system_or_model, "backend", "auto")
        backend = "auto" if backend == "c" else backend  # the reduced code is matrices: not for the c back end
    backend = resolve_backend(backend, c_ok=False)
    module = _module(model)
    names = tuple(module.STATE_NAMES[: module.N_COORDINATES])
    kept = _keep_indices(keep, names)
    n_boundary = len(set(module.BOUNDARY) | set(kept))
    n_interior = len(names) - n_boundary
    if n_interior == 0:
        raise ParameterError(f"reduce: {model.name} has no interior coordinates to reduce (every coordinate is on "
                             "the boundary: a local term or keep acts on it)")
    if isinstance(modes, bool) or not isinstance(modes, numbers.Integral) or not 0 <= modes <= n_interior:
        raise ParameterError(f"modes={modes!r}: expected an integer from 0 to {n_interior} (the interior "
                             f"coordinates of {model.name}: {len(names)} coordinates, {n_boundary} on the boundary)")
    if backend == "numba":
        core = numba_function(module, "rhs")
        if not core.signatures:
            from ..engines.rk_numba import CORE_SIGNATURE
            from ..progress import announce_if_slow

            with announce_if_slow(f"compiling the reduced {model.name} with numba"):
                core.compile(CORE_SIGNATURE.args)
    else:
        core = module.rhs
    return ReducedSystem(model, module, backend, core, int(modes), kept)
