"""Spectra, time-frequency waterfalls, spectrograms and spectrum cascades.

The figures of the paper's Section 3 (Figs. 9-16):

- :func:`plot_waterfall`: a *time-frequency waterfall*: amplitude spectra of
  short segments, stacked along time in 3-D (Figs. 9-12, 16), from
  :func:`rotorkit.signals.stft`;
- :func:`plot_spectrogram`: the same data as a 2-D colour map;
- :func:`plot_cascade`: a *spectrum cascade*: the spectra of a parameter
  sweep stacked along the swept parameter (Figs. 13-15), from
  :func:`rotorkit.sweep.load_sweep`;
- :func:`plot_spectrum`: one spectrum with order lines and peaks.

Order lines mark frequencies of interest (``{"1/2 low": 750.0, ...}``, in
the data's frequency units); :func:`speed_orders` gives the paper's set.
Every function draws on ``ax=`` or, without it, on pyplot's current axes
(see :mod:`rotorkit.plotting.basic`) and returns the Axes.
"""

import math
import numbers
from collections.abc import Iterable, Mapping
from fractions import Fraction

import numpy as np

from ..errors import ParameterError
from .basic import new_axes

__all__ = ["plot_waterfall", "plot_spectrogram", "plot_cascade", "plot_spectrum", "speed_orders",
           "default_amplitude_label"]

#: markers of the points of a cascade that have no spectrum
_STATUS_MARKERS = {"failed": ("x", "C3"), "runaway": ("^", "m"), "missing": ("o", "0.5")}
#: colour-scale floor of log colour maps, relative to the largest amplitude
_LOG_FLOOR = 1e-4


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
    low = _positive(low_speed, "low_speed")
    ratio = _positive(speed_ratio, "speed_ratio")
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
# Checks and helpers
# ---------------------------------------------------------------------------


def _positive(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
        raise ParameterError(f"{name}={value!r}: expected a finite number > 0")
    return float(value)


def _check_orders(orders, units):
    """Orders as {label: frequency}; None -> {}."""
    if orders is None:
        return {}
    if not isinstance(orders, Mapping):
        raise ParameterError(f"orders={orders!r}: expected a mapping of labels to frequencies in {units}")
    out = {}
    for label, value in orders.items():
        if not isinstance(label, str) or not label:
            raise ParameterError(f"orders has the label {label!r}: expected non-empty strings")
        out[label] = _positive(value, f"orders[{label!r}] ({units})")
    return out


def _frequency_mask(frequency, fmax, units):
    if fmax is None:
        return np.ones(frequency.size, dtype=bool)
    fmax = _positive(fmax, f"fmax ({units})")
    mask = frequency <= fmax
    if frequency.size and np.count_nonzero(mask) < 2:
        raise ParameterError(f"fmax={fmax!r} {units} keeps fewer than 2 frequency bins (bin spacing "
                             f"{frequency[1] - frequency[0]:.4g} {units})")
    return mask


def _check_scale(scale):
    return _positive(scale, "scale")


def _axes_3d(ax, figsize=(7.5, 5.5)):
    if ax is None:
        ax = new_axes(None, figsize=figsize, projection="3d")
        ax.view_init(elev=30.0, azim=-65.0)
        return ax
    if getattr(ax, "name", None) != "3d":
        raise ParameterError("ax must be a 3-D axes (add_subplot(projection='3d')) for this plot")
    return ax


def _axes_2d(ax, figsize=(7.0, 4.5)):
    if ax is not None and getattr(ax, "name", None) == "3d":
        raise ParameterError("ax is a 3-D axes; this plot needs a 2-D one")
    return new_axes(ax, figsize=figsize)


def _time_frequency_view(tf, orders, fmax, scale):
    """(time, frequency, scaled amplitude, units, checked orders) of ``tf`` up to ``fmax``."""
    time, frequency, amplitude, units = _time_frequency(tf)
    orders = _check_orders(orders, units)
    keep = _frequency_mask(frequency, fmax, units)
    return time, frequency[keep], amplitude[keep] * _check_scale(scale), units, orders


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


def _edges(centres):
    """Cell edges around sorted centres (for pcolormesh)."""
    centres = np.asarray(centres, dtype=float)
    if centres.size == 1:
        half = 0.5 * abs(centres[0]) or 0.5
        return np.array([centres[0] - half, centres[0] + half])
    mid = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate([[2 * centres[0] - mid[0]], mid, [2 * centres[-1] - mid[-1]]])


def _frequency_label(units):
    return f"frequency ({units})"


def default_amplitude_label(signal=None, scale=1.0):
    """Default amplitude axis label: quantity and unit, with the unit the scale implies.

    >>> default_amplitude_label("x2", 1e6)
    'x2 amplitude (µm)'
    >>> default_amplitude_label("alpha2-alpha5")
    'alpha2-alpha5 amplitude (rad)'
    >>> default_amplitude_label(None, 1e6)
    'amplitude (µ[signal unit])'
    """
    from .basic import scaled_unit, signal_unit

    shown = scaled_unit(signal_unit(signal) if signal else "[signal unit]", scale)
    return f"{signal} amplitude ({shown})" if signal else f"amplitude ({shown})"


def _limits(low, high):
    """(low, high), widened around ``low`` when the range is empty."""
    if np.isfinite(low) and np.isfinite(high) and high > low:
        return float(low), float(high)
    low = float(low) if np.isfinite(low) else 0.0
    pad = 0.05 * abs(low) or 1.0
    return low - pad, low + pad


# ---------------------------------------------------------------------------
# Time-frequency
# ---------------------------------------------------------------------------


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

    ax = _axes_3d(ax)
    time, f, a, units, orders = _time_frequency_view(tf, orders, fmax, scale)
    segments = [np.column_stack([f, np.full(f.size, t), a[:, j]]) for j, t in enumerate(time)]
    ax.add_collection3d(Line3DCollection(segments, colors=color, linewidths=linewidth), autolim=False)
    t0, t1 = _limits(time[0], time[-1])
    f0, f1 = _limits(f[0], f[-1]) if f.size else (0.0, 1.0)
    _draw_orders_3d(ax, orders, f0, f1, t0, t1)
    top = float(np.nanmax(a)) if a.size and np.any(np.isfinite(a)) else 0.0
    ax.set_xlim(f0, f1)
    ax.set_ylim(t0, t1)
    ax.set_zlim(0.0, top * 1.05 if top > 0 else 1.0)
    ax.set_xlabel(_frequency_label(units))
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

    ax = _axes_2d(ax)
    time, f, a, units, orders = _time_frequency_view(tf, orders, fmax, scale)
    top = float(np.max(a)) if a.size else 0.0
    norm = None
    if log and top > 0:
        norm = LogNorm(vmin=top * _LOG_FLOOR, vmax=top)
        a = np.maximum(a, top * _LOG_FLOOR)
    mesh = ax.pcolormesh(_edges(time), _edges(f), a, shading="flat", norm=norm, cmap="viridis", rasterized=True)
    for label, freq in orders.items():
        if f.size and f[0] <= freq <= f[-1]:
            ax.axhline(freq, ls="--", lw=0.8, color="w", alpha=0.9, label=label)
            ax.text(0.99, freq, label, transform=ax.get_yaxis_transform(), ha="right", va="bottom", fontsize=7,
                    color="w")
    if colorbar:
        ax.figure.colorbar(mesh, ax=ax, label=amplitude_label or default_amplitude_label(signal, scale))
    ax.set_xlabel("t (s)")
    ax.set_ylabel(_frequency_label(units))
    if signal:
        ax.set_title(f"{signal}: spectrogram", fontsize=9)
    return ax


# ---------------------------------------------------------------------------
# Cascades
# ---------------------------------------------------------------------------


def _cascade_orders(orders, values, units):
    """{label: frequencies per value, shape (n_values,)} from a mapping or a callable of the value."""
    if orders is None:
        return {}
    if callable(orders) and not isinstance(orders, Mapping):
        per_value = [_check_orders(orders(float(v)), units) for v in values]
        labels = list(per_value[0])
        for v, d in zip(values, per_value):
            if list(d) != labels:
                raise ParameterError(
                    f"orders({v:g}) gives the labels {list(d)}, but orders({values[0]:g}) gave {labels}: "
                    "the callable must give the same labels for every value"
                )
        return {label: np.array([d[label] for d in per_value]) for label in labels}
    return {label: np.full(len(values), freq) for label, freq in _check_orders(orders, units).items()}


def _parameter_unit(cascade):
    """SI unit of the swept parameter: the cascade's own, else its preset's ``UNITS``, else ``None``."""
    unit = getattr(cascade, "parameter_unit", None)
    if unit is None and getattr(cascade, "preset", ""):
        try:
            from ..presets import preset_module

            unit = getattr(preset_module(cascade.preset), "UNITS", {}).get(cascade.parameter)
        except Exception:  # a build callable or a file: no unit known
            unit = None
    return unit


def _plain_ticks(axis):
    """Tick labels that carry their own exponent (no bare ``1e7`` offset beside the axis)."""
    from matplotlib.ticker import FuncFormatter

    axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.4g}"))


def plot_cascade(cascade, signal, ax=None, *, orders=None, fmax=None, three_d=True, log_values=False, log=False,
                 scale=1.0, amplitude_label=None, color="C0", linewidth=0.8, colorbar=True):
    """Spectrum cascade: the spectra of a sweep stacked along the swept parameter.

    Parameters
    ----------
    cascade : rotorkit.sweep.Cascade
        From :func:`rotorkit.sweep.load_sweep` or :func:`rotorkit.sweep.run_sweep`.
    signal : str
        One of ``cascade.signals`` (``"x2"``, ``"alpha2-alpha5"``).
    ax : matplotlib.axes.Axes, optional
        3-D axes if ``three_d`` (default: new Figure), else 2-D.
    orders : mapping of str to float, or callable, optional
        Order lines in ``cascade.units``: ``{label: frequency}`` for lines at
        constant frequency, or a function ``value -> {label: frequency}`` of
        the swept value for lines that move with it (a sweep of the LP speed:
        ``orders=speed_orders``).
    fmax : float, optional
        Highest frequency shown.
    three_d : bool
        3-D stacked lines (as the paper's Figs. 13-15), else a 2-D colour map
        over (frequency, value).
    log_values : bool
        Place the spectra at ``log10(value)`` (for log-spaced sweeps).
    log : bool
        Logarithmic colour scale (2-D only).
    scale : float
        Factor applied to the amplitudes.
    amplitude_label : str, optional
        Label of the amplitude axis (or colour bar), with its unit; default
        ``"<signal> amplitude (m)"`` (rad for angles) when ``scale`` is 1.
    color, linewidth
        Of the spectra (3-D).
    colorbar : bool
        Add a colour bar to the axes' figure (2-D).

    Returns
    -------
    matplotlib.axes.Axes
        3-D: one ``Line3DCollection`` of the spectra of the ``ok`` points;
        2-D: one ``QuadMesh`` (rows without a spectrum left blank). Both: one
        marker collection per status without a spectrum (``failed``,
        ``runaway``, ``missing``), placed at the lowest frequency, and one
        line per order.
    """
    try:
        rows = cascade.amplitude[signal]
    except KeyError:
        raise ParameterError(f"the cascade has no signal {signal!r}; signals are {', '.join(cascade.amplitude)}") \
            from None
    except AttributeError:
        raise ParameterError(f"cascade={type(cascade).__name__}: expected a rotorkit.sweep.Cascade") from None
    units = cascade.units
    scale = _check_scale(scale)
    if amplitude_label is None:
        amplitude_label = default_amplitude_label(signal, scale)
    values = np.asarray(cascade.values, dtype=float)
    unit = _parameter_unit(cascade)
    shown_unit = f" ({unit})" if unit else (" (-)" if unit == "" else "")
    if log_values:
        if np.any(values <= 0):
            raise ParameterError("log_values=True needs positive swept values")
        position = np.log10(values)
        value_label = f"log10 {cascade.parameter}{shown_unit}"
    else:
        position, value_label = values, f"{cascade.parameter}{shown_unit}"
    status = np.asarray(cascade.status)
    frequency = np.asarray(cascade.frequency, dtype=float)
    keep = _frequency_mask(frequency, fmax, units)
    f, a = frequency[keep], np.asarray(rows, dtype=float)[:, keep] * scale
    ok = status == "ok"
    lines = _cascade_orders(orders, values, units)
    sort = np.argsort(position)
    y0, y1 = _limits(position[sort[0]], position[sort[-1]])
    f0, f1 = _limits(f[0], f[-1]) if f.size else (0.0, max([float(np.max(v)) for v in lines.values()] or [1.0]))
    if three_d:
        from mpl_toolkits.mplot3d.art3d import Line3DCollection

        ax = _axes_3d(ax)
        segments = [np.column_stack([f, np.full(f.size, position[i]), a[i]]) for i in sort if ok[i]]
        ax.add_collection3d(Line3DCollection(segments, colors=color, linewidths=linewidth), autolim=False)
        top = float(np.nanmax(a[ok])) if f.size and ok.any() else 0.0
        ax.set_zlim(0.0, top * 1.05 if top > 0 else 1.0)
        ax.set_zlabel(amplitude_label, labelpad=12)
        _plain_ticks(ax.zaxis)
        ax.yaxis.labelpad = 14
    else:
        from matplotlib.colors import LogNorm

        ax = _axes_2d(ax)
        if f.size and ok.any():
            table = np.ma.masked_invalid(a[sort])
            top = float(table.max())
            norm = None
            if log and top > 0:
                norm = LogNorm(vmin=top * _LOG_FLOOR, vmax=top)
                table = np.ma.maximum(table, top * _LOG_FLOOR)
            mesh = ax.pcolormesh(_edges(f), _edges(position[sort]), table, shading="flat", norm=norm,
                                 cmap="viridis", rasterized=True)
            if colorbar:
                ax.figure.colorbar(mesh, ax=ax, label=amplitude_label)
    marked = False
    for kind, (marker, mcolor) in _STATUS_MARKERS.items():
        mask = status == kind
        if not mask.any():
            continue
        xs = np.full(int(mask.sum()), f0)
        if three_d:
            ax.scatter(xs, position[mask], np.zeros(xs.size), marker=marker, color=mcolor, s=30, label=kind,
                       depthshade=False)
        else:
            ax.scatter(xs, position[mask], marker=marker, color=mcolor, s=30, label=kind, clip_on=False, zorder=3)
        marked = True
    for k, (label, freqs) in enumerate(lines.items()):
        freqs = np.where((freqs >= f0) & (freqs <= f1), freqs, np.nan)[sort]
        if np.all(np.isnan(freqs)):
            continue
        style = dict(ls="--", lw=0.9, color=f"C{(k + 1) % 10}", label=label)
        if three_d:
            ax.plot(freqs, position[sort], np.zeros(freqs.size), **style)
        else:
            ax.plot(freqs, position[sort], **style)
    if marked or lines:  # beside the axes, so order labels neither pile up nor cover spectra
        ax.legend(loc="upper left", bbox_to_anchor=(1.02 if not three_d else 1.08, 1.0), fontsize=7,
                  borderaxespad=0.0)
    ax.set_xlim(f0, f1)
    ax.set_ylim(y0, y1)
    _plain_ticks(ax.yaxis)
    ax.set_xlabel(_frequency_label(units))
    ax.set_ylabel(value_label)
    window = getattr(cascade, "window", None)
    title = f"spectra of {signal} against {cascade.parameter}"
    if getattr(cascade, "preset", ""):
        title = f"{cascade.preset}: {title}"
    if window:
        title += f", t in [{window[0]:g}, {window[1]:g}] s"
    ax.set_title(title, fontsize=9)
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
    ax = _axes_2d(ax)
    orders = _check_orders(orders, units)
    scale = _check_scale(scale)
    keep = _frequency_mask(frequency, fmax, units)
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
    ax.set_xlabel(_frequency_label(units))
    ax.set_ylabel(amplitude_label or default_amplitude_label(signal, scale))
    if signal:
        ax.set_title(f"{signal}: amplitude spectrum", fontsize=9)
    return ax
