"""Checks and axes the spectral figures share (:mod:`~rotorkit.plotting.spectra`, :mod:`~rotorkit.plotting.cascade`).

Order lines as ``{label: frequency}``, the frequency range kept (``fmax``),
the amplitude scale, 2-D and 3-D axes, cell edges for ``pcolormesh``, axis
limits and labels.
"""

import math
import numbers
from collections.abc import Mapping

import numpy as np

from ..errors import ParameterError
from .basic import new_axes

__all__ = ["LOG_FLOOR", "positive", "check_orders", "frequency_mask", "check_scale", "axes_3d", "axes_2d",
           "cell_edges", "frequency_label", "default_amplitude_label", "axis_limits"]

#: colour-scale floor of log colour maps, relative to the largest amplitude
LOG_FLOOR = 1e-4


def positive(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
        raise ParameterError(f"{name}={value!r}: expected a finite number > 0")
    return float(value)


def check_orders(orders, units):
    """Orders as {label: frequency}; None -> {}."""
    if orders is None:
        return {}
    if not isinstance(orders, Mapping):
        raise ParameterError(f"orders={orders!r}: expected a mapping of labels to frequencies in {units}")
    out = {}
    for label, value in orders.items():
        if not isinstance(label, str) or not label:
            raise ParameterError(f"orders has the label {label!r}: expected non-empty strings")
        out[label] = positive(value, f"orders[{label!r}] ({units})")
    return out


def frequency_mask(frequency, fmax, units):
    if fmax is None:
        return np.ones(frequency.size, dtype=bool)
    fmax = positive(fmax, f"fmax ({units})")
    mask = frequency <= fmax
    if frequency.size and np.count_nonzero(mask) < 2:
        raise ParameterError(f"fmax={fmax!r} {units} keeps fewer than 2 frequency bins (bin spacing "
                             f"{frequency[1] - frequency[0]:.4g} {units})")
    return mask


def check_scale(scale):
    return positive(scale, "scale")


def axes_3d(ax, figsize=(7.5, 5.5)):
    if ax is None:
        ax = new_axes(None, figsize=figsize, projection="3d")
        ax.view_init(elev=30.0, azim=-65.0)
        return ax
    if getattr(ax, "name", None) != "3d":
        raise ParameterError("ax must be a 3-D axes (add_subplot(projection='3d')) for this plot")
    return ax


def axes_2d(ax, figsize=(7.0, 4.5)):
    if ax is not None and getattr(ax, "name", None) == "3d":
        raise ParameterError("ax is a 3-D axes; this plot needs a 2-D one")
    return new_axes(ax, figsize=figsize)


def cell_edges(centres):
    """Cell edges around sorted centres (for pcolormesh)."""
    centres = np.asarray(centres, dtype=float)
    if centres.size == 1:
        half = 0.5 * abs(centres[0]) or 0.5
        return np.array([centres[0] - half, centres[0] + half])
    mid = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate([[2 * centres[0] - mid[0]], mid, [2 * centres[-1] - mid[-1]]])


def frequency_label(units):
    return f"frequency ({units})"


def default_amplitude_label(signal=None, scale=1.0):
    """Default amplitude axis label: quantity and unit, with the unit the scale implies.

    >>> default_amplitude_label("x2", 1e6)
    'x2 amplitude (µm)'
    >>> default_amplitude_label("alpha2-alpha5")
    'alpha2-alpha5 amplitude (rad)'
    >>> default_amplitude_label(None, 1e6)
    'amplitude (µ[signal unit])'
    """
    from .basic import scaled_unit, signal_unit

    shown = scaled_unit(signal_unit(signal) if signal else "[signal unit]", scale)
    return f"{signal} amplitude ({shown})" if signal else f"amplitude ({shown})"


def axis_limits(low, high):
    """(low, high), widened around ``low`` when the range is empty."""
    if np.isfinite(low) and np.isfinite(high) and high > low:
        return float(low), float(high)
    low = float(low) if np.isfinite(low) else 0.0
    pad = 0.05 * abs(low) or 1.0
    return low - pad, low + pad
