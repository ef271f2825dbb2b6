"""Critical speed map (:mod:`rotorkit.linear.critical_map`)."""

import numpy as np

from .basic import legend_beside, new_axes

__all__ = ["plot_critical_speed_map"]


def plot_critical_speed_map(cmap, ax=None, *, units="rpm", show_backward=False):
    """Critical speeds against support stiffness on log-log axes, bearing curves overlaid.

    Parameters
    ----------
    cmap : rotorkit.linear.critical_map.CriticalSpeedMap
    ax : matplotlib.axes.Axes, optional
    units : {"rad/s", "Hz", "rpm"}
        Unit of the speed axis.
    show_backward : bool
        Also draw the backward critical speeds (dashed).

    Returns
    -------
    matplotlib.axes.Axes
    """
    from ..units import display_factor

    f = display_factor(units, "speed")
    ax = new_axes(ax, figsize=(6.0, 4.5))
    for j in range(cmap.speeds.shape[1]):
        if np.any(np.isfinite(cmap.speeds[:, j])):  # none of this order in the range: no empty legend entry
            ax.loglog(cmap.stiffnesses, cmap.speeds[:, j] * f, "-", color=f"C{j % 10}", lw=1.4,
                      label=f"critical speed {j + 1}")
        if show_backward:
            ax.loglog(cmap.stiffnesses, cmap.backward[:, j] * f, "--", color=f"C{j % 10}", lw=1.0)
    # one shade per bearing, one line style per direction ("<bearing> kxx", "<bearing> kyy")
    bearings = list(dict.fromkeys(label.rsplit(" ", 1)[0] for label in cmap.bearing_curves))
    shades = {name: str(0.55 * i / max(len(bearings) - 1, 1)) for i, name in enumerate(bearings)}
    for i, (label, (speeds, stiffness)) in enumerate(cmap.bearing_curves.items()):
        style = "-." if label.endswith("kyy") else ":"
        ax.loglog(np.asarray(stiffness), np.asarray(speeds) * f, style, color=shades[label.rsplit(" ", 1)[0]],
                  lw=1.4, label=label)
    ax.set_xlabel("support stiffness (N/m)")
    ax.set_ylabel(f"critical speed ({units})")
    ax.set_title(f"undamped critical speed map (supports at {', '.join(cmap.supports)})", fontsize=9)
    ax.grid(True, which="both", lw=0.3)
    legend_beside(ax, fontsize=7)
    return ax
