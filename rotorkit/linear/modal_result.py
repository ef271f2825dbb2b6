"""The result of a modal analysis: :class:`Modes` (frequencies, damping, whirl, shapes) and its outputs.

:class:`Modes` holds the modes :mod:`rotorkit.linear.modal` solves, with the quantities derived from them
(damped frequencies, log decrements, whirl per station, orbits, dominant coordinates) and their outputs:
text table, CSV, data frame and plots. :func:`frequency_factor` and :func:`unit_slug` convert rad/s to an
output unit and name its columns, for every linear result.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .tables import DEFAULT_TABLE_MODES, csv_output
from .whirl import orbit, reference_length, shape_whirl, slope_orbit, station_pairs, tilt_pairs

__all__ = ["Modes", "frequency_factor", "unit_slug"]


def frequency_factor(units, name="units"):
    """Factor from rad/s to the output ``units`` (``"rad/s"``, ``"Hz"``, ``"rpm"`` or another angular speed).

    See :func:`rotorkit.units.display_factor`; Hz and rpm count cycles (1 Hz = 2 pi rad/s).
    """
    from ..units import display_factor

    return display_factor(units, "speed", name)


def unit_slug(units):
    """A unit as a column-name suffix: ``"rad/s"`` -> ``"rad_s"``, ``"rpm"`` -> ``"rpm"``."""
    return "".join(c if c.isalnum() else "_" for c in str(units).replace("**", "")).strip("_")



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

