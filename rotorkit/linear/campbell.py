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

The result types (:class:`Campbell`, :class:`CriticalSpeed`,
:class:`InstabilityOnset`, :func:`neutral_tolerance`) live in
:mod:`rotorkit.linear.campbell_result` and the per-speed eigen-solution in
:mod:`rotorkit.linear.speed_modes`; both are importable from here.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ParameterError
from .campbell_result import (EIGENVALUE_ROUNDING, NEUTRAL_LOG_DECREMENT, Campbell, CriticalSpeed,
                              InstabilityOnset, neutral_tolerance)  # noqa: F401 (re-exported)
from .speed_modes import resolve_source, speed_solver

__all__ = ["Campbell", "CriticalSpeed", "InstabilityOnset", "campbell", "mac", "neutral_tolerance"]


def mac(a, b):
    """Modal assurance criterion matrix ``|a_i^H b_j|^2 / (|a_i|^2 |b_j|^2)`` of shape columns."""
    a, b = np.atleast_2d(a), np.atleast_2d(b)
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(den > 0, num / den, 0.0)


# ---------------------------------------------------------------------------
# Tracking modes from one speed to the next
# ---------------------------------------------------------------------------


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
    target = resolve_source(model_or_preset_builder, backend)
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
    modes_at, spins_at, speed_parameter = speed_solver(target, speed_parameter, options, n_modes, relinearize, w,
                                                        backend)

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
