"""Plot of an energy balance (:mod:`rotorkit.analysis.energy`)."""

from .basic import legend_beside, new_axes

__all__ = ["plot_energy_balance"]


def plot_energy_balance(balance, ax=None, *, channels=True):
    """Plot ``h - h0``, the work of each power channel and the residual against time.

    Parameters
    ----------
    balance : EnergyBalance
    ax : matplotlib.axes.Axes, optional
    channels : bool
        Also draw the work of each channel.

    Returns
    -------
    matplotlib.axes.Axes
    """
    ax = new_axes(ax, figsize=(7.0, 4.0))
    ax.plot(balance.t, balance.h - balance.h[0], label="h - h0", lw=1.5)
    if channels:
        for name, w in balance.work.items():
            ax.plot(balance.t, w, label=f"work: {name}", lw=1)
    ax.plot(balance.t, balance.residual, label="residual", lw=1, color="k")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("energy (J)")
    ax.set_title(f"energy balance: change of h, work per channel, residual (max {balance.relative_residual:.1e} "
                 "of the energy scale)", fontsize=9)
    legend_beside(ax)
    return ax
