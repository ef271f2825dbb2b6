"""Axis orbits and time histories."""

import numpy as np

__all__ = ["plot_orbit", "plot_signals", "new_axes", "LENGTH_UNITS"]

#: output length units -> factor from metres
LENGTH_UNITS = {"m": 1.0, "mm": 1e3, "um": 1e6}


def new_axes(ax=None, figsize=(6.0, 4.0)):
    """``ax`` itself, or the axes of a new Figure (no pyplot)."""
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    return Figure(figsize=figsize, layout="constrained").add_subplot()


def _factor(units):
    try:
        return LENGTH_UNITS[units]
    except KeyError:
        from ..errors import ParameterError

        raise ParameterError(f"units={units!r} is unknown; expected one of {sorted(LENGTH_UNITS)}") from None


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
    ax = new_axes(ax, figsize=(5.0, 5.0))
    f = _factor(units)
    r = result.window(start if start is not None else result.t[0], end if end is not None else result.t[-1])
    ax.plot(r[f"x{station}"] * f, r[f"y{station}"] * f, lw=0.4, **line_kwargs)
    if clearance is not None:
        th = np.linspace(0, 2 * np.pi, 361)
        ax.plot(clearance * f * np.cos(th), clearance * f * np.sin(th), "k--", lw=0.8, label="clearance")
        ax.legend(loc="upper right")
    ax.set_aspect("equal", adjustable="datalim")
    unit = "µm" if units == "um" else units
    ax.set_xlabel(f"x{station} ({unit})")
    ax.set_ylabel(f"y{station} ({unit})")
    ax.set_title(f"{result.name}: axis orbit at station {station}")
    return ax


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
            from ..analysis.signals import highpass as hp

            x = hp(result.t, x, highpass)
        ax.plot(result.t, x * scale, lw=0.5, label=name, **line_kwargs)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"{', '.join(names)}" + (f" ({unit_label})" if unit_label else ""))
    ax.legend(loc="upper right")
    ax.set_title(result.name + (f" (high-pass {highpass:g} Hz)" if highpass else ""))
    return ax
