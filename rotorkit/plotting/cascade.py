"""Spectrum cascades: the spectra of a parameter sweep stacked along the swept parameter.

:func:`plot_cascade` draws a :class:`rotorkit.sweep.Cascade` (from
:func:`rotorkit.sweep.load_sweep`) as the paper's Figs. 13-15: 3-D stacked
lines, or a 2-D colour map over (frequency, swept value), with markers for
the points that have no spectrum and order lines that may follow the swept
value (:func:`rotorkit.plotting.spectra.speed_orders`). It draws on ``ax=``
or, without it, on pyplot's current axes (see :mod:`rotorkit.plotting.basic`)
and returns the Axes.
"""

from collections.abc import Mapping

import numpy as np

from ..errors import ParameterError
from .spectral_axes import (LOG_FLOOR, axes_2d, axes_3d, axis_limits, cell_edges, check_orders, check_scale,
                            default_amplitude_label, frequency_label, frequency_mask)

__all__ = ["plot_cascade"]

#: markers of the points of a cascade that have no spectrum
_STATUS_MARKERS = {"failed": ("x", "C3"), "runaway": ("^", "m"), "missing": ("o", "0.5")}


def _cascade_orders(orders, values, units):
    """{label: frequencies per value, shape (n_values,)} from a mapping or a callable of the value."""
    if orders is None:
        return {}
    if callable(orders) and not isinstance(orders, Mapping):
        per_value = [check_orders(orders(float(v)), units) for v in values]
        labels = list(per_value[0])
        for v, d in zip(values, per_value):
            if list(d) != labels:
                raise ParameterError(
                    f"orders({v:g}) gives the labels {list(d)}, but orders({values[0]:g}) gave {labels}: "
                    "the callable must give the same labels for every value"
                )
        return {label: np.array([d[label] for d in per_value]) for label in labels}
    return {label: np.full(len(values), freq) for label, freq in check_orders(orders, units).items()}


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
    scale = check_scale(scale)
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
    keep = frequency_mask(frequency, fmax, units)
    f, a = frequency[keep], np.asarray(rows, dtype=float)[:, keep] * scale
    ok = status == "ok"
    lines = _cascade_orders(orders, values, units)
    sort = np.argsort(position)
    y0, y1 = axis_limits(position[sort[0]], position[sort[-1]])
    f0, f1 = axis_limits(f[0], f[-1]) if f.size else (0.0, max([float(np.max(v)) for v in lines.values()] or [1.0]))
    if three_d:
        from mpl_toolkits.mplot3d.art3d import Line3DCollection

        ax = axes_3d(ax)
        segments = [np.column_stack([f, np.full(f.size, position[i]), a[i]]) for i in sort if ok[i]]
        ax.add_collection3d(Line3DCollection(segments, colors=color, linewidths=linewidth), autolim=False)
        top = float(np.nanmax(a[ok])) if f.size and ok.any() else 0.0
        ax.set_zlim(0.0, top * 1.05 if top > 0 else 1.0)
        ax.set_zlabel(amplitude_label, labelpad=12)
        _plain_ticks(ax.zaxis)
        ax.yaxis.labelpad = 14
    else:
        from matplotlib.colors import LogNorm

        ax = axes_2d(ax)
        if f.size and ok.any():
            table = np.ma.masked_invalid(a[sort])
            top = float(table.max())
            norm = None
            if log and top > 0:
                norm = LogNorm(vmin=top * LOG_FLOOR, vmax=top)
                table = np.ma.maximum(table, top * LOG_FLOOR)
            mesh = ax.pcolormesh(cell_edges(f), cell_edges(position[sort]), table, shading="flat", norm=norm,
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
    ax.set_xlabel(frequency_label(units))
    ax.set_ylabel(value_label)
    window = getattr(cascade, "window", None)
    title = f"spectra of {signal} against {cascade.parameter}"
    if getattr(cascade, "preset", ""):
        title = f"{cascade.preset}: {title}"
    if window:
        title += f", t in [{window[0]:g}, {window[1]:g}] s"
    ax.set_title(title, fontsize=9)
    return ax
