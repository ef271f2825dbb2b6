"""Bode, polar and FRF plots (:mod:`rotorkit.linear.unbalance`, :mod:`rotorkit.linear.frf`)."""

import numpy as np

from .basic import legend_beside, new_axes, new_axes_pair

__all__ = ["plot_unbalance_bode", "plot_unbalance_polar", "plot_frf", "plot_static_deflection"]

_SPEED, LENGTH_UNITS = "speed", "length"


def _check(kind, units, name="units"):
    from ..units import display_factor

    return display_factor(units, kind, name)


def _two_axes(axes, figsize=(6.5, 5.0)):
    return new_axes_pair(axes, figsize)


def plot_unbalance_bode(response, coordinate, *, rotor=None, axes=None, units="rad/s", length_units="um",
                        log=True):
    """Amplitude and phase of one coordinate's unbalance response against speed.

    Parameters
    ----------
    response : rotorkit.linear.unbalance.UnbalanceResponse
    coordinate : str
        E.g. ``"x2"``.
    rotor : str, optional
        Which spool's component (required when several rotors carry unbalance).
    axes : (Axes, Axes), optional
    units : {"rad/s", "Hz", "rpm"}
        Speed axis.
    length_units : {"m", "mm", "um"}
    log : bool
        Logarithmic amplitude axis.

    Returns
    -------
    (matplotlib.axes.Axes, matplotlib.axes.Axes)
    """
    fs, fl = _check(_SPEED, units), _check(LENGTH_UNITS, length_units, "length_units")
    top, bottom = _two_axes(axes)
    x = response.speeds * fs
    top.plot(x, response.amplitude(coordinate, rotor) * fl, "-", lw=1.3)
    if log:
        top.set_yscale("log")
    top.set_ylabel(f"amplitude |{coordinate}| ({length_units})")
    top.set_title(f"unbalance response of {coordinate}")
    bottom.plot(x, np.degrees(np.unwrap(response.phase(coordinate, rotor))), "-", lw=1.3)
    bottom.set_ylabel(f"phase of {coordinate} (deg)")
    bottom.set_xlabel(f"{response.speed_parameter} ({units})")
    for ax in (top, bottom):
        ax.grid(True, lw=0.3)
    return top, bottom


def plot_unbalance_polar(response, coordinate, *, rotor=None, ax=None, length_units="um", units="rad/s"):
    """The complex response of one coordinate over speed in its complex plane (polar plot).

    Returns
    -------
    matplotlib.axes.Axes
    """
    fl = _check(LENGTH_UNITS, length_units, "length_units")
    fs = _check(_SPEED, units)
    ax = new_axes(ax, figsize=(5.0, 5.0))
    z = response.response(coordinate, rotor) * fl
    ax.plot(z.real, z.imag, "-", lw=1.3)
    for i in np.linspace(0, z.size - 1, min(z.size, 6)).astype(int):
        ax.annotate(f"{response.speeds[i] * fs:.4g}", (z.real[i], z.imag[i]), fontsize=7)
    ax.plot([0.0], [0.0], "k+")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"Re {coordinate} ({length_units})")
    ax.set_ylabel(f"Im {coordinate} ({length_units})")
    ax.set_title(f"polar plot of {coordinate} (labels: {response.speed_parameter} in {units})", fontsize=9)
    ax.grid(True, lw=0.3)
    return ax


def plot_frf(frf, output, input, *, axes=None, units="rad/s"):
    """Magnitude (log) and phase of one FRF against frequency.

    Returns
    -------
    (matplotlib.axes.Axes, matplotlib.axes.Axes)
    """
    fs = _check(_SPEED, units)
    top, bottom = _two_axes(axes)
    H = frf(output, input)
    x = frf.frequencies * fs
    top.semilogy(x, np.abs(H), lw=1.3)
    top.set_ylabel(f"|{frf.kind}| ({frf.units})")
    top.set_title(f"{frf.kind} {output}/{input} at speed {frf.speed * fs:.6g} {units}")
    bottom.plot(x, np.degrees(np.angle(H)), lw=1.3)
    bottom.set_ylabel("phase (deg)")
    bottom.set_xlabel(f"frequency ({units})")
    for ax in (top, bottom):
        ax.grid(True, lw=0.3)
    return top, bottom


def plot_static_deflection(static, ax=None, *, length_units="um", rotor=True):
    """Static deflection x and y of every station, with each support's largest reaction (N) annotated.

    Parameters
    ----------
    static : rotorkit.analysis.static.StaticDeflection
    ax : matplotlib.axes.Axes, optional
        Drawn on (default the current axes).
    length_units : str
        Deflection units (``"um"``, ``"mm"``, ``"m"`` ...).
    rotor : bool
        Draw the rotor (shaft outline, disks, bearings) under the deflection,
        as the mode-shape plots do, when the result carries its layout and
        the stations have axial positions.

    Returns
    -------
    matplotlib.axes.Axes
    """
    fl = _check(LENGTH_UNITS, length_units, "length_units")
    ax = new_axes(ax, figsize=(6.5, 3.5))
    stations = static.stations
    if static.station_positions and all(s in static.station_positions for s in stations):
        pos, label = np.array([static.station_positions[s] for s in stations]), "axial position (m)"
    else:
        pos, label = np.arange(len(stations), dtype=float), "station"
        ax.set_xticks(pos, list(stations))
    for axis, style in (("x", "-o"), ("y", "-s")):
        ax.plot(pos, [static.deflection[f"{axis}{s}"] * fl for s in stations], style, ms=4, label=axis)
    where = {f"{axis}{s}": (p, axis) for p, s in zip(pos, stations) for axis in "xy"}
    for element, forces in static.reactions.items():  # each support's largest force on the rotor, at its station
        shown = [(abs(v), name, v) for name, v in forces.items() if name in where]
        if shown:
            _, name, value = max(shown)
            p, axis = where[name]
            ax.annotate(f"{element}\nF{axis} = {value:.3g} N", (p, static.deflection[name] * fl), fontsize=6,
                        textcoords="offset points", xytext=(4, 6), color="0.3")
    ax.axhline(0.0, color="0.6", lw=0.8)
    layout = getattr(static, "layout", None)
    if rotor and layout is not None and layout.positions and label != "station":
        from .rotor import draw_rotor

        values = np.array([static.deflection[f"{axis}{s}"] * fl for s in stations for axis in "xy"])
        low, high = min(float(values.min()), 0.0), max(float(values.max()), 0.0)
        height = max(high - low, 1e-300)
        draw_rotor(ax, layout, bottom=low - 0.6 * height, top=low - 0.12 * height)  # a band below the curves
        ax.set_ylim(low - 0.65 * height, high + 0.25 * height)
        ax.set_yticks([t for t in ax.get_yticks() if low - 0.05 * height <= t <= high + 0.05 * height])
    ax.set_xlabel(label)
    ax.set_ylabel(f"static deflection ({length_units})")
    ax.set_title(f"static deflection along the rotor at t = {static.t:g} s", fontsize=9)
    ax.grid(True, lw=0.3)
    legend_beside(ax)
    return ax
