"""Mode shapes as whirl orbits along the shaft (:class:`rotorkit.linear.modal.Modes`), the rotor drawn under them."""

import numpy as np

from .basic import legend_beside, new_axes

__all__ = ["plot_mode_shape", "plot_mode_orbits"]

_MARKERS = {"forward": "o", "backward": "x", "linear": "s"}


def _layout(modes, model):
    """The rotor layout: from ``model`` when given, else the one the modes carry (None without)."""
    if model is not None:
        from .rotor import rotor_layout

        return rotor_layout(model)
    return modes.layout


def _stations(modes, layout):
    """``[(rotor, [(station, position, i_x, i_y)])]``: each spool's stations by axial position, and the axis label.

    Positions from the layout (spools placed), else the modes' own station
    positions, else the station order (one line).
    """
    from ..linear.whirl import station_pairs

    pairs = station_pairs(modes.coordinate_names)
    positions = layout.positions if layout is not None else modes.station_positions
    if positions and all(s in positions for s, _, _ in pairs):
        rotors = layout.rotors if layout is not None else {}
        groups = {}
        for s, ix, iy in pairs:
            groups.setdefault(rotors.get(s), []).append((s, float(positions[s]), ix, iy))
        return [(r, sorted(g, key=lambda item: item[1])) for r, g in groups.items()], "axial position (m)", False
    return [(None, [(s, float(k), ix, iy) for k, (s, ix, iy) in enumerate(pairs)])], "station", True


def _title(modes, i, units):
    from ..units import display_factor

    f = display_factor(units, "speed")
    return (f"mode {i + 1}: {modes.eigenvalues[i].imag * f:.4g} {units} damped, "
            f"log dec {modes.log_decrements[i]:.3g}, {modes.whirl[i]} whirl")


def plot_mode_shape(modes, mode, ax=None, *, model=None, units="rad/s", rotor=True):
    """Whirl orbits of ``mode`` (1-based) along the rotor axis, the rotor drawn underneath.

    Parameters
    ----------
    modes : rotorkit.linear.modal.Modes
    mode : int
        Mode number (1 is the lowest).
    ax : matplotlib.axes.Axes, optional
        Default: pyplot's current axes (see :mod:`rotorkit.plotting.basic`).
    model : rotorkit.Model or System, optional
        The model the modes belong to, for the axial positions of every spool
        and the rotor drawing; default the layout the modes carry (modes of a
        compiled system, :func:`~rotorkit.linear.modes.natural_frequencies`).
    units : str
        Frequency units of the title.
    rotor : bool
        Draw the rotor (shaft outline, disks, bearings) under the shape.

    Returns
    -------
    matplotlib.axes.Axes

    Notes
    -----
    The semi-major (solid) and semi-minor (dashed) axes of each station's
    orbit, normalised by the largest displacement orbit (its peak is 1),
    against axial position; each spool is its own line. Markers give each
    station's whirl (circle forward, cross backward, square a straight
    line). Where stations also tilt, their slope orbits are drawn dotted
    (relative to the largest slope orbit), with their own markers where
    they are significant against the displacements (the slope times the
    rotor's length, :attr:`~rotorkit.linear.modal.Modes.reference_length`,
    as the whirl of a mode weighs it): the mode's whirl in the title (and
    the table) is forward, backward or mixed from all these markers
    together.
    """
    from ..linear.whirl import SIGNIFICANT, orbit, slope_orbit, tilt_pairs

    i = modes._index(mode)
    layout = _layout(modes, model)
    groups, label, ordinal = _stations(modes, layout)
    ax = new_axes(ax, figsize=(7.0, 4.0))
    v = modes.shapes[:, i]
    tilts = {s: (a, b) for s, a, b in tilt_pairs(modes.coordinate_names)}
    length = modes.reference_length  # as the whirl of the mode weighs slopes
    lines = []
    for rotor_name, items in groups:
        pos = np.array([p for _, p, _, _ in items])
        o = orbit(v[[ix for *_, ix, _ in items]], v[[iy for *_, iy in items]])
        slope = [slope_orbit(v[tilts[s][0]], v[tilts[s][1]]) if s in tilts else None for s, *_ in items]
        lines.append((rotor_name, pos, o, slope))
    peak = max((float(np.max(o.major)) for _, _, o, _ in lines if o.major.size), default=0.0)
    slope_peak = max((float(sl.major) * length for *_, slopes in lines for sl in slopes if sl is not None),
                     default=0.0)
    largest = max(peak, slope_peak)
    scale = 1.0 / peak if peak > 0 else (1.0 / largest if largest > 0 else 1.0)
    shown = set()

    def once(text):
        if text in shown:
            return None
        shown.add(text)
        return text

    top = 1.0
    for k, (rotor_name, pos, o, slope) in enumerate(lines):
        colour = f"C{k % 10}"
        suffix = f" ({rotor_name})" if rotor_name is not None and len(lines) > 1 else ""
        ax.plot(pos, o.major * scale, "-", color=colour, label=once(f"semi-major axis{suffix}"))
        ax.plot(pos, o.minor * scale, "--", color=colour, lw=0.9, label=once(f"semi-minor axis{suffix}"))
        significant = (o.major >= SIGNIFICANT * largest) & (o.major > 0)
        for kind, marker in _MARKERS.items():
            sel = [j for j, d in enumerate(np.atleast_1d(o.direction)) if d == kind and significant[j]]
            if sel:
                ax.plot(pos[sel], o.major[sel] * scale, marker, color="k", ms=5, ls="none",
                        label=once(f"{kind} whirl"))
        sizes = np.array([sl.major * length if sl is not None else np.nan for sl in slope], dtype=float)
        if np.isfinite(sizes).any() and slope_peak > 0:
            shown_sizes = sizes / slope_peak  # the slopes on their own scale: the displacements stay readable
            ax.plot(pos, shown_sizes, ":", color=colour, lw=0.9, label=once(f"slope orbit / largest{suffix}"))
            for kind, marker in _MARKERS.items():
                sel = [j for j, sl in enumerate(slope) if sl is not None and sl.direction == kind
                       and sizes[j] >= SIGNIFICANT * largest]
                if sel:
                    ax.plot(pos[sel], shown_sizes[sel], marker, color="0.45", ms=4, ls="none",
                            label=once(f"slope {kind} whirl"))
    if ordinal:
        ax.set_xticks(lines[0][1], [s for s, *_ in groups[0][1]])
    bottom = 0.0
    if rotor and layout is not None and layout.positions and not ordinal:
        from .rotor import draw_rotor

        bottom = -0.55 * top
        draw_rotor(ax, layout, bottom=bottom, top=-0.08 * top)
    ax.set_xlabel(label)
    ax.set_ylabel("relative orbit size (largest displacement = 1)")
    ax.set_ylim(bottom, 1.08 * top)
    if bottom < 0:
        ax.set_yticks([t for t in ax.get_yticks() if 0 <= t <= 1.08 * top])
    twist = [f"|{n}| = {abs(x):.3g}" for n, x in modes.shape_of(mode).items() if n.startswith("alpha")]
    ax.set_title(_title(modes, i, units) + ("\n" + ", ".join(twist) if twist else ""), fontsize=9)
    ax.grid(True, lw=0.3)
    legend_beside(ax)
    return ax


def plot_mode_orbits(modes, mode, ax=None, *, model=None, points=60, units="rad/s"):
    """3-D view: the whirl orbit of every station of ``mode`` (1-based) along the shaft axis.

    Parameters as :func:`plot_mode_shape`; ``ax`` must be a 3-D axes
    (default: pyplot's current one if 3-D, else a new figure). Sizes are
    relative to the largest displacement orbit.

    Returns
    -------
    mpl_toolkits.mplot3d.axes3d.Axes3D
    """
    from ..linear.whirl import orbit

    i = modes._index(mode)
    ax = new_axes(ax, figsize=(7.0, 4.5), projection="3d")
    groups, label, _ = _stations(modes, _layout(modes, model))
    v = modes.shapes[:, i]
    tau = np.linspace(0.0, 2.0 * np.pi, points)
    displacement = [ix for _, items in groups for *_, ix, _ in items] + [iy for _, items in groups
                                                                       for *_, iy in items]
    peak = float(np.max(np.abs(v[displacement]))) if displacement else 1.0
    scale = 1.0 / peak if peak > 0 else 1.0
    for k, (_, items) in enumerate(groups):
        centre_x, centre_y, pos = [], [], []
        for s, z, ix, iy in items:
            x, y = (v[ix] * scale * np.exp(1j * tau)).real, (v[iy] * scale * np.exp(1j * tau)).real
            kind = orbit(v[ix], v[iy]).direction
            ax.plot(np.full_like(x, z), x, y, color="C0" if kind == "forward" else "C3", lw=1.0)
            centre_x.append(x[0])  # the deflected shaft line at t = 0
            centre_y.append(y[0])
            pos.append(z)
        ax.plot(pos, centre_x, centre_y, "-o", color="k" if k == 0 else "0.4", ms=3, lw=1.0)
        ax.plot(pos, np.zeros(len(pos)), np.zeros(len(pos)), color="0.6", lw=0.8)
    ax.set_xlabel(label)
    ax.set_ylabel("x / largest (-)")
    ax.set_zlabel("y / largest (-)")
    ax.set_title(_title(modes, i, units) + "\nblue forward, red backward", fontsize=9)
    return ax
