"""Modes of a linear second-order system: frequencies, log decrement, whirl, left/right shapes.

The system is ``M q'' + C q' + K q = 0`` (``C`` holding damping and the
speed-scaled gyroscopic matrix, ``K`` the stiffness and any cross-coupled,
circulatory part). Its state matrix ``A = [[0, I], [-M^-1 K, -M^-1 C]]``
has eigenvalues ``lambda`` in conjugate pairs; a mode is one pair, kept by
its member with ``Im(lambda) > 0``.

- natural frequency ``|lambda|`` (the undamped one for viscous damping),
- damped natural frequency ``Im(lambda)``,
- damping ratio ``zeta = -Re(lambda) / |lambda|``,
- logarithmic decrement ``delta = -2 pi Re(lambda) / Im(lambda)`` (the
  log of the ratio of successive peaks of a free decay; negative: unstable),
- right shape ``x``: ``(lambda^2 M + lambda C + K) x = 0``; left shape
  ``y``: ``y^H (lambda^2 M + lambda C + K) = 0``, normalised so that
  ``y^H (2 lambda M + C) x = 1`` (they differ when ``C`` or ``K`` is not
  symmetric: gyroscopics, cross-coupled bearings),
- whirl per station and per mode (:mod:`rotorkit.analysis.whirl`).

A double eigenvalue (an isotropic rotor at rest) has no preferred basis;
the pair is rotated into its backward and forward circular combinations,
backward first.

Mode numbers are 1-based in every method (mode 1 is the lowest); arrays
are plain numpy arrays indexed from 0.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .tables import DEFAULT_TABLE_MODES, csv_output
from .whirl import orbit, reference_length, shape_whirl, slope_orbit, station_pairs, tilt_pairs

__all__ = ["Modes", "modes_from_matrices", "modes_from_state_matrix", "oscillatory_order", "sparse_pays",
           "state_matrix"]

#: A pair is oscillatory when Im(lambda) exceeds this fraction of |lambda|.
OSCILLATORY_RTOL = 1e-9
#: Two eigenvalues closer than this fraction of |lambda| form a double one.
DOUBLE_RTOL = 1e-7

def frequency_factor(units, name="units"):
    """Factor from rad/s to the output ``units`` (``"rad/s"``, ``"Hz"``, ``"rpm"`` or another angular speed).

    See :func:`rotorkit.units.display_factor`; Hz and rpm count cycles (1 Hz = 2 pi rad/s).
    """
    from ..units import display_factor

    return display_factor(units, "speed", name)


def unit_slug(units):
    """A unit as a column-name suffix: ``"rad/s"`` -> ``"rad_s"``, ``"rpm"`` -> ``"rpm"``."""
    return "".join(c if c.isalnum() else "_" for c in str(units).replace("**", "")).strip("_")


def _readonly(array):
    array = np.array(array)
    array.setflags(write=False)
    return array


@dataclass(frozen=True, slots=True, eq=False)
class Modes:
    """Natural frequencies, damping, whirl and mode shapes of a linear(ised) system.

    Attributes
    ----------
    frequencies : numpy.ndarray, shape (k,)
        Natural frequencies ``|lambda|`` (rad/s), ascending.
    damping_ratios : numpy.ndarray, shape (k,)
        ``-Re(lambda) / |lambda|`` (dimensionless); negative for a growing mode.
    eigenvalues : numpy.ndarray of complex, shape (k,)
        ``lambda`` (1/s), the member of each conjugate pair with ``Im > 0``.
    shapes : numpy.ndarray of complex, shape (n, k)
        Column ``i`` is the right eigenvector (coordinate part) of mode
        ``i + 1``, in :attr:`coordinate_names` order (m for ``x``/``y``, rad
        for angles), scaled so that its largest entry is exactly ``1``.
    coordinate_names : tuple of str, length n
    operating_point : numpy.ndarray, shape (n,)
        The coordinates ``q*`` (m, rad) the system was linearised at.
    frequency_range : numpy.ndarray, shape (k, 2)
        Lowest and highest value (rad/s) of each frequency over the sampled
        cage positions (both equal :attr:`frequencies` for one sample).
    sample_times : numpy.ndarray, shape (m,)
        Times (s) at which the Jacobian was evaluated and averaged.
    all_eigenvalues : numpy.ndarray of complex, shape (2n,)
        Every eigenvalue, real ones included, by ascending ``|lambda|``.
    rub_engaged : bool
        Whether a rub contact was engaged in the linearisation.
    left_shapes : numpy.ndarray of complex, shape (n, k), or None
        Left eigenvectors ``y`` with ``y^H (2 lambda M + C) x = 1`` for the
        scaled right shape ``x`` (for a compiled system ``M`` is the identity:
        the mass-normalised problem ``q'' + M^-1 C q' + M^-1 K q = 0``).
    speed : float or None
        The swept rotor speed (rad/s) the modes belong to, if known.
    station_positions : dict or None
        Station -> axial position (m), when the model has them.
    layout : rotorkit.plotting.rotor.RotorLayout or None
        The rotor drawn under the mode shapes (positions of every spool,
        shaft, disks, bearings), when the modes come from a model.

    Notes
    -----
    The arrays are read-only. ``eq=False``: results compare by identity.
    """

    frequencies: np.ndarray
    damping_ratios: np.ndarray
    eigenvalues: np.ndarray
    shapes: np.ndarray
    coordinate_names: tuple
    operating_point: np.ndarray
    frequency_range: np.ndarray
    sample_times: np.ndarray
    all_eigenvalues: np.ndarray
    rub_engaged: bool = False
    left_shapes: np.ndarray | None = None
    speed: float | None = None
    station_positions: dict | None = None
    layout: object = None

    def __len__(self):
        return int(self.frequencies.size)

    @property
    def damped_frequencies(self):
        """``Im(lambda)`` (rad/s), shape (k,): the frequency of free decay."""
        return self.eigenvalues.imag.copy()

    @property
    def log_decrements(self):
        """Logarithmic decrement ``-2 pi Re(lambda) / Im(lambda)``, shape (k,); negative: unstable."""
        return -2.0 * np.pi * self.eigenvalues.real / self.eigenvalues.imag

    @property
    def stable(self):
        """True when no mode grows (every ``Re(lambda) <= 0``, real eigenvalues included)."""
        return bool(np.all(self.all_eigenvalues.real <= 0.0))

    @property
    def stations(self):
        """Stations with an ``x`` and a ``y`` coordinate, in model order (str)."""
        return tuple(s for s, _, _ in station_pairs(self.coordinate_names))

    def _index(self, mode):
        """0-based column of 1-based ``mode`` (negative numbers count from the highest)."""
        k = len(self)
        if isinstance(mode, bool) or not isinstance(mode, numbers.Integral) or mode == 0 or not -k <= mode <= k:
            raise ParameterError(f"mode {mode!r} is invalid: expected a mode number from 1 to {k}")
        return int(mode) - 1 if mode > 0 else k + int(mode)

    def shape_of(self, mode):
        """Mode shape of ``mode`` (1-based) as ``{coordinate name: complex amplitude}`` (largest entry 1)."""
        i = self._index(mode)
        return dict(zip(self.coordinate_names, self.shapes[:, i].tolist()))

    @property
    def reference_length(self):
        """Length (m) weighing tilts against displacements: the span of the station positions, else 1 m."""
        return reference_length(self.station_positions)

    def displacement_sizes(self, mode):
        """``|shape|`` of ``mode`` (1-based) per coordinate, tilts times :attr:`reference_length` (m, relative).

        What the dominant coordinates are ranked by: a tilt ``theta`` counts
        as the displacement ``theta L`` it makes over the rotor's length.
        """
        i = self._index(mode)
        sizes = np.abs(self.shapes[:, i]).astype(float)
        tilts = [j for _, a, b in tilt_pairs(self.coordinate_names) for j in (a, b)]
        sizes[tilts] *= self.reference_length
        return sizes

    def dominant_coordinates(self, mode, count=3):
        """Names of the ``count`` coordinates of ``mode`` (1-based) that move most, largest first.

        Ranked by displacement: the ``x``, ``y`` (m) and torsion (rad)
        entries of the shape first, then the tilts; entries below
        :data:`~rotorkit.analysis.whirl.SIGNIFICANT` of the largest (tilts
        times :attr:`reference_length`, as the whirl of a mode weighs them)
        are left out. Tilts lead only when the displacements are
        insignificant: a station that only tilts.
        """
        from .whirl import SIGNIFICANT

        sizes = self.displacement_sizes(mode)
        tilt = np.zeros(sizes.size, dtype=bool)
        tilt[[j for _, a, b in tilt_pairs(self.coordinate_names) for j in (a, b)]] = True
        moved = sizes[~tilt].max() if (~tilt).any() else 0.0
        tilted = sizes[tilt].max() if tilt.any() else 0.0
        keep = sizes >= SIGNIFICANT * max(moved, tilted)
        if moved >= SIGNIFICANT * tilted and moved > 0:  # displacements first, tilts after them
            rank = np.where(tilt, sizes / max(tilted, 1e-300) - 2.0, sizes / moved)
        else:
            rank = sizes
        order = [j for j in np.argsort(-rank, kind="stable") if keep[j] and sizes[j] > 0]
        return tuple(self.coordinate_names[j] for j in order[:count])

    def orbits(self, mode):
        """Station -> :class:`~rotorkit.analysis.whirl.Orbit` of ``mode`` (1-based), relative size."""
        i = self._index(mode)
        v = self.shapes[:, i]
        return {s: orbit(v[ix], v[iy]) for s, ix, iy in station_pairs(self.coordinate_names)}

    def slope_orbits(self, mode):
        """Station -> :class:`~rotorkit.analysis.whirl.Orbit` of the shaft slope ``(thy, -thx)`` (tilting stations)."""
        i = self._index(mode)
        v = self.shapes[:, i]
        return {s: slope_orbit(v[a], v[b]) for s, a, b in tilt_pairs(self.coordinate_names)}

    def station_whirl(self, mode):
        """Station -> ``"forward"``, ``"backward"`` or ``"linear"`` for ``mode`` (1-based).

        The whirl of the station's displacement orbit, or of its slope orbit
        where the station only tilts (see :func:`~rotorkit.analysis.whirl.shape_whirl`).
        """
        i = self._index(mode)
        stations = shape_whirl(self.shapes[:, [i]], self.coordinate_names, self.station_positions)[1]
        return {s: str(kinds[0]) for s, kinds in stations.items()}

    @property
    def whirl(self):
        """Per mode: ``"forward"``, ``"backward"``, ``"mixed"`` or ``"linear"`` (no bending motion).

        Displacement orbits and slope orbits (tilting stations, weighed by
        the span of the station positions) below 1 % of the mode's largest
        are ignored (:func:`~rotorkit.analysis.whirl.shape_whirl`).
        """
        return shape_whirl(self.shapes, self.coordinate_names, self.station_positions)[0]

    @property
    def sampled(self):
        """Whether the modes average several cage positions (ball bearings): the table shows the spread."""
        return self.sample_times.size > 1

    def _rows(self, n_modes):
        if n_modes is None:
            return len(self)
        if isinstance(n_modes, bool) or not isinstance(n_modes, numbers.Integral) or n_modes < 1:
            raise ParameterError(f"n_modes={n_modes!r} is invalid: expected an integer >= 1 or None (all modes)")
        return min(int(n_modes), len(self))

    def table(self, units="rad/s", n_modes=DEFAULT_TABLE_MODES):
        """A plain-text table: frequency, damping ratio, log decrement, whirl, dominant coordinates.

        Parameters
        ----------
        units : str
            Units of the frequency columns: ``"rad/s"``, ``"Hz"``, ``"rpm"``
            (Hz and rpm count cycles) or another angular speed.
        n_modes : int or None
            The lowest modes listed (default 6); None lists all.

        Notes
        -----
        The cage-spread column (the range of each frequency over the cage
        positions of ball bearings) appears only when several cage positions
        were sampled. Dominant coordinates are ranked by displacement (see
        :meth:`dominant_coordinates`); the whirl is the one the mode-shape
        plot marks (:func:`~rotorkit.analysis.whirl.shape_whirl`).
        """
        factor = frequency_factor(units)
        rows = self._rows(n_modes)
        spread_head = f"  {f'cage spread ({units})':>23}" if self.sampled else ""
        head = (f"{'mode':>4}  {f'natural ({units})':>16}  {f'damped ({units})':>15}  {'damping ratio':>13}  "
                f"{'log dec':>9}  {'whirl':>8}{spread_head}  dominant coordinates")
        lines = [head, "-" * len(head)]
        whirl, logdec = self.whirl, self.log_decrements
        for i in range(rows):
            spread = ""
            if self.sampled:
                lo, hi = self.frequency_range[i] * factor
                spread = "  " + (f"{lo:10.4g} - {hi:<10.4g}" if np.isfinite(lo) else f"{'n/a':>23}")
            lines.append(
                f"{i + 1:>4}  {self.frequencies[i] * factor:>16.6g}  {self.eigenvalues[i].imag * factor:>15.6g}  "
                f"{self.damping_ratios[i]:>13.4g}  {logdec[i]:>9.4g}  {whirl[i]:>8}{spread}  "
                f"{', '.join(self.dominant_coordinates(i + 1))}"
            )
        if rows < len(self):
            lines.append(f"({len(self) - rows} higher modes not shown; table(n_modes=None) lists all {len(self)})")
        return "\n".join(lines)

    def _columns(self, units):
        factor = frequency_factor(units)
        slug = unit_slug(units)
        columns = {
            "mode": np.arange(1, len(self) + 1),
            f"natural_frequency_{slug}": self.frequencies * factor,
            f"damped_frequency_{slug}": self.eigenvalues.imag * factor,
            "damping_ratio": np.asarray(self.damping_ratios),
            "log_decrement": self.log_decrements,
            "whirl": np.array(self.whirl, dtype=object),
        }
        if self.sampled:
            columns[f"cage_low_{slug}"] = self.frequency_range[:, 0] * factor
            columns[f"cage_high_{slug}"] = self.frequency_range[:, 1] * factor
        return columns

    def to_csv(self, path=None, *, units="rad/s"):
        """The modes as CSV: mode, natural and damped frequency, damping ratio, log dec, whirl (all modes).

        ``path`` (None: the text) and ``units`` as for every linear result
        (:func:`~rotorkit.analysis.tables.csv_output`).
        """
        columns = self._columns(units)
        rows = [",".join(columns)]
        for i in range(len(self)):
            rows.append(",".join(f"{v[i]:.10g}" if isinstance(v[i], (float, np.floating)) else str(v[i])
                                 for v in columns.values()))
        return csv_output("\n".join(rows) + "\n", path)

    def to_dataframe(self, units="rad/s"):
        """The modes as a :class:`pandas.DataFrame` indexed by mode number (columns as in :meth:`to_csv`)."""
        import pandas as pd

        columns = self._columns(units)
        return pd.DataFrame({k: v for k, v in columns.items() if k != "mode"}, index=pd.Index(columns["mode"],
                                                                                                name="mode"))

    def plot_mode_shape(self, mode, ax=None, **kwargs):
        """Whirl orbit sizes of ``mode`` (1-based) along the shaft; returns the matplotlib Axes."""
        from ..plotting.modes import plot_mode_shape

        return plot_mode_shape(self, mode, ax=ax, **kwargs)

    def plot_orbits(self, mode, ax=None, **kwargs):
        """3-D view of the whirl orbits of ``mode`` (1-based) along the shaft; returns the Axes."""
        from ..plotting.modes import plot_mode_orbits

        return plot_mode_orbits(self, mode, ax=ax, **kwargs)


def _circularise_pairs(lam, vec, names):
    """Rotate each double eigenvalue's two vectors into backward and forward circular whirl (backward first)."""
    pairs = station_pairs(names)
    if not pairs:
        return vec
    ix = np.array([p[1] for p in pairs])
    iy = np.array([p[2] for p in pairs])
    k = lam.size
    i = 0
    while i < k - 1:
        if abs(lam[i + 1] - lam[i]) > DOUBLE_RTOL * abs(lam[i]):
            i += 1
            continue
        V = vec[:, i:i + 2].copy()
        fwd = (V[ix] + 1j * V[iy]) / 2.0  # forward circle of each station, per basis vector
        bwd = (V[ix] - 1j * V[iy]) / 2.0
        combos = []
        for part in (fwd, bwd):  # kill the forward part -> backward vector, and vice versa
            _, s, vh = np.linalg.svd(part)  # vh is 2 x 2: its last row spans the (near) null space
            s = np.concatenate([s, np.zeros(2 - s.size)])
            combos.append(vh.conj()[-1] if s[-1] <= 1e-6 * max(s[0], 1e-300) else None)
        if all(c is not None for c in combos):
            vec[:, i] = V @ combos[0]
            vec[:, i + 1] = V @ combos[1]
        i += 2
    return vec


def modes_from_state_matrix(A, names, *, mass=None, left=True, n_modes=None, sparse=None, spectrum=None, **fields):
    """:class:`Modes` from a state matrix ``A = [[0, I], [-M^-1 K, -M^-1 C]]``.

    Parameters
    ----------
    A : numpy.ndarray, shape (2n, 2n)
    names : tuple of str, length n
    mass : numpy.ndarray, shape (n, n), optional
        ``M``, for the normalisation of the left shapes (default identity).
    left : bool
        Compute the left eigenvectors too.
    n_modes : int, optional
        Only the ``n_modes`` modes of smallest ``|lambda|``: for large models
        found by shift-invert Arnoldi iteration about 0
        (:func:`scipy.sparse.linalg.eigs`, a sparse LU of ``A``) instead of
        the full dense eigen-solution; :attr:`Modes.all_eigenvalues` then
        holds only the computed ones.
    sparse : bool, optional
        With ``n_modes``: True for the Arnoldi iteration, False for the
        dense eigenvalues (all of them) with the vectors of the ``n_modes``
        modes alone; None (default) chooses the Arnoldi iteration when
        more than :data:`DENSE_SIZE` coordinates and ``2 n > 4 n_modes + 20``.
    spectrum : numpy.ndarray of complex, shape (2n,), optional
        Every eigenvalue of ``A``, when already known (the dense solution
        with few vectors then computes the vectors alone).
    **fields
        Further :class:`Modes` fields (operating point, sample times, speed ...).

    Notes
    -----
    The dense solution computes the eigenvalues alone
    (:func:`numpy.linalg.eigvals`) and the vectors of the modes kept by
    inverse iteration (:func:`~rotorkit.linear.inverse_iteration.state_eigenvectors`)
    when they are few (``n_modes <= n / 5``: then cheaper than all the
    vectors); otherwise, with left vectors, :func:`scipy.linalg.eig` (left
    and right vectors in one solve) when scipy is imported already or
    ``n^4 > LEFT_ITERATION_WORK`` (about ``n > 119``), else every right
    vector by :func:`numpy.linalg.eig` and the left ones by inverse
    iteration: no 0.4 s import of :mod:`scipy.linalg` in a process that has
    no other use for it (``rotorkit modes FILE``). All agree with the full
    eigen-solution to rounding (``tests/test_inverse_iteration.py``).
    """
    n = len(names)
    n_modes = check_count(n_modes)
    if sparse is None:
        sparse = n_modes is not None and sparse_pays(n, n_modes)
    Mm = np.eye(n) if mass is None else np.asarray(mass, dtype=float)
    damping = (-A[n:, n:] if mass is None else Mm @ -A[n:, n:]) if left else None  # C: for the left shapes
    if sparse and n_modes is not None:
        eigenvalues, vr, wl = _lowest_eigenpairs(A, int(n_modes), left)
        index = oscillatory_order(eigenvalues)
        X, W = vr[:, index], None if wl is None else wl[:, index]
    elif n_modes is not None and _few(n_modes, n):
        from .inverse_iteration import state_eigenvectors

        eigenvalues = np.linalg.eigvals(A) if spectrum is None else np.asarray(spectrum, dtype=complex)
        index = oscillatory_order(eigenvalues)
        index = index[:_with_partner(eigenvalues[index], n_modes)]
        X = state_eigenvectors(A, eigenvalues[index], eigenvalues)
        W = state_eigenvectors(A, eigenvalues[index], eigenvalues, left=True) if left else None
    elif left and (float(n) ** 4 > LEFT_ITERATION_WORK or scipy_linalg_loaded()):  # scipy: both in one solve
        from scipy import linalg

        eigenvalues, wl, vr = linalg.eig(A, left=True, right=True)
        index = oscillatory_order(eigenvalues)
        X, W = vr[:, index], wl[:, index]
    else:
        eigenvalues, vr = np.linalg.eig(A)
        index = oscillatory_order(eigenvalues)
        X, W = vr[:, index], None
        if left:
            from .inverse_iteration import state_eigenvectors

            W = state_eigenvectors(A, eigenvalues[index], eigenvalues, left=True)
    Y = None
    if W is not None:  # the lower half of a left state vector is M^H y (y: left coordinate vector)
        Y = np.linalg.solve(Mm.conj().T, W[n:]) if mass is not None else W[n:]
    return _modes(eigenvalues, eigenvalues[index], X[:n], Y, names, Mm, damping, fields, n_modes)


#: models with at most this many coordinates solve all eigenvalues densely, also for a few modes (n_modes)
DENSE_SIZE = 100


def sparse_pays(n, n_modes):
    """Whether the ``n_modes`` lowest modes of ``n`` coordinates are solved by shift-invert Arnoldi iteration.

    For more than :data:`DENSE_SIZE` coordinates and ``2 n > 4 n_modes + 20``; below, the dense eigenvalues
    (milliseconds, no scipy import) with the vectors of the modes kept.
    """
    return n > DENSE_SIZE and 2 * n > 4 * int(n_modes) + 20


#: the dense solution finds the kept modes' vectors by inverse iteration when they are at most n / FEW_VECTORS
FEW_VECTORS = 5
#: left vectors of all modes by inverse iteration (no scipy) while n^4 (modes x the cost of a solve) is below
#: this, else scipy.linalg.eig: about n = 119
LEFT_ITERATION_WORK = 2e8


def scipy_linalg_loaded():
    """Whether :mod:`scipy.linalg` is imported already (then its eigen-solution with left vectors is the cheaper)."""
    import sys

    return "scipy.linalg" in sys.modules


def _few(n_modes, n):
    return int(n_modes) <= n // FEW_VECTORS


def oscillatory_order(eigenvalues):
    """Indices of the oscillatory eigenvalues (``Im(lambda) > OSCILLATORY_RTOL |lambda|``), by ascending ``|lambda|``.

    The modes of :class:`Modes`, in their order (a stable sort: equal moduli keep the solver's order).
    """
    eigenvalues = np.asarray(eigenvalues)
    index = np.flatnonzero(eigenvalues.imag > OSCILLATORY_RTOL * np.abs(eigenvalues))
    return index[np.argsort(np.abs(eigenvalues[index]), kind="stable")]


def double_pairs(lam):
    """Start indices ``i`` of the double eigenvalues ``(lam[i], lam[i + 1])`` of ascending ``lam``, as paired for
    the circular combinations (scanning up: a member of a pair is not paired again)."""
    pairs = []
    i = 0
    while i < lam.size - 1:
        if abs(lam[i + 1] - lam[i]) > DOUBLE_RTOL * abs(lam[i]):
            i += 1
            continue
        pairs.append(i)
        i += 2
    return pairs


def _with_partner(lam, n_modes):
    """``n_modes``, or one more when mode ``n_modes`` is the first member of a double eigenvalue (both are needed)."""
    k = min(int(n_modes), lam.size)
    return k + 1 if k < lam.size and k - 1 in double_pairs(lam[:k + 1]) else k


def modes_from_matrices(mass, damping, stiffness, names, *, left=True, n_modes=None, sparse=None, **fields):
    """:class:`Modes` of ``M q'' + C q' + K q = 0`` from its matrices.

    Parameters
    ----------
    mass, damping, stiffness : numpy.ndarray or scipy sparse matrix, shape (n, n)
        ``M``, ``C`` (damping plus speed-scaled gyroscopics) and ``K``
        (cross-coupled and circulatory parts included), SI units.
    names : tuple of str, length n
    left : bool
        Compute the left shapes too.
    n_modes : int, optional
        Only the ``n_modes`` modes of smallest ``|lambda|``. For large models
        (:func:`sparse_pays`: more than :data:`DENSE_SIZE` coordinates and
        ``2 n > 4 n_modes + 20``) they are found by shift-invert Arnoldi
        iteration (:func:`scipy.sparse.linalg.eigs`) on the pencil of the
        first-order form, each step one sparse LU solve with
        ``K + s C + s^2 M`` (``n x n``, factored once; the dense
        ``M^-1 K`` is never formed), so the cost grows with the bandwidth,
        not with ``n^3``. Otherwise, and when the iteration fails, they come
        from the dense eigen-solution of the state matrix
        (:func:`modes_from_state_matrix`).
    sparse : bool, optional
        As in :func:`modes_from_state_matrix`: False for the dense
        eigenvalues with the vectors of the ``n_modes`` modes alone.
    **fields
        Further :class:`Modes` fields.
    """
    n = len(names)
    n_modes = check_count(n_modes)
    dense = [np.asarray(A.toarray() if hasattr(A, "toarray") else A, dtype=float)
             for A in (mass, damping, stiffness)]
    if n_modes is not None and (sparse_pays(n, n_modes) if sparse is None else sparse):
        solved = _lowest_pencil_eigenpairs(mass, damping, stiffness, int(n_modes), left)
        if solved is not None:
            eigenvalues, X, Y = solved
            index = oscillatory_order(eigenvalues)
            return _modes(eigenvalues, eigenvalues[index], X[:, index], None if Y is None else Y[:, index], names,
                          dense[0], dense[1], fields, n_modes)
    M, C, K = dense
    A = state_matrix(M, C, K)
    return modes_from_state_matrix(A, names, mass=M, left=left, n_modes=n_modes, sparse=sparse, **fields)


def state_matrix(mass, damping, stiffness):
    """``A = [[0, I], [-M^-1 K, -M^-1 C]]`` (shape (2n, 2n)) of dense ``M``, ``C``, ``K`` (one LU of ``M``, numpy)."""
    M, C, K = (np.asarray(X, dtype=float) for X in (mass, damping, stiffness))
    n = M.shape[0]
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:] = -np.linalg.solve(M, np.hstack([K, C]))
    return A


def check_count(n_modes):
    if n_modes is None:
        return None
    if isinstance(n_modes, bool) or not isinstance(n_modes, numbers.Integral) or n_modes < 1:
        raise ParameterError(f"n_modes={n_modes!r} is invalid: expected an integer >= 1 or None (all modes)")
    return int(n_modes)


def _modes(eigenvalues, lam, vec, Y, names, M, C, fields, n_modes=None):
    """:class:`Modes` from the oscillatory eigenvalues ``lam`` (ascending ``|lambda|``, as
    :func:`oscillatory_order`) with right (and left) coordinate vectors of ``lambda^2 M + lambda C + K``.

    ``eigenvalues``: every computed one (:attr:`Modes.all_eigenvalues`). ``n_modes``: keep the lowest
    ``n_modes`` modes (the sparse solvers compute a few more to converge, and the dense one may give all of
    them, or the ``n_modes`` and the partner of a double one).
    """
    n = len(names)
    vec = np.array(vec, dtype=complex)
    vec = _circularise_pairs(lam, vec, names)
    if n_modes is not None:  # after the circular combinations, which need both members of a double root
        lam, vec = lam[:n_modes], vec[:, :n_modes]
        Y = None if Y is None else Y[:, :n_modes]
    k = lam.size
    shapes = np.empty((n, k), dtype=complex)
    for i in range(k):
        v = vec[:, i]
        shapes[:, i] = v / v[int(np.argmax(np.abs(v)))]
    left_shapes = None
    if Y is not None:
        left_shapes = np.empty((n, k), dtype=complex)
        i = 0
        while i < k:
            N = 2.0 * lam[i] * M + C
            width = 2 if i + 1 < k and abs(lam[i + 1] - lam[i]) <= DOUBLE_RTOL * abs(lam[i]) else 1
            Xi, Yi = shapes[:, i:i + width], Y[:, i:i + width]
            P = Yi.conj().T @ N @ Xi  # bi-orthonormalise within a double root's eigenspace
            try:
                left_shapes[:, i:i + width] = Yi @ np.linalg.inv(P).conj().T
            except np.linalg.LinAlgError:
                left_shapes[:, i:i + width] = np.nan  # defective (coalescing) eigenvalue
            i += width
    frequencies = np.abs(lam)
    damping = -lam.real / frequencies if k else np.empty(0)
    fields = dict(fields)
    fields.setdefault("frequency_range", np.column_stack([frequencies, frequencies]) if k else np.empty((0, 2)))
    fields.setdefault("sample_times", np.array([0.0]))
    fields.setdefault("operating_point", np.zeros(n))
    return Modes(
        frequencies=_readonly(frequencies),
        damping_ratios=_readonly(damping),
        eigenvalues=_readonly(lam),
        shapes=_readonly(shapes),
        coordinate_names=tuple(names),
        all_eigenvalues=_readonly(eigenvalues[np.argsort(np.abs(eigenvalues), kind="stable")]),
        left_shapes=None if left_shapes is None else _readonly(left_shapes),
        **{key: (_readonly(v) if isinstance(v, np.ndarray) else v) for key, v in fields.items()},
    )


def _lowest_eigenpairs(A, n_modes, left):
    """Eigenvalues of smallest modulus, right (and left) vectors, by shift-invert Arnoldi about 0."""
    from scipy import sparse
    from scipy.sparse.linalg import eigs

    k = min(2 * n_modes + 4, A.shape[0] - 2)
    S = sparse.csc_matrix(A)
    lam, vr = eigs(S, k=k, sigma=0.0, which="LM")
    wl = None
    if left:
        mu, wv = eigs(S.T.tocsc(), k=k, sigma=0.0, which="LM")
        wl = np.empty_like(vr)
        for i, value in enumerate(lam):  # left vector of lambda: eigenvector of A^T for lambda, conjugated
            wl[:, i] = np.conj(wv[:, int(np.argmin(np.abs(mu - value)))])
    return lam, vr, wl


def _pencil_operator(M, C, K):
    """``(op, shift)``: ``z -> (A - s B)^-1 B z`` for ``A = [[0, I], [-K, -C]]``, ``B = diag(I, M)``.

    Eigenvalues ``mu`` of the operator give ``lambda = s + 1 / mu`` with the
    same eigenvectors ``[x, lambda x]``. The shift ``s`` is 0 unless ``K``
    is singular (a free rigid-body coordinate), then a small negative number.
    """
    from scipy import sparse
    from scipy.sparse.linalg import LinearOperator, splu

    n = M.shape[0]
    M, C, K = (sparse.csc_matrix(A) for A in (M, C, K))
    scale = math.sqrt(max(abs(K.diagonal()).max(), 1e-300) / max(abs(M.diagonal()).max(), 1e-300))
    for shift in (0.0, -1e-3 * scale, -1e-1 * scale):
        try:
            with np.errstate(all="ignore"):
                lu = splu((K + shift * C + shift * shift * M).tocsc())
        except RuntimeError:  # exactly singular
            continue
        if np.all(np.isfinite(lu.U.diagonal())) and np.min(np.abs(lu.U.diagonal())) > 1e-13 * np.max(
                np.abs(lu.U.diagonal())):
            break
    else:
        return None
    CsM = (C + shift * M).tocsr()
    M = M.tocsr()

    def matvec(z):
        z = np.asarray(z).reshape(-1)
        a, b = z[:n], M @ z[n:]
        u = lu.solve(np.asarray(-b - CsM @ a))
        return np.concatenate([u, a + shift * u])

    dtype = np.result_type(M.dtype, C.dtype, K.dtype)
    return LinearOperator((2 * n, 2 * n), matvec=matvec, dtype=dtype), shift


def _lowest_pencil_eigenpairs(M, C, K, n_modes, left):
    """``(eigenvalues, X, Y)`` of the ``2 n_modes + 4`` smallest ``|lambda|``, or None if the iteration fails.

    ``X`` holds right coordinate vectors, ``Y`` left ones (``y^H (lambda^2 M
    + lambda C + K) = 0``: right vectors of the transposed problem, conjugated).
    """
    from scipy.sparse.linalg import ArpackError, ArpackNoConvergence, eigs

    n = M.shape[0]
    k = min(2 * n_modes + 4, 2 * n - 2)

    def solve(M, C, K):
        built = _pencil_operator(M, C, K)
        if built is None:
            return None
        op, shift = built
        for ncv in (None, min(2 * n, 4 * k + 20)):
            try:
                mu, z = eigs(op, k=k, which="LM", ncv=ncv, maxiter=20 * 2 * n)
            except (ArpackNoConvergence, ArpackError):
                continue
            with np.errstate(divide="ignore"):
                return shift + 1.0 / mu, z[:n]
        return None

    right = solve(M, C, K)
    if right is None:
        return None
    lam, X = right
    Y = None
    if left:
        transposed = solve(M.T, C.T, K.T)
        if transposed is None:
            return None
        mu, Z = transposed
        Y = np.empty_like(X)
        for i, value in enumerate(lam):
            Y[:, i] = np.conj(Z[:, int(np.argmin(np.abs(mu - value)))])
    return lam, X, Y
