"""Axis orbits and time histories, and where every plot function draws.

Plot functions follow matplotlib's convention: given ``ax=`` they draw
there; without it they draw through pyplot, so ``plt.savefig()`` and
``plt.show()`` after a plot call work as with any matplotlib function. They
use the current axes when nothing is drawn on them yet (after
``plt.figure()``, ``plt.subplots()`` or ``plt.sca(ax)``), else a new pyplot
figure of the plot's own size, which becomes the current one: two plot
calls in a row never draw over each other (pass ``ax=`` to overlay).
Inside :func:`standalone_figures` (the command line uses it) they draw on
new ``matplotlib.figure.Figure`` objects that pyplot never sees instead.
pyplot is imported only when a plot is drawn, never at import.
"""

import contextlib
import contextvars

import numpy as np

__all__ = ["plot_orbit", "plot_signals", "new_axes", "new_axes_pair", "standalone_figures", "signal_unit",
           "scaled_unit", "LENGTH_UNITS"]

#: output length units -> factor from metres
LENGTH_UNITS = {"m": 1.0, "mm": 1e3, "um": 1e6}

_STANDALONE = contextvars.ContextVar("rotorkit_standalone_figures", default=False)


@contextlib.contextmanager
def standalone_figures():
    """Within the block, plots without ``ax=`` go on new standalone Figures, not on pyplot's current axes.

    For programs that write many figures (the command line): no pyplot
    state, nothing to close, no figure drawn over another.
    """
    token = _STANDALONE.set(True)
    try:
        yield
    finally:
        _STANDALONE.reset(token)


def _new_figure(figsize):
    if _STANDALONE.get():
        from matplotlib.figure import Figure

        return Figure(figsize=figsize, layout="constrained")
    import matplotlib.pyplot as plt

    return plt.figure(figsize=figsize, layout="constrained")


def _current_figure():
    """pyplot's current figure, or None (none open, or standalone figures wanted)."""
    if _STANDALONE.get():
        return None
    import matplotlib.pyplot as plt

    return plt.gcf() if plt.get_fignums() else None


def new_axes(ax=None, figsize=(6.0, 4.0), projection=None):
    """``ax`` itself, else pyplot's current axes if empty and of the kind asked, else the axes of a new figure.

    ``projection``: ``None`` for ordinary 2-D axes, ``"3d"``. An empty
    current figure gets a subplot of that kind. See the module notes.
    """
    if ax is not None:
        return ax
    fig = _current_figure()
    if fig is not None:
        if not fig.axes:
            return fig.add_subplot(projection=projection)
        current = fig.gca()
        if current.name == (projection or "rectilinear") and not current.has_data():
            return current
    return _new_figure(figsize).add_subplot(projection=projection)


def new_axes_pair(axes=None, figsize=(6.5, 5.0)):
    """``axes`` itself, else two stacked axes sharing x, on the current figure if it is empty, else on a new one."""
    if axes is not None:
        return axes
    fig = _current_figure()
    if fig is None or fig.axes:
        fig = _new_figure(figsize)
    top = fig.add_subplot(2, 1, 1)
    return top, fig.add_subplot(2, 1, 2, sharex=top)


def legend_beside(ax, *args, fontsize=8, **kwargs):
    """The legend outside the axes, to the right of the data (the figure's constrained layout makes room)."""
    return ax.legend(*args, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=fontsize, borderaxespad=0.0,
                     **kwargs)


def _factor(units):
    from ..units import display_factor

    return display_factor(units, "length")


def plot_orbit(result, station, ax=None, *, units="um", start=None, end=None, clearance=None, **line_kwargs):
    """Axis orbit ``(x, y)`` of a station.

    Parameters
    ----------
    result : rotorkit.Result
    station : int or str
    ax : matplotlib.axes.Axes, optional
    units : {"m", "mm", "um"}
        Length unit of the axes.
    start, end : float, optional
        Time window (s).
    clearance : float, optional
        Draw a circle of this radius (m), e.g. the rub clearance.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax, figsize=(5.6, 5.0))
    f = _factor(units)
    unit = "µm" if units == "um" else units
    t = result.t
    keep = (t >= (start if start is not None else t[0])) & (t <= (end if end is not None else t[-1]))
    x, y, t = result[f"x{station}"][keep] * f, result[f"y{station}"][keep] * f, t[keep]  # (not all states)
    if line_kwargs or t.size < 2:
        ax.plot(x, y, lw=0.4, **line_kwargs)
    else:  # colour shows time, so the path through a manoeuvre can be followed
        lines = _time_coloured_path(x, y, t)
        ax.add_collection(lines)
        ax.autoscale_view()
        ax.figure.colorbar(lines, ax=ax, label="time t (s)", shrink=0.8)
    title = f"{result.name}: axis orbit of station {station}, {t[0]:g}-{t[-1]:g} s" if t.size else result.name
    if clearance is not None:
        th = np.linspace(0, 2 * np.pi, 361)
        ax.plot(clearance * f * np.cos(th), clearance * f * np.sin(th), "k--", lw=0.8)
        title += f"\ndashed circle: clearance {clearance * f:.4g} {unit}"
    window = _maneuver_window(result)
    if window is not None and t.size and window[0] < t[-1]:
        title += f"; manoeuvre {window[0]:g}-{window[1]:g} s"
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"horizontal displacement x{station} ({unit})")
    ax.set_ylabel(f"vertical displacement y{station} ({unit})")
    ax.set_title(title, fontsize=9)
    return ax


def _time_coloured_path(x, y, t, cmap="viridis", linewidths=0.5):
    """The path ``(x, y)`` as a LineCollection coloured by time, one polyline per colour of the colour map.

    Each segment takes the colour of its mid-time, as if every segment were a
    line of its own, but the segments that fall on the same of the colour
    map's (256) colours are drawn as one polyline: a long orbit (60,000
    samples) draws in a fraction of the time, with the same colours.
    """
    from matplotlib import colormaps
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize

    mid = 0.5 * (t[:-1] + t[1:])
    colours = colormaps[cmap]
    norm = Normalize(vmin=mid.min(), vmax=mid.max())
    # the colour map's own quantisation of a value into one of its N entries (as Colormap.__call__ does it)
    index = np.clip((np.ma.getdata(norm(mid)) * colours.N).astype(int), 0, colours.N - 1)
    starts = np.flatnonzero(np.r_[True, index[1:] != index[:-1]])
    ends = np.r_[starts[1:], mid.size]
    points = np.column_stack([x, y])
    lines = LineCollection([points[a:b + 1] for a, b in zip(starts, ends)], cmap=colours, norm=norm,
                           linewidths=linewidths)
    lines.set_array(mid[starts])
    return lines


def _maneuver_window(result):
    """(start, end) of a manoeuvre in the result's parameters, or None."""
    start, end = result.parameters.get("maneuver_roll_start"), result.parameters.get("maneuver_roll_end")
    return None if start is None or end is None else (float(start), float(end))


#: SI unit of a coordinate's signal, by its name
def signal_unit(name):
    """SI unit of a named signal: m for x/y, rad for alpha, per second for ``_dot`` (differences alike)."""
    base = name.split("-")[0].strip()
    speed = base.endswith("_dot")
    unit = "rad" if base.startswith("alpha") else "m"
    return f"{unit}/s" if speed else unit


#: unit prefixes of the usual display scales
_PREFIXES = {1e3: "m", 1e6: "µ", 1e9: "n"}


def scaled_unit(unit, scale=1.0):
    """The unit of ``values * scale`` for values in ``unit``: ``("m", 1e6) -> "µm"``, ``("rad", 2.0) -> "0.5 rad"``.

    >>> scaled_unit("m", 1e6), scaled_unit("rad/s", 1e3), scaled_unit("m", 4.0)
    ('µm', 'mrad/s', '0.25 m')
    """
    if scale == 1.0:
        return unit
    if scale in _PREFIXES:
        return _PREFIXES[scale] + unit
    return f"{1.0 / scale:.3g} {unit}"


def plot_signals(result, names, ax=None, *, scale=1.0, unit_label="", highpass=None, **line_kwargs):
    """Time histories of named signals (``"x2"``, ``"alpha2-alpha5"``).

    Parameters
    ----------
    result : rotorkit.Result
    names : str or sequence of str
    ax : matplotlib.axes.Axes, optional
    scale : float
        Factor applied to the signals (e.g. 1e6 for µm).
    unit_label : str
        Unit shown on the y axis.
    highpass : float, optional
        Cut-off (Hz) of a zero-phase high-pass filter applied first.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax, figsize=(8.0, 3.5))
    if isinstance(names, str):
        names = [names]
    for name in names:
        x = result[name]
        if highpass is not None:
            from ..signals import highpass as hp

            x = hp(result.t, x, highpass)
        ax.plot(result.t, x * scale, lw=0.5, label=name, **line_kwargs)
    units = sorted({signal_unit(n) for n in names})
    if not unit_label:  # SI (scaled), named from the signals themselves
        unit_label = scaled_unit(units[0], scale) if len(units) == 1 else ""
    quantity = {"m": "displacement", "rad": "torsional angle", "m/s": "velocity", "rad/s": "angular velocity"}
    what = ", ".join(sorted({quantity.get(u, "signal") for u in units}))
    ax.set_xlabel("time t (s)")
    shown = unit_label or ", ".join(f"{n}: {scaled_unit(signal_unit(n), scale)}" for n in names)
    ax.set_ylabel(f"{what} {', '.join(names)} ({shown})")
    window = _maneuver_window(result)
    if window is not None and result.t.size and window[0] < result.t[-1]:
        ax.axvspan(window[0], min(window[1], result.t[-1]), color="0.9", zorder=0, label="manoeuvre")
    legend_beside(ax)
    ax.set_title(f"{result.name}: {', '.join(names)} against time"
                 + (f" (high-pass {highpass:g} Hz)" if highpass else ""), fontsize=10)
    return ax
