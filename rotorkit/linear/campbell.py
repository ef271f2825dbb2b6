"""Campbell and stability diagrams: modes tracked across speed, critical speeds, instability onset.

:func:`campbell` solves the modes at each speed of a grid, either of a
:class:`~rotorkit.analysis.linear_model.LinearModel` (one eigen-solution
per speed) or of a compiled system: a linear one has its matrices
evaluated at each speed from the derived symbolic ones (speed-dependent
bearings exactly), one with contacts is linearised once (or, on request,
at every speed). Modes are tracked
from one speed to the next by the modal assurance criterion (MAC) of their
shapes, ``|a^H b|^2 / (|a|^2 |b|^2)``, with an optimal assignment
(:func:`rotorkit.analysis.roots.assignment`), not by sorting frequencies:
a forward and a backward mode that cross keep their identity (their
circular shapes are orthogonal). At each speed every eigenvalue is
computed but, for a dense model, the shapes of the modes near the tracked
ones in frequency alone (inverse iteration,
:mod:`rotorkit.linear.inverse_iteration`); where the assignment could still
pick a mode left out (bounded by the frequency part of its cost), the
shapes of all: the diagram is the one all shapes give.

On every grid interval where a tracked damped frequency crosses an
excitation line ``order x spin speed`` of a rotor, the critical speed is
located by Brent's method on the re-solved (and re-tracked) mode; the same
for the instability onset, where a mode's logarithmic decrement crosses
zero.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .modal import frequency_factor, unit_slug
from .tables import csv_output

__all__ = ["Campbell", "CriticalSpeed", "InstabilityOnset", "campbell", "mac", "neutral_tolerance"]

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


def mac(a, b):
    """Modal assurance criterion matrix ``|a_i^H b_j|^2 / (|a_i|^2 |b_j|^2)`` of shape columns."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / den, 0.0)


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


# ---------------------------------------------------------------------------
# Solving modes at a speed
# ---------------------------------------------------------------------------


def _resolve_system(source, backend):
    """A System or LinearModel from a System, a Model, a preset name or a builder."""
    from .linear_model import LinearModel

    if isinstance(source, LinearModel):
        return source
    if isinstance(source, str):
        from ..presets import preset

        source = preset(source)
    elif callable(source) and not hasattr(source, "rhs") and not hasattr(source, "compile"):
        source = source()
    if hasattr(source, "rhs") or hasattr(source, "compile"):
        return source  # a model is compiled only if it needs linearising (see _solver)
    raise TypeError(
        f"campbell: expected a LinearModel, a System, a Model, a preset name or a function returning one of "
        f"them, got {type(source).__name__}"
    )


def _solver(target, speed_parameter, options, n_modes=None, relinearize=False, speeds=None, backend="auto"):
    """(modes_at(speed, vectors=None), spins_at(speed), parameter name) for a LinearModel, a System or a Model.

    ``modes_at(speed, vectors)`` gives every eigenvalue and, where it can
    (a linear model of at most :data:`~rotorkit.linear.modal.DENSE_SIZE` coordinates), the shapes of
    the ``vectors`` lowest modes alone (None: of all).
    """
    from .linear_model import LinearModel, frozen_system, linear_model
    from .modal import DENSE_SIZE, FEW_VECTORS, modes_from_matrices, modes_from_state_matrix, state_matrix

    def sparse_count(n):
        return int(n_modes) + 4 if n_modes is not None and n > DENSE_SIZE else None  # sparse solve for big models

    def dense_modes(state_at, names, positions):
        """modes_at(w, vectors) of a dense state matrix; a speed asked again (more vectors) reuses its eigenvalues."""
        last = {}

        def modes_at(w, vectors=None):
            w = float(w)
            if vectors is not None and vectors > len(names) // FEW_VECTORS:
                vectors = None  # as many as that: every vector at once is cheaper (and certain)
            if last.get("speed") != w:
                last.clear()
                last["speed"], last["A"] = w, state_at(w)
            modes = modes_from_state_matrix(last["A"], names, left=False, n_modes=vectors, sparse=False,
                                            spectrum=last.get("spectrum"), speed=w, station_positions=positions)
            last["spectrum"] = modes.all_eigenvalues
            return modes

        return modes_at

    if isinstance(target, LinearModel):
        wanted = sparse_count(target.n)
        dense_at = dense_modes(target.state_matrix, target.coordinate_names, target.station_positions)

        def linear_modes_at(w, vectors=None):
            if wanted:
                return target.modes(w, left=False, n_modes=wanted)
            return dense_at(w, vectors)

        linear_modes_at.matrices = target.matrices  # dense (M, C, K) at a speed: the refinement's Newton steps
        return linear_modes_at, target.spin_speeds, target.speed_parameter
    from .linear_matrices import linear_evaluator, rotor_spin_speeds, station_positions
    from .modes import natural_frequencies

    t = options["t"]
    model, speed_parameter = frozen_system(target, speed_parameter, None, t, who="campbell")
    values = model.parameters

    def spins_at(w):
        return rotor_spin_speeds(model, t, dict(values, **{speed_parameter: float(w)}))

    evaluator = None if relinearize else linear_evaluator(model, t, values, free=(speed_parameter,))
    if evaluator is not None:  # linear equations: numbers per speed, no linearisation
        names, positions = tuple(model.coordinate_names), station_positions(model)
        wanted = sparse_count(len(names))

        def matrices_at(w):
            return evaluator.dense(**{speed_parameter: float(w)})

        dense_at = dense_modes(lambda w: state_matrix(*matrices_at(w)), names, positions)

        def modes_at(w, vectors=None):
            if wanted:
                M, C, K = evaluator(**{speed_parameter: float(w)})
                return modes_from_matrices(M, C, K, names, left=False, n_modes=wanted, speed=float(w),
                                           station_positions=positions)
            return dense_at(w, vectors)

        modes_at.matrices = matrices_at
        return modes_at, spins_at, speed_parameter
    source = getattr(target, "model", target)
    system = target if model is source and hasattr(target, "rhs") else model.compile(
        backend=getattr(target, "backend", backend))
    if not relinearize:  # contacts, Hertzian bearings: one linear model about the middle of the range
        middle = 0.5 * (float(speeds[0]) + float(speeds[-1]))
        linear = linear_model(system, speed_parameter=speed_parameter, speed=middle,
                              **{k: v for k, v in options.items() if k != "unbalance"})
        return _solver(linear, speed_parameter, options, n_modes)[0], spins_at, speed_parameter

    def relinearized_modes_at(w, vectors=None):
        return natural_frequencies(system.with_parameters(**{speed_parameter: float(w)}), **options)

    return relinearized_modes_at, spins_at, speed_parameter


#: the shapes computed at a speed: those of the modes whose damped frequency was within this factor of the
#: highest tracked one at the previous speed (at least the tracked ones and EXTRA_SHAPES more); all of them when
#: the tracking could still pick a mode beyond
FREQUENCY_REACH = 1.25
EXTRA_SHAPES = 2


def _match(previous_shapes, previous_freqs, modes, count):
    """Columns of ``modes`` continuing the tracked shapes (MAC, ties broken by frequency), and whether certain.

    Certain: the modes of ``modes`` are all the oscillatory ones, or no assignment that takes one of those
    left out (whose shapes were not computed) could cost less: each cost is ``1 - MAC`` (>= 0) plus
    ``0.1 min(relative frequency distance, 10)``, the latter known from the eigenvalues alone.
    """
    from .modal import oscillatory_order
    from .roots import assignment

    k = len(modes)
    spectrum = modes.all_eigenvalues
    outside = spectrum[oscillatory_order(spectrum)][k:].imag  # oscillatory modes without a computed shape
    if previous_shapes is None:
        return list(range(min(count, k))), k >= count or outside.size == 0
    rows_n = previous_shapes.shape[1]
    if k == 0:
        return [None] * rows_n, outside.size == 0
    M = mac(previous_shapes, modes.shapes)
    cost = (1.0 - M) + 0.1 * _frequency_cost(modes.damped_frequencies, previous_freqs)
    rows, cols = assignment(cost)
    out = [None] * rows_n
    for r, c in zip(rows, cols):
        out[r] = int(c)
    if outside.size == 0:
        return out, True
    if k < rows_n:
        return out, False
    best = float(cost[rows, cols].sum())
    row_min = cost.min(axis=1)
    beyond = 0.1 * _frequency_cost(outside, previous_freqs).min(axis=1)  # the least any left-out mode costs
    return out, bool(row_min.sum() + np.min(beyond - row_min) > best)


def _frequency_cost(frequencies, previous_freqs):
    """``min(|f - f_prev| / |f_prev|, 10)`` (NaN: 10), shape (len(previous_freqs), len(frequencies))."""
    with np.errstate(invalid="ignore", divide="ignore"):
        rel = np.abs(frequencies[None, :] - previous_freqs[:, None]) / np.maximum(
            np.abs(previous_freqs[:, None]), 1e-300)
    return np.nan_to_num(np.minimum(rel, 10.0), nan=10.0)


def _solve_matched(modes_at, speed, previous_shapes, previous_freqs, count, previous_spectrum=None):
    """``(modes, columns)`` at ``speed``: the shapes of the lowest modes, as many as the tracking needs.

    The modes that can continue the tracked ones lie near them in frequency: shapes are computed for those
    within :data:`FREQUENCY_REACH` of the highest tracked frequency at the previous speed (whose spectrum
    ``previous_spectrum`` predicts the count), and for all modes where :func:`_match` cannot rule out that a
    mode left out would be picked.
    """
    from .modal import oscillatory_order

    if previous_shapes is None:
        vectors = count
    else:
        vectors = count + EXTRA_SHAPES
        if previous_spectrum is not None and np.any(np.isfinite(previous_freqs)):
            lam = previous_spectrum[oscillatory_order(previous_spectrum)]
            reach = FREQUENCY_REACH * float(np.nanmax(np.abs(previous_freqs)))
            vectors = max(vectors, int(np.count_nonzero(lam.imag <= reach)) + 1)
    modes = modes_at(speed, vectors)
    cols, certain = _match(previous_shapes, previous_freqs, modes, count)
    if certain or len(modes) < vectors:  # len < vectors: every oscillatory mode is there
        return modes, cols
    modes = modes_at(speed, None)
    return modes, _match(previous_shapes, previous_freqs, modes, count)[0]


#: most speeds a Campbell diagram is computed at
MAX_SPEEDS = 100_000


def _check_speeds(speeds):
    from ..units import to_si_array

    w = to_si_array(speeds, "rad/s", "speeds")
    if w.size > MAX_SPEEDS:  # each speed is an eigen-solution (and a linearisation): bounded before any work
        raise ParameterError(f"speeds: {w.size} speeds, more than the {MAX_SPEEDS} a diagram takes (each one an "
                             "eigen-solution of the model; about a millisecond or more each): give fewer speeds")
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)):
        raise ParameterError(f"speeds has shape {w.shape}: expected a non-empty 1-D array of finite speeds (rad/s)")
    if w.size > 1 and np.any(np.diff(w) <= 0):
        raise ParameterError("speeds must increase strictly (rad/s)")
    return w


def campbell(model_or_preset_builder, speeds, *, n_modes=6, speed_parameter=None, orders=(1.0,), refine=True,
             t=0.0, equilibrium=True, rub_engaged=None, unbalance=False, cage_samples=None, method="auto",
             backend="auto", xtol=None, relinearize=False):
    """Modes tracked across speeds, critical speeds and instability onsets.

    Parameters
    ----------
    model_or_preset_builder : LinearModel, System, Model, str or callable
        A linear model (its ``G`` and ``H`` scale with the speed); or a
        compiled system, a model (compiled with ``backend``), a preset name
        or a function of no arguments returning one. A system whose
        equations are linear in the coordinates and their rates (beams,
        disks, linear bearings, speed-dependent ones included) has its
        matrices evaluated from the derived symbolic ones at each speed
        (:func:`~rotorkit.analysis.linear_matrices.linear_evaluator`: no
        linearisation). A system with contacts or Hertzian bearings is
        linearised once, at its static equilibrium about the middle of the
        speed range (:func:`~rotorkit.analysis.linear_model.linear_model`:
        exact gyroscopics, first order in the speed otherwise), or at every
        speed with ``relinearize=True``
        (:func:`~rotorkit.analysis.modes.natural_frequencies`). A rotor with
        a speed profile is swept by ``<rotor>_speed`` like a constant one.
    speeds : array_like, pint.Quantity or sequence of str, shape (n_speeds,)
        Increasing values of the swept speed: rad/s as plain numbers, or
        with their unit (``Q_(np.linspace(0, 15000, 31), "rpm")``,
        ``["0 rpm", "3000 rpm"]``).
    n_modes : int
        Number of modes tracked (the lowest ``n_modes`` at the first speed).
    speed_parameter : str, optional
        For a system: the swept ``<rotor>_speed`` (default the first rotor's,
        ``"LP_speed"`` for the AL-31F preset); rotors given by a speed ratio
        follow it.
    orders : sequence of float
        Excitation orders whose lines are searched for crossings (1x default).
    refine : bool
        Locate crossings and onsets by root finding (False: linear
        interpolation between grid points).
    t, equilibrium, rub_engaged, unbalance, cage_samples, method
        As in :func:`~rotorkit.analysis.modes.natural_frequencies` (systems only).
    backend : {"auto", "c", "numba", "python"}
        Used only when a model has to be compiled.
    xtol : float, str or pint.Quantity, optional
        Absolute tolerance (rad/s) of the located speeds (default 1e-9 of the
        speed range).
    relinearize : bool
        For a system that is not linear: re-linearise it at every speed
        (slow: an equilibrium and a Jacobian per speed and per root-finding
        step) instead of once.

    Returns
    -------
    Campbell

    Examples
    --------
    >>> from rotorkit import Rotor, Disk, ElasticSupport, Model
    >>> model = Model([Rotor(name="R", stations=(1,), speed=0.0),
    ...                Disk(station=1, mass=2.0, radius=0.1),
    ...                ElasticSupport(station=1, stiffness=2e4)])
    >>> c = campbell(model, [0.0, 50.0, 150.0], n_modes=2, speed_parameter="R_speed", backend="python")
    >>> c.frequencies.round(6).tolist()
    [[100.0, 100.0], [100.0, 100.0], [100.0, 100.0]]
    >>> [(x.rotor, x.mode, round(x.speed, 6), x.whirl) for x in c.critical_speeds()]
    [('R', 1, 100.0, 'backward'), ('R', 2, 100.0, 'forward')]
    """
    from .eigenpair import follow_mode
    from .roots import brent
    from .whirl import shape_whirl

    from .modes import DEFAULT_CAGE_SAMPLES

    from ..units import to_si

    w = _check_speeds(speeds)  # first: a count beyond the bound is refused before any compilation
    target = _resolve_system(model_or_preset_builder, backend)
    t = to_si(t, "s", "t")
    if isinstance(n_modes, bool) or not isinstance(n_modes, numbers.Integral) or n_modes < 1:
        raise ParameterError(f"n_modes={n_modes!r} is invalid: expected an integer >= 1")
    try:
        orders = tuple(float(o) for o in orders)
    except (TypeError, ValueError):
        raise ParameterError(f"orders={orders!r} is invalid: expected a sequence of positive numbers") from None
    if not orders or any(not (math.isfinite(o) and o > 0) for o in orders):
        raise ParameterError(f"orders={orders!r} is invalid: expected positive excitation orders, e.g. (1, 2)")
    options = dict(t=t, equilibrium=equilibrium, rub_engaged=rub_engaged, unbalance=unbalance,
                   cage_samples=DEFAULT_CAGE_SAMPLES if cage_samples is None else cage_samples, method=method)
    if not isinstance(relinearize, bool):
        raise ParameterError(f"relinearize={relinearize!r} is invalid: expected True or False")
    modes_at, spins_at, speed_parameter = _solver(target, speed_parameter, options, n_modes, relinearize, w, backend)

    count = int(n_modes)
    shape = (w.size, count)
    lam = np.full(shape, np.nan + 0j)
    whirl = np.full(shape, "", dtype=object)
    tracked_shapes = []  # per speed: (n, count) shapes of the tracked modes
    radius = np.zeros(w.size)  # largest |lambda| of each speed's eigen-problem
    prev_shapes = prev_freqs = None
    lines = None
    spectra = []  # per speed: every eigenvalue (the gaps that keep a Newton refinement on its mode)
    for i, speed in enumerate(w):
        modes, cols = _solve_matched(modes_at, float(speed), prev_shapes, prev_freqs, count,
                                     spectra[-1] if spectra else None)
        radius[i] = float(np.max(np.abs(modes.all_eigenvalues))) if modes.all_eigenvalues.size else 0.0
        if prev_shapes is None:
            count = len(cols)
            lam, whirl = lam[:, :count], whirl[:, :count]
            if count == 0:
                raise ParameterError("campbell: the system has no oscillatory mode at the first speed")
        spectra.append(modes.all_eigenvalues)
        kinds = _whirl_of_columns(modes, cols)
        shapes = np.array(prev_shapes, dtype=complex) if prev_shapes is not None else np.empty(
            (len(modes.coordinate_names), count), dtype=complex)
        freqs = np.array(prev_freqs) if prev_freqs is not None else np.empty(count)
        for k, c in enumerate(cols):
            if c is None:
                continue
            lam[i, k] = modes.eigenvalues[c]
            whirl[i, k] = kinds[c]
            shapes[:, k] = modes.shapes[:, c]
            freqs[k] = modes.eigenvalues[c].imag
        prev_shapes, prev_freqs = shapes, freqs
        tracked_shapes.append(shapes.copy())
        spins = spins_at(float(speed))
        if lines is None:
            lines = {name: np.empty(w.size) for name in spins}
        for name, value in spins.items():
            lines[name][i] = value

    names = tuple(modes.coordinate_names)
    positions = modes.station_positions
    damped = lam.imag
    logdec = -2.0 * np.pi * lam.real / lam.imag
    span = float(w[-1] - w[0]) if w.size > 1 else 1.0
    xtol = 1e-9 * max(span, 1.0) if xtol is None else to_si(xtol, "rad/s", "xtol", sign="positive")

    matrices_at = getattr(modes_at, "matrices", None)

    def tracked(k, j, speed):
        """Eigenvalue and whirl of tracked mode k at ``speed``, continued from grid point j."""
        if matrices_at is not None and j + 1 < w.size:  # Newton from the grid: no full eigen-solution
            followed = follow_mode(matrices_at, lam[j, k], lam[j + 1, k], tracked_shapes[j][:, k],
                                   tracked_shapes[j + 1][:, k], spectra[j], spectra[j + 1], float(w[j]),
                                   float(w[j + 1]), speed)
            if followed is not None:
                value, shape = followed
                return value, shape_whirl(shape[:, None], names, positions)[0][0]
        modes, (c,) = _solve_matched(modes_at, speed, tracked_shapes[j][:, [k]], np.array([damped[j, k]]), 1,
                                     spectra[j])
        if c is None:
            return complex("nan"), ""
        return modes.eigenvalues[c], modes.whirl[c]

    def locate(g, j, k):
        a, b = float(w[j]), float(w[j + 1])
        ga, gb = g(a, None), g(b, None)
        if not refine:
            return a + (b - a) * ga / (ga - gb)
        try:
            return brent(lambda s: g(s, tracked(k, j, s)[0]), a, b, xtol=xtol, maxiter=60)
        except ValueError:  # the re-tracked mode does not bracket: fall back on the grid
            return a + (b - a) * ga / (ga - gb)

    crossings = []
    for name in lines:
        ratio_of = _line_function(w, lines[name])
        for order in orders:
            for k in range(count):
                d = damped[:, k] - order * lines[name]
                for j in range(w.size - 1):
                    if not (np.isfinite(d[j]) and np.isfinite(d[j + 1])) or d[j] * d[j + 1] > 0 or \
                            (d[j] == 0 and j > 0):
                        continue

                    def g(s, value, k=k, j=j, order=order, line=ratio_of):
                        if value is None:
                            return float((damped[j, k] if s == w[j] else damped[j + 1, k]) - order * line(s))
                        return float(value.imag - order * line(s))

                    s = float(w[j]) if d[j] == 0 else float(w[j + 1]) if d[j + 1] == 0 else locate(g, j, k)
                    value, kind = tracked(k, j, s) if refine else (lam[j, k], whirl[j, k])
                    crossings.append(CriticalSpeed(rotor=name, order=order, mode=k + 1, speed=s,
                                                   frequency=float(order * ratio_of(s)), whirl=kind or whirl[j, k]))
    neutral = neutral_tolerance(lam, radius[:, None])
    onsets = []
    for k in range(count):
        d = logdec[:, k]
        for j in range(w.size - 1):
            if not (np.isfinite(d[j]) and np.isfinite(d[j + 1])) or d[j] * d[j + 1] >= 0:
                continue
            if abs(d[j]) <= neutral[j, k] and abs(d[j + 1]) <= neutral[j + 1, k]:
                continue  # an undamped mode: rounding noise about zero, not an onset

            def g(s, value, k=k, j=j):
                if value is None:
                    return float(logdec[j, k] if s == w[j] else logdec[j + 1, k])
                return float(-value.real / value.imag)

            s = locate(g, j, k)
            value, kind = tracked(k, j, s) if refine else (lam[j, k], whirl[j, k])
            onsets.append(InstabilityOnset(mode=k + 1, speed=float(s), frequency=float(value.imag),
                                           whirl=kind or whirl[j, k], becomes="unstable" if d[j] > 0 else "stable"))
    return Campbell(
        speeds=_ro(w),
        frequencies=_ro(damped),
        natural_frequencies=_ro(np.abs(lam)),
        damping_ratios=_ro(-lam.real / np.abs(lam)),
        log_decrements=_ro(logdec),
        whirl=_ro(whirl.astype(str)),
        rotor_speeds={name: _ro(v) for name, v in lines.items()},
        speed_parameter=speed_parameter,
        orders=orders,
        crossings=tuple(sorted(crossings, key=lambda c: (c.speed, c.mode))),
        onsets=tuple(sorted(onsets, key=lambda o: o.speed)),
        neutral_log_decrements=_ro(neutral),
    )


def _whirl_of_columns(modes, cols):
    """``modes.whirl`` for the columns ``cols`` only (None entries skipped): a mode's whirl is its own."""
    from .whirl import shape_whirl

    used = sorted({c for c in cols if c is not None})
    kinds = shape_whirl(modes.shapes[:, used], modes.coordinate_names, modes.station_positions)[0] if used else ()
    return dict(zip(used, kinds))


def _line_function(w, values):
    """Spin speed at any swept speed: exactly affine in the swept speed, interpolated between grid points."""
    if w.size == 1:
        return lambda s: float(values[0])
    return lambda s: float(np.interp(s, w, values))


def _ro(a):
    a = np.array(a)
    a.setflags(write=False)
    return a
