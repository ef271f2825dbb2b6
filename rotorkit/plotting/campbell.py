"""Campbell diagram and mode shapes of a linearised rotor (:mod:`rotorkit.analysis.modes`)."""

import math
import re

import numpy as np

from .basic import new_axes

__all__ = ["plot_campbell", "plot_mode_shape"]

#: frequency units -> factor from rad/s
FREQUENCY_UNITS = {"rad/s": 1.0, "Hz": 1.0 / (2.0 * math.pi), "rpm": 60.0 / (2.0 * math.pi)}


def _factor(units):
    try:
        return FREQUENCY_UNITS[units]
    except (KeyError, TypeError):
        from ..errors import ParameterError

        raise ParameterError(f"units={units!r} is unknown; expected one of {list(FREQUENCY_UNITS)}") from None


def plot_campbell(campbell, ax=None, units="rad/s", *, show_critical=True):
    """Natural frequencies against speed, with the 1x line of each rotor.

    Parameters
    ----------
    campbell : rotorkit.analysis.modes.Campbell
    ax : matplotlib.axes.Axes, optional
    units : {"rad/s", "Hz", "rpm"}
        Unit of both axes (speeds and frequencies), so a 1x line has slope
        1 for the swept rotor.
    show_critical : bool
        Mark where a 1x line crosses a frequency curve.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax, figsize=(6.5, 4.5))
    f = _factor(units)
    speeds = campbell.speeds * f
    for k in range(campbell.n_modes):
        if not np.isfinite(campbell.frequencies[:, k]).any():
            continue  # a mode that does not exist in the swept range gets no legend entry
        ax.plot(speeds, campbell.frequencies[:, k] * f, "-", color=f"C{k % 10}", lw=1.2,
                marker="o" if speeds.size < 30 else None, ms=3, label=f"mode {k + 1}")
    for j, (rotor, line) in enumerate(campbell.rotor_speeds.items()):
        (drawn,) = ax.plot(speeds, line * f, "--", color="k", lw=0.9, alpha=1.0 - 0.35 * (j % 2),
                           label=f"1x {rotor}")
        ax.annotate(f"1x {rotor}", (speeds[-1], line[-1] * f), xytext=(-4, 4), textcoords="offset points",
                    ha="right", va="bottom", fontsize=8, color=drawn.get_color())
    if show_critical:
        crossings = campbell.critical_speeds()
        if crossings:
            xs = np.array([c[2] for c in crossings])
            ys = np.array([np.interp(c[2], campbell.speeds, campbell.rotor_speeds[c[0]]) for c in crossings])
            ax.plot(xs * f, ys * f, "kx", ms=6, label="critical speeds")
    top = np.nanmax(campbell.frequencies) if np.isfinite(campbell.frequencies).any() else 1.0
    ax.set_ylim(0.0, 1.1 * top * f)
    ax.set_xlim(speeds.min(), speeds.max() if speeds.max() > speeds.min() else speeds.min() + 1.0)
    ax.set_xlabel(f"{campbell.speed_parameter} ({units})")
    ax.set_ylabel(f"natural frequency ({units})")
    ax.set_title("Campbell diagram")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=7, loc="upper left")
    return ax


def _station_order(names):
    stations = []
    for name in names:
        m = re.fullmatch(r"[xy](.+)", name)
        if m and m.group(1) not in stations:
            stations.append(m.group(1))
    return stations


def plot_mode_shape(modes, i, ax=None):
    """Bending magnitudes ``|x_s|``, ``|y_s|`` of mode ``i`` along the stations.

    Parameters
    ----------
    modes : rotorkit.analysis.modes.Modes
    i : int
        Mode index (0 is the lowest).
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    Stations are in model order (rotor by rotor). Magnitudes are relative:
    the shape's largest entry is 1 (it may be a torsion angle, listed in the
    title, in which case the bending curves show the coupling).
    """
    shape = modes.shape_of(i)
    ax = new_axes(ax, figsize=(6.5, 3.5))
    stations = _station_order(modes.coordinate_names)
    pos = np.arange(len(stations))
    for axis, style in (("x", "-o"), ("y", "--s")):
        ax.plot(pos, [abs(shape[f"{axis}{s}"]) for s in stations], style, ms=4, label=f"|{axis}|")
    ax.set_xticks(pos, [str(s) for s in stations])
    ax.set_xlabel("station")
    ax.set_ylabel("relative amplitude")
    ax.set_ylim(0.0, 1.05)  # the shape's largest entry is 1: round-off stays invisible
    twist = [f"|{n}| = {abs(v):.3g}" for n, v in shape.items() if n.startswith("alpha")]
    idx = modes._index(i)
    title = (f"mode {idx + 1}: {modes.frequencies[idx]:.4g} rad/s ({modes.frequencies[idx] / (2 * math.pi):.4g} Hz), "
             f"zeta = {modes.damping_ratios[idx]:.3g}")
    if twist:
        title += "\n" + ", ".join(twist)
    ax.set_title(title, fontsize=9)
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8)
    return ax
