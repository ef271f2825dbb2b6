"""Spectra, time-frequency waterfalls, spectrograms and spectrum cascades.

The figures of the paper's Section 3 (Figs. 9-16):

- :func:`plot_waterfall`: a *time-frequency waterfall*: amplitude spectra of
  short segments, stacked along time in 3-D (Figs. 9-12, 16), from
  :func:`rotorkit.signals.stft`;
- :func:`plot_spectrogram`: the same data as a 2-D colour map;
- :func:`plot_cascade`: a *spectrum cascade*: the spectra of a parameter
  sweep stacked along the swept parameter (Figs. 13-15), from
  :func:`rotorkit.sweep.load_sweep` (defined in
  :mod:`rotorkit.plotting.cascade`, importable from here);
- :func:`plot_spectrum`: one spectrum with order lines and peaks.

Order lines mark frequencies of interest (``{"1/2 low": 750.0, ...}``, in
the data's frequency units); :func:`speed_orders` gives the paper's set.
Every function draws on ``ax=`` or, without it, on pyplot's current axes
(see :mod:`rotorkit.plotting.basic`) and returns the Axes.
The checks and axes these figures share are in
:mod:`rotorkit.plotting.spectral_axes`.
"""

import math
from collections.abc import Iterable
from fractions import Fraction

import numpy as np

from ..errors import ParameterError
from .cascade import plot_cascade
from .spectral_axes import (LOG_FLOOR, axes_2d, axes_3d, axis_limits, cell_edges, check_orders, check_scale,
                            default_amplitude_label, frequency_label, frequency_mask, positive)

__all__ = ["plot_waterfall", "plot_spectrogram", "plot_cascade", "plot_spectrum", "speed_orders",
           "default_amplitude_label"]


def speed_orders(low_speed, speed_ratio=1.8, *, ratios=("1/2", "1", "5/4", "3/2")):
    """The paper's order lines: fractions of the LP speed, the HP speed and their difference.

    Parameters
    ----------
    low_speed : float
        LP rotor speed omega_low (rad/s, or any unit: the lines come out in it).
    speed_ratio : float
        omega_high / omega_low.
    ratios : iterable of str, int or Fraction
        Orders of omega_low to draw.

    Returns
    -------
    dict
        Label -> frequency, e.g. ``{"1/2 low": 750.0, "low": 1500.0, ...,
        "high": 2700.0, "high - low": 1200.0}``.

    Examples
    --------
    >>> speed_orders(1500.0)["high - low"]
    1200.0

    For a sweep of the LP speed, pass ``orders=speed_orders`` to
    :func:`plot_cascade`: the lines follow the swept speed.
    """
    low = positive(low_speed, "low_speed")
    ratio = positive(speed_ratio, "speed_ratio")
    out = {}
    for r in ratios:
        try:
            r = Fraction(r)
        except (TypeError, ValueError, ZeroDivisionError):
            raise ParameterError(f"ratios contains {r!r}: expected orders such as '1/2', 1 or '5/4'") from None
        out["low" if r == 1 else f"{r} low"] = float(r * Fraction(low))
    out["high"] = ratio * low
    if ratio != 1:
        out["high - low" if ratio > 1 else "low - high"] = abs(ratio - 1.0) * low
    return out


# ---------------------------------------------------------------------------
# Time-frequency
# ---------------------------------------------------------------------------


def _time_frequency_view(tf, orders, fmax, scale):
    """(time, frequency, scaled amplitude, units, checked orders) of ``tf`` up to ``fmax``."""
    time, frequency, amplitude, units = _time_frequency(tf)
    orders = check_orders(orders, units)
    keep = frequency_mask(frequency, fmax, units)
    return time, frequency[keep], amplitude[keep] * check_scale(scale), units, orders


def _time_frequency(tf):
    try:
        time = np.asarray(tf.time, dtype=float)
        frequency = np.asarray(tf.frequency, dtype=float)
        amplitude = np.asarray(tf.amplitude, dtype=float)
        units = tf.units
    except AttributeError:
        raise ParameterError(
            f"tf={type(tf).__name__}: expected a TimeFrequency (rotorkit.signals.stft)"
        ) from None
    if time.ndim != 1 or frequency.ndim != 1 or amplitude.shape != (frequency.size, time.size) or time.size < 1:
        raise ParameterError(
            f"tf has time {time.shape}, frequency {frequency.shape}, amplitude {amplitude.shape}: "
            "expected amplitude of shape (n_freq, n_time)"
        )
    return time, frequency, amplitude, units


def plot_waterfall(tf, ax=None, *, orders=None, fmax=None, scale=1.0, amplitude_label=None, signal=None,
                   color="C0", linewidth=0.6):
    """Time-frequency waterfall: spectra of short segments stacked along time, in 3-D.

    Parameters
    ----------
    tf : rotorkit.signals.TimeFrequency
        From :func:`~rotorkit.signals.stft` (``amplitude`` of shape
        (n_freq, n_time)).
    ax : mpl_toolkits.mplot3d.axes3d.Axes3D, optional
        A 3-D axes; default: a new Figure with one.
    orders : mapping of str to float, optional
        Order lines ``{label: frequency}`` in ``tf.units``, drawn at constant
        frequency along the time axis on the floor of the plot.
    fmax : float, optional
        Highest frequency shown (``tf.units``).
    scale : float
        Factor applied to the amplitudes (e.g. 1e6 for µm).
    amplitude_label : str, optional
        Label of the amplitude axis, with its unit; default from ``signal``
        and ``scale`` (:func:`default_amplitude_label`: ``"x2 amplitude (µm)"``).
    signal : str, optional
        Name of the analysed signal (``"x2"``, ``"alpha2-alpha5"``): gives the
        default label its quantity and unit (m, rad) and the figure a title.
    color, linewidth
        Of the spectra.

    Returns
    -------
    mpl_toolkits.mplot3d.axes3d.Axes3D
        Holding one ``Line3DCollection`` (one line per time) and one line
        per order drawn (orders outside the frequency range are skipped).
    """
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    ax = axes_3d(ax)
    time, f, a, units, orders = _time_frequency_view(tf, orders, fmax, scale)
    segments = [np.column_stack([f, np.full(f.size, t), a[:, j]]) for j, t in enumerate(time)]
    ax.add_collection3d(Line3DCollection(segments, colors=color, linewidths=linewidth), autolim=False)
    t0, t1 = axis_limits(time[0], time[-1])
    f0, f1 = axis_limits(f[0], f[-1]) if f.size else (0.0, 1.0)
    _draw_orders_3d(ax, orders, f0, f1, t0, t1)
    top = float(np.nanmax(a)) if a.size and np.any(np.isfinite(a)) else 0.0
    ax.set_xlim(f0, f1)
    ax.set_ylim(t0, t1)
    ax.set_zlim(0.0, top * 1.05 if top > 0 else 1.0)
    ax.set_xlabel(frequency_label(units))
    ax.set_ylabel("t (s)")
    ax.set_zlabel(amplitude_label or default_amplitude_label(signal, scale))
    if signal:
        ax.set_title(f"{signal}: short-time spectra", fontsize=9)
    return ax


def _draw_orders_3d(ax, orders, f0, f1, y0, y1):
    for k, (label, freq) in enumerate(orders.items()):
        if not f0 <= freq <= f1:
            continue
        ax.plot([freq, freq], [y0, y1], [0.0, 0.0], ls="--", lw=0.9, color=f"C{(k + 1) % 10}", label=label)
    if ax.lines:  # a legend beside the axes: labels at the line ends piled up where orders are close
        ax.legend(loc="upper left", bbox_to_anchor=(1.05, 1.0), fontsize=7, borderaxespad=0.0)


def plot_spectrogram(tf, ax=None, *, orders=None, fmax=None, log=True, scale=1.0, amplitude_label=None,
                     signal=None, colorbar=True):
    """Time-frequency map: amplitude in colour over time (x) and frequency (y).

    Parameters
    ----------
    tf : rotorkit.signals.TimeFrequency
        From :func:`~rotorkit.signals.stft`.
    ax : matplotlib.axes.Axes, optional
    orders : mapping of str to float, optional
        Order lines ``{label: frequency}`` in ``tf.units`` (horizontal lines).
    fmax : float, optional
        Highest frequency shown (``tf.units``).
    log : bool
        Logarithmic colour scale (floor at 1e-4 of the largest amplitude).
    scale : float
        Factor applied to the amplitudes.
    amplitude_label : str, optional
        Label of the colour bar, with its unit; default from ``signal`` and
        ``scale`` (:func:`default_amplitude_label`).
    signal : str, optional
        Name of the analysed signal: the default label's quantity and unit,
        and the title.
    colorbar : bool
        Add a colour bar to the axes' figure.

    Returns
    -------
    matplotlib.axes.Axes
        Holding one ``QuadMesh`` and one line per order drawn.
    """
    from matplotlib.colors import LogNorm

    ax = axes_2d(ax)
    time, f, a, units, orders = _time_frequency_view(tf, orders, fmax, scale)
    top = float(np.max(a)) if a.size else 0.0
    norm = None
    if log and top > 0:
        norm = LogNorm(vmin=top * LOG_FLOOR, vmax=top)
        a = np.maximum(a, top * LOG_FLOOR)
    mesh = ax.pcolormesh(cell_edges(time), cell_edges(f), a, shading="flat", norm=norm, cmap="viridis", rasterized=True)
    for label, freq in orders.items():
        if f.size and f[0] <= freq <= f[-1]:
            ax.axhline(freq, ls="--", lw=0.8, color="w", alpha=0.9, label=label)
            ax.text(0.99, freq, label, transform=ax.get_yaxis_transform(), ha="right", va="bottom", fontsize=7,
                    color="w")
    if colorbar:
        ax.figure.colorbar(mesh, ax=ax, label=amplitude_label or default_amplitude_label(signal, scale))
    ax.set_xlabel("t (s)")
    ax.set_ylabel(frequency_label(units))
    if signal:
        ax.set_title(f"{signal}: spectrogram", fontsize=9)
    return ax


# ---------------------------------------------------------------------------
# One spectrum
# ---------------------------------------------------------------------------


def _peak_points(peaks, spectrum):
    from ..signals import Peak, find_peaks

    factors = {("Hz", "rad/s"): 2.0 * math.pi, ("rad/s", "Hz"): 0.5 / math.pi}

    if peaks is True:
        peaks = find_peaks(spectrum, min_relative_height=0.05, max_peaks=10)
    if isinstance(peaks, (str, bytes, Peak)) or not isinstance(peaks, Iterable):
        raise ParameterError(f"peaks={peaks!r}: expected True, Peak objects or (frequency, amplitude) pairs")
    out = []
    for p in peaks:
        if isinstance(p, Peak):
            factor = factors.get((p.units, spectrum.units), 1.0)
            out.append((float(p.frequency) * factor, float(p.amplitude)))
        else:
            try:
                fp, ap = (float(v) for v in p)
            except (TypeError, ValueError):
                raise ParameterError(f"peaks contains {p!r}: expected a Peak or a (frequency, amplitude) pair") \
                    from None
            out.append((fp, ap))
    return out


def plot_spectrum(spectrum, ax=None, *, orders=None, peaks=None, fmax=None, scale=1.0, amplitude_label=None,
                  signal=None):
    """An amplitude spectrum with order lines and marked peaks.

    Parameters
    ----------
    spectrum : rotorkit.signals.Spectrum
        From :func:`~rotorkit.signals.amplitude_spectrum` or
        :meth:`rotorkit.sweep.Cascade.spectrum`.
    ax : matplotlib.axes.Axes, optional
    orders : mapping of str to float, optional
        Order lines ``{label: frequency}`` in ``spectrum.units`` (vertical).
    peaks : True or iterable, optional
        Peaks to mark: :class:`~rotorkit.signals.Peak` objects (from
        :func:`~rotorkit.signals.find_peaks`) or ``(frequency,
        amplitude)`` pairs; ``True`` finds them (peaks above 5 % of the
        largest, at most 10).
    fmax : float, optional
        Highest frequency shown.
    scale : float
        Factor applied to the amplitudes.
    amplitude_label : str, optional
        Label of the amplitude axis, with its unit; default from ``signal``
        and ``scale`` (:func:`default_amplitude_label`).
    signal : str, optional
        Name of the analysed signal: the default label's quantity and unit,
        and the title.

    Returns
    -------
    matplotlib.axes.Axes
        Holding the spectrum line, one line per order drawn and, with
        peaks, one line of peak markers.
    """
    try:
        frequency = np.asarray(spectrum.frequency, dtype=float)
        amplitude = np.asarray(spectrum.amplitude, dtype=float)
        units = spectrum.units
    except AttributeError:
        raise ParameterError(f"spectrum={type(spectrum).__name__}: expected a Spectrum") from None
    if frequency.ndim != 1 or amplitude.shape != frequency.shape:
        raise ParameterError(f"spectrum has frequency {frequency.shape} and amplitude {amplitude.shape}: "
                             "expected equal 1-D shapes")
    ax = axes_2d(ax)
    orders = check_orders(orders, units)
    scale = check_scale(scale)
    keep = frequency_mask(frequency, fmax, units)
    f = frequency[keep]
    ax.plot(f, amplitude[keep] * scale, lw=0.8, color="C0", label="spectrum")
    f0, f1 = (f[0], f[-1]) if f.size else (0.0, 1.0)
    for k, (label, freq) in enumerate(orders.items()):
        if not f0 <= freq <= f1:
            continue
        ax.axvline(freq, ls="--", lw=0.8, color=f"C{(k + 1) % 10}", label=label)
        ax.text(freq, 0.98, f" {label}", transform=ax.get_xaxis_transform(), rotation=90, va="top", fontsize=7,
                color=f"C{(k + 1) % 10}")
    if peaks is not None:
        points = [(fp, ap) for fp, ap in _peak_points(peaks, spectrum) if f0 <= fp <= f1]
        if points:
            fp, ap = (np.array(v) for v in zip(*points))
            ax.plot(fp, ap * scale, "o", ms=4, color="C3", label="peaks")
            for x, y in zip(fp, ap * scale):
                ax.annotate(f"{x:.0f}", (x, y), textcoords="offset points", xytext=(3, 3), fontsize=7)
    ax.set_xlim(f0, f1)
    ax.set_xlabel(frequency_label(units))
    ax.set_ylabel(amplitude_label or default_amplitude_label(signal, scale))
    if signal:
        ax.set_title(f"{signal}: amplitude spectrum", fontsize=9)
    return ax
