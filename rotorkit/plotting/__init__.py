"""Plotting functions: take data, ``ax=None``, return matplotlib objects.

matplotlib's convention: a plot draws on the given ``ax=`` or on pyplot's
current axes (a new figure when none is open), so ``plt.savefig()`` after
a plot call saves it; :func:`~rotorkit.plotting.basic.standalone_figures`
keeps pyplot out of a program that writes many figures. No matplotlib
setting is changed and pyplot is imported only when a plot is drawn.
"""

from .basic import plot_orbit, plot_signals

__all__ = ["plot_orbit", "plot_signals"]
