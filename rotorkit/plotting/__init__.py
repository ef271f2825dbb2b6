"""Plotting functions: take data, ``ax=None``, return matplotlib objects.

No pyplot state is touched: without ``ax`` a new ``matplotlib.figure.Figure``
is made, so these work headless and never change global settings.
"""

from .basic import plot_orbit, plot_signals

__all__ = ["plot_orbit", "plot_signals"]
