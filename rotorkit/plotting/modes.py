"""Mode shapes as whirl orbits along the shaft (:class:`rotorkit.analysis.modal.Modes`)."""

import math

import numpy as np

from .basic import legend_beside, new_axes

__all__ = ["plot_mode_shape", "plot_mode_orbits"]


def _positions(modes):
    """Axial positions (m) of the stations and the axis label; station order when positions are unknown."""
    stations = modes.stations
    if modes.station_positions and all(s in modes.station_positions for s in stations):
        return np.array([modes.station_positions[s] for s in stations]), "axial position (m)", False
    return np.arange(len(stations), dtype=float), "station", True


def _title(modes, i):
    return (f"mode {i + 1}: {modes.eigenvalues[i].imag:.4g} rad/s ({modes.eigenvalues[i].imag / (2 * math.pi):.4g} Hz) "
            f"damped, log dec {modes.log_decrements[i]:.3g}, {modes.whirl[i]} whirl"
)


def plot_mode_shape(modes, mode, ax=None):
    """Semi-major and semi-minor axes of the whirl orbits of ``mode`` (1-based) along the shaft.

    Parameters
    ----------
    modes : rotorkit.analysis.modal.Modes
    mode : int
        Mode number (1 is the lowest).
    ax : matplotlib.axes.Axes, optional

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    Stations at their axial position when the model has one, else in model
    order. Sizes are relative: the shape's largest entry is 1. Forward-whirling
    stations are marked with circles, backward ones with crosses.
    """
    i = modes._index(mode)
    orbits = modes.orbits(mode)
    ax = new_axes(ax, figsize=(6.5, 3.5))
    pos, label, ordinal = _positions(modes)
    major = np.array([o.major for o in orbits.values()])
    minor = np.array([o.minor for o in orbits.values()])
    kinds = [o.direction for o in orbits.values()]
    ax.plot(pos, major, "-", color="C0", label="semi-major axis")
    ax.plot(pos, minor, "--", color="C1", label="semi-minor axis")
    for kind, marker in (("forward", "o"), ("backward", "x"), ("linear", "s")):
        sel = [j for j, k in enumerate(kinds) if k == kind]
        if sel:
            ax.plot(pos[sel], major[sel], marker, color="k", ms=5, ls="none", label=f"{kind} whirl")
    if ordinal:
        ax.set_xticks(pos, list(modes.stations))
    ax.set_xlabel(label)
    ax.set_ylabel("relative orbit size (-)")
    ax.set_ylim(0.0, 1.05 * max(float(major.max()) if major.size else 1.0, 1e-12))
    twist = [f"|{n}| = {abs(v):.3g}" for n, v in modes.shape_of(mode).items() if n.startswith("alpha")]
    ax.set_title(_title(modes, i) + ("\n" + ", ".join(twist) if twist else ""), fontsize=9)
    ax.grid(True, lw=0.3)
    legend_beside(ax)
    return ax


def plot_mode_orbits(modes, mode, ax=None, *, points=60):
    """3-D view: the whirl orbit of every station of ``mode`` (1-based) along the shaft axis.

    Returns
    -------
    mpl_toolkits.mplot3d.axes3d.Axes3D
    """
    i = modes._index(mode)
    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(7.0, 4.5), layout="constrained").add_subplot(projection="3d")
    pos, label, _ = _positions(modes)
    from ..analysis.whirl import station_pairs

    orbits = modes.orbits(mode)
    v = modes.shapes[:, i]
    tau = np.linspace(0.0, 2.0 * np.pi, points)
    centre_x, centre_y = [], []
    for z, (s, ix, iy) in zip(pos, station_pairs(modes.coordinate_names)):
        x, y = (v[ix] * np.exp(1j * tau)).real, (v[iy] * np.exp(1j * tau)).real
        ax.plot(np.full_like(x, z), x, y, color="C0" if orbits[s].direction == "forward" else "C3", lw=1.0)
        centre_x.append(x[0])  # the deflected shaft line at t = 0
        centre_y.append(y[0])
    ax.plot(pos, centre_x, centre_y, "k-o", ms=3, lw=1.0)
    ax.plot(pos, np.zeros_like(pos), np.zeros_like(pos), color="0.6", lw=0.8)
    ax.set_xlabel(label)
    ax.set_ylabel("x, relative to the largest (-)")
    ax.set_zlabel("y, relative to the largest (-)")
    ax.set_title(_title(modes, i) + "\nblue forward, red backward", fontsize=9)
    return ax
