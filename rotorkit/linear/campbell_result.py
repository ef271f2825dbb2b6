"""The result of a Campbell diagram: tracked modes against speed, critical speeds and instability onsets.

:class:`Campbell` holds the tracked modes of :func:`~rotorkit.linear.campbell.campbell` (frequencies, log
decrements, whirl per speed and mode), the :class:`CriticalSpeed` crossings of the excitation lines and the
:class:`InstabilityOnset` points, with their text table, CSV, xarray and plot outputs.
:func:`neutral_tolerance` is the log decrement below which a mode counts as undamped (no onset).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .modal_result import frequency_factor, unit_slug
from .tables import csv_output

__all__ = ["Campbell", "CriticalSpeed", "InstabilityOnset", "EIGENVALUE_ROUNDING", "NEUTRAL_LOG_DECREMENT",
           "neutral_tolerance"]

#: log decrements within this of zero are a neutral (undamped) mode, whatever the problem (the floor of
#: :func:`neutral_tolerance`)
NEUTRAL_LOG_DECREMENT = 1e-8
#: relative rounding of an eigenvalue's real part, in units of the largest eigenvalue modulus of the problem
EIGENVALUE_ROUNDING = 1e3 * np.finfo(float).eps


def neutral_tolerance(eigenvalues, spectral_radius):
    """Log decrements below this in magnitude are rounding noise of the eigen-solution, not damping.

    A backward-stable eigen-solver gives ``Re(lambda)`` to about ``eps``
    times the largest eigenvalue modulus ``rho`` of the state matrix (times
    a modest condition number), so the log decrement
    ``-2 pi Re(lambda) / Im(lambda)`` of an undamped mode comes out as
    ``+-2 pi eps rho / Im(lambda)`` or so: large for low modes of a stiff
    finite-element model. The tolerance is::

        max(NEUTRAL_LOG_DECREMENT, 2 pi EIGENVALUE_ROUNDING rho / |Im(lambda)|)

    with ``EIGENVALUE_ROUNDING = 1000 eps`` (``2.2e-13``) and
    ``NEUTRAL_LOG_DECREMENT = 1e-8``.

    Parameters
    ----------
    eigenvalues : numpy.ndarray of complex
        The modes' eigenvalues (1/s).
    spectral_radius : float or numpy.ndarray
        Largest ``|lambda|`` (1/s) of the eigen-problem they come from
        (broadcast against ``eigenvalues``).

    Returns
    -------
    numpy.ndarray
        Same shape as ``eigenvalues``.
    """
    lam = np.asarray(eigenvalues, dtype=complex)
    with np.errstate(divide="ignore", invalid="ignore"):
        scaled = 2.0 * np.pi * EIGENVALUE_ROUNDING * np.asarray(spectral_radius, dtype=float) / np.abs(lam.imag)
    return np.fmax(NEUTRAL_LOG_DECREMENT, np.nan_to_num(scaled, nan=NEUTRAL_LOG_DECREMENT, posinf=np.inf))



@dataclass(frozen=True, slots=True)
class CriticalSpeed:
    """Where an excitation line meets a tracked mode.

    Attributes
    ----------
    rotor : str
    order : float
        Excitation order (1 for unbalance).
    mode : int
        Tracked mode number (1-based).
    speed : float
        Swept speed (rad/s).
    frequency : float
        Damped natural frequency there (rad/s) = ``order x`` the rotor's spin.
    whirl : str
        The mode's whirl there.
    """

    rotor: str
    order: float
    mode: int
    speed: float
    frequency: float
    whirl: str


@dataclass(frozen=True, slots=True)
class InstabilityOnset:
    """Speed (rad/s) where tracked ``mode``'s log decrement crosses zero, and its frequency there."""

    mode: int
    speed: float
    frequency: float
    whirl: str
    becomes: str  # "unstable" or "stable"


@dataclass(frozen=True, slots=True, eq=False)
class Campbell:
    """Tracked modes against a swept rotor speed.

    Attributes
    ----------
    speeds : numpy.ndarray, shape (n_speeds,)
        Values of :attr:`speed_parameter` (rad/s).
    frequencies : numpy.ndarray, shape (n_speeds, n_modes)
        Damped natural frequencies ``Im(lambda)`` (rad/s) of the tracked
        modes (column ``k`` is mode ``k + 1``, numbered by frequency at the
        first speed); NaN where a mode is lost.
    natural_frequencies : numpy.ndarray, shape (n_speeds, n_modes)
        ``|lambda|`` (rad/s).
    damping_ratios, log_decrements : numpy.ndarray, shape (n_speeds, n_modes)
    whirl : numpy.ndarray of str, shape (n_speeds, n_modes)
        ``"forward"``, ``"backward"``, ``"mixed"`` or ``"linear"``.
    rotor_speeds : dict of str to numpy.ndarray, shape (n_speeds,)
        Rotor name -> its spin speed (rad/s): the 1x lines.
    speed_parameter : str
    orders : tuple of float
        Excitation orders drawn and searched (default 1x).
    crossings : tuple of CriticalSpeed
        Located by root finding, by speed.
    onsets : tuple of InstabilityOnset
        Located by root finding, by speed.
    neutral_log_decrements : numpy.ndarray, shape (n_speeds, n_modes), optional
        Log decrements smaller than this in magnitude are taken as zero
        (rounding noise of an undamped mode, :func:`neutral_tolerance`): no
        onset is reported where a log decrement only changes sign within it.
    """

    speeds: np.ndarray
    frequencies: np.ndarray
    natural_frequencies: np.ndarray
    damping_ratios: np.ndarray
    log_decrements: np.ndarray
    whirl: np.ndarray
    rotor_speeds: dict
    speed_parameter: str
    orders: tuple = (1.0,)
    crossings: tuple = ()
    onsets: tuple = ()
    neutral_log_decrements: np.ndarray | None = None

    @property
    def n_modes(self):
        return int(self.frequencies.shape[1])

    def critical_speeds(self, rotor=None, order=None):
        """The :class:`CriticalSpeed` list, optionally of one rotor and/or one order."""
        if rotor is not None and rotor not in self.rotor_speeds:
            raise ParameterError(f"rotor={rotor!r} is unknown; rotors: {', '.join(self.rotor_speeds)}")
        return [c for c in self.crossings if (rotor is None or c.rotor == rotor)
                and (order is None or c.order == order)]

    @property
    def instability_onset(self):
        """Lowest swept speed (rad/s) where a mode becomes unstable, or None."""
        ups = [o.speed for o in self.onsets if o.becomes == "unstable"]
        tol = 0.0 if self.neutral_log_decrements is None else self.neutral_log_decrements[0]
        if not ups and np.any(self.log_decrements[0] < -tol):
            return float(self.speeds[0])
        return min(ups) if ups else None

    def table(self, units="rad/s"):
        """Critical speeds and instability onsets as plain text."""
        f = frequency_factor(units)
        head = f"{'rotor':>6}  {'order':>5}  {'mode':>4}  {f'speed ({units})':>14}  {f'frequency ({units})':>18}  whirl"
        lines = ["critical speeds", head, "-" * len(head)]
        for c in self.crossings:
            lines.append(f"{c.rotor:>6}  {c.order:>5g}  {c.mode:>4}  {c.speed * f:>14.6g}  {c.frequency * f:>18.6g}  "
                         f"{c.whirl}")
        if self.onsets:
            lines.append("instability onsets (log decrement crosses 0)")
            for o in self.onsets:
                lines.append(f"mode {o.mode}: {o.becomes} above {o.speed * f:.6g} {units} "
                             f"({o.whirl}, {o.frequency * f:.6g} {units})")
        return "\n".join(lines)

    def to_csv(self, path=None, *, units="rad/s"):
        """One row per speed: speed, each rotor's spin, each mode's damped frequency, log dec and whirl.

        ``path`` (None: the text) and ``units`` as for every linear result
        (:func:`~rotorkit.analysis.tables.csv_output`).
        """
        f = frequency_factor(units)
        u = unit_slug(units)
        cols = [f"{self.speed_parameter}_{u}"] + [f"{r}_spin_{u}" for r in self.rotor_speeds]
        for k in range(self.n_modes):
            cols += [f"mode{k + 1}_frequency_{u}", f"mode{k + 1}_log_decrement", f"mode{k + 1}_whirl"]
        rows = [",".join(cols)]
        for i, w in enumerate(self.speeds):
            vals = [f"{w * f:.10g}"] + [f"{line[i] * f:.10g}" for line in self.rotor_speeds.values()]
            for k in range(self.n_modes):
                vals += [f"{self.frequencies[i, k] * f:.10g}", f"{self.log_decrements[i, k]:.10g}",
                         str(self.whirl[i, k])]
            rows.append(",".join(vals))
        return csv_output("\n".join(rows) + "\n", path)

    def to_xarray(self, units="rad/s"):
        """The diagram as an :class:`xarray.Dataset` over (speed, mode), CF-style ``units``/``long_name``."""
        import xarray as xr

        f = frequency_factor(units)
        speed = xr.Variable("speed", self.speeds * f, {"units": units, "long_name": self.speed_parameter})
        modes = np.arange(1, self.n_modes + 1)
        data = {
            "frequency": (("speed", "mode"), self.frequencies * f,
                          {"units": units, "long_name": "damped natural frequency"}),
            "natural_frequency": (("speed", "mode"), self.natural_frequencies * f,
                                  {"units": units, "long_name": "natural frequency |lambda|"}),
            "damping_ratio": (("speed", "mode"), np.asarray(self.damping_ratios), {"units": "1"}),
            "log_decrement": (("speed", "mode"), np.asarray(self.log_decrements),
                              {"units": "1", "long_name": "logarithmic decrement"}),
            "whirl": (("speed", "mode"), np.asarray(self.whirl, dtype=str)),
        }
        for rotor, line in self.rotor_speeds.items():
            data[f"{rotor}_spin"] = ("speed", line * f, {"units": units, "long_name": f"spin speed of {rotor}"})
        return xr.Dataset(data, coords={"speed": speed, "mode": modes})

    def plot(self, ax=None, **kwargs):
        """Draw the Campbell diagram (:func:`rotorkit.plotting.campbell.plot_campbell`); returns the Axes."""
        from ..plotting.campbell import plot_campbell

        return plot_campbell(self, ax=ax, **kwargs)

    def plot_stability(self, ax=None, **kwargs):
        """Log decrement against speed (:func:`rotorkit.plotting.campbell.plot_log_decrement`)."""
        from ..plotting.campbell import plot_log_decrement

        return plot_log_decrement(self, ax=ax, **kwargs)

