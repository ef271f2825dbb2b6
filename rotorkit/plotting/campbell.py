"""Campbell and stability diagrams (:mod:`rotorkit.linear.campbell`)."""

import math

import numpy as np

from .basic import legend_beside, new_axes
from .modes import plot_mode_shape

__all__ = ["plot_campbell", "plot_log_decrement", "plot_mode_shape", "WHIRL_STYLES"]

#: frequency units -> factor from rad/s
FREQUENCY_UNITS = {"rad/s": 1.0, "Hz": 1.0 / (2.0 * math.pi), "rpm": 60.0 / (2.0 * math.pi)}
#: whirl -> line style of a mode's segments
WHIRL_STYLES = {"forward": "-", "backward": "--", "mixed": ":", "linear": "-.", "": ":"}


def _factor(units, name="units"):
    from ..units import display_factor

    return display_factor(units, "speed", name)


def _segments(x, y, kinds):
    """Runs of equal whirl: [(kind, x, y)], neighbouring runs sharing their end point."""
    out, start = [], 0
    for i in range(1, len(x) + 1):
        if i == len(x) or kinds[i] != kinds[start]:
            stop = min(i + 1, len(x))
            out.append((kinds[start], x[start:stop], y[start:stop]))
            start = i
    return out


def plot_campbell(campbell, ax=None, units="rad/s", *, show_critical=True, frequency_units=None):
    """Damped natural frequencies against speed: forward solid, backward dashed, mixed dotted.

    Parameters
    ----------
    campbell : rotorkit.linear.campbell.Campbell
    ax : matplotlib.axes.Axes, optional
    units : {"rad/s", "Hz", "rpm"}
        Unit of the speed axis (and of the frequency axis unless
        ``frequency_units`` is given): in one unit a 1x line has slope 1.
    show_critical : bool
        Mark the critical speeds (crossings located by root finding).
    frequency_units : {"rad/s", "Hz", "rpm"}, optional

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax, figsize=(6.5, 4.5))
    fs = _factor(units)
    ff = _factor(frequency_units or units)
    speeds = campbell.speeds * fs
    marker = "o" if speeds.size < 30 else None
    for k in range(campbell.n_modes):
        if not np.isfinite(campbell.frequencies[:, k]).any():
            continue  # a mode that does not exist in the swept range gets no legend entry
        colour = f"C{k % 10}"
        first = True
        for kind, xs, ys in _segments(speeds, campbell.frequencies[:, k] * ff, list(campbell.whirl[:, k])):
            ax.plot(xs, ys, WHIRL_STYLES.get(kind, ":"), color=colour, lw=1.3, marker=marker, ms=3,
                    label=f"mode {k + 1}" if first else None)
            first = False
    for j, (rotor, line) in enumerate(campbell.rotor_speeds.items()):
        for order in campbell.orders:
            (drawn,) = ax.plot(speeds, order * line * ff, color="k" if j == 0 else "0.45", lw=0.9,
                               ls=(0, (6, 2)) if j == 0 else (0, (2, 2)), label=f"{order:g}x {rotor}")
            ax.annotate(f"{order:g}x {rotor}", (speeds[-1], order * line[-1] * ff), xytext=(-4, 4),
                        textcoords="offset points", ha="right", va="bottom", fontsize=8, color=drawn.get_color())
    if show_critical and campbell.crossings:
        xs = np.array([c.speed for c in campbell.crossings]) * fs
        ys = np.array([c.frequency for c in campbell.crossings]) * ff
        ax.plot(xs, ys, "kx", ms=7, mew=1.5, label="critical speeds")
    from matplotlib.lines import Line2D

    handles, labels = ax.get_legend_handles_labels()
    for kind in ("forward", "backward", "mixed"):
        if np.any(campbell.whirl == kind):
            handles.append(Line2D([], [], color="0.3", ls=WHIRL_STYLES[kind]))
            labels.append(kind)
    top = np.nanmax(campbell.frequencies) if np.isfinite(campbell.frequencies).any() else 1.0
    ax.set_ylim(0.0, 1.1 * top * ff)
    ax.set_xlim(speeds.min(), speeds.max() if speeds.max() > speeds.min() else speeds.min() + 1.0)
    ax.set_xlabel(f"{campbell.speed_parameter} ({units})")
    ax.set_ylabel(f"damped natural frequency ({frequency_units or units})")
    ax.set_title("Campbell diagram")
    ax.grid(True, lw=0.3)
    legend_beside(ax, handles, labels, fontsize=7)  # beside the lines, never over them
    return ax


def plot_log_decrement(campbell, ax=None, units="rad/s", *, show_onset=True):
    """Logarithmic decrement of each tracked mode against speed (stability diagram).

    Parameters
    ----------
    campbell : rotorkit.linear.campbell.Campbell
    ax : matplotlib.axes.Axes, optional
    units : {"rad/s", "Hz", "rpm"}
        Unit of the speed axis.
    show_onset : bool
        Mark the speeds where a log decrement crosses zero.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax, figsize=(6.5, 3.5))
    fs = _factor(units)
    speeds = campbell.speeds * fs
    for k in range(campbell.n_modes):
        first = True
        for kind, xs, ys in _segments(speeds, campbell.log_decrements[:, k], list(campbell.whirl[:, k])):
            ax.plot(xs, ys, WHIRL_STYLES.get(kind, ":"), color=f"C{k % 10}", lw=1.3,
                    label=f"mode {k + 1}" if first else None)
            first = False
    ax.axhline(0.0, color="k", lw=0.8)
    if show_onset and campbell.onsets:
        ax.plot([o.speed * fs for o in campbell.onsets], [0.0] * len(campbell.onsets), "rv", ms=7,
                label="stability limit")
    ax.set_xlabel(f"{campbell.speed_parameter} ({units})")
    ax.set_ylabel("logarithmic decrement (-)")
    ax.set_title("Stability diagram")
    ax.grid(True, lw=0.3)
    legend_beside(ax, fontsize=7)
    return ax
