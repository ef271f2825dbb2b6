"""Plots of a :class:`~rotorkit.periodic.branch.Branch`: response curve, orbit, harmonic content (``ax=None`` in,
the axes out, drawing on the given or current axes)."""

from __future__ import annotations

import numpy as np

from ..errors import ParameterError

__all__ = ["plot_branch_response", "plot_branch_orbit", "plot_branch_harmonics"]

_LENGTH = {"m": 1.0, "mm": 1e3, "um": 1e6}
_MARKERS = {"fold": "o", "grazing fold": "^", "period doubling": "s", "Neimark-Sacker": "D"}


def _factor(units):
    try:
        return _LENGTH[units]
    except KeyError:
        raise ParameterError(f"units={units!r} is unknown: expected one of {list(_LENGTH)}") from None


def _axes(ax):
    if ax is None:
        import matplotlib.pyplot as plt

        ax = plt.gca()
    return ax


def _parameter_axis(branch):
    if branch.parameter_name == branch.speed_parameter:
        return branch.parameter, f"{branch.parameter_name} (rad/s)"
    return branch.parameter, branch.parameter_name + " (SI)"


def plot_branch_response(branch, station=None, *, coordinate=None, ax=None, units="mm", color=None, label=None):
    """Max orbit radius of ``station`` (or the harmonic-1 amplitude of ``coordinate``) along the branch.

    Stable stretches solid, unstable dashed (solid throughout when stability was not computed);
    bifurcations marked (o fold, ^ grazing fold, s period doubling, D Neimark-Sacker).
    """
    ax = _axes(ax)
    f = _factor(units)
    if (station is None) == (coordinate is None):
        raise ParameterError("give one of station=... or coordinate=...")
    if station is not None:
        y, what = branch.max_radius(station) * f, f"max radius at station {station} ({units})"
    else:
        y, what = branch.harmonic_amplitude(coordinate, branch.subharmonic) * f, f"|{coordinate}| harmonic 1 ({units})"
    x, xlabel = _parameter_axis(branch)
    stable = branch.stable if branch.stable is not None else np.ones(len(x), dtype=bool)
    line = None
    start = 0
    for i in range(1, len(x) + 1):
        if i == len(x) or stable[i] != stable[start]:
            stop = min(i + 1, len(x))
            style = "-" if stable[start] else "--"
            (line,) = ax.plot(x[start:stop], y[start:stop], style, color=color if line is None else line.get_color(),
                              label=label if start == 0 else None)
            start = i
    for b in branch.bifurcations:
        ax.plot([b.parameter], [y[b.index]], _MARKERS.get(b.kind, "x"), color="k", mfc="none")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(what)
    return ax


def plot_branch_orbit(branch, i, station, *, ax=None, units="mm", **kwargs):
    """The orbit (x, y) of ``station`` at point ``i``, equal axes."""
    ax = _axes(ax)
    f = _factor(units)
    x, y = branch.orbit(i, station)
    ax.plot(x * f, y * f, **kwargs)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"x{station} ({units})")
    ax.set_ylabel(f"y{station} ({units})")
    ax.set_title(f"{branch.parameter_name} = {branch.parameter[branch._point(i)]:.6g}")
    return ax


def plot_branch_harmonics(branch, coordinate, *, ax=None, units="mm"):
    """Amplitude of every harmonic 0 ... H of ``coordinate`` along the branch (log scale)."""
    ax = _axes(ax)
    f = _factor(units)
    x, xlabel = _parameter_axis(branch)
    for k in range(branch.harmonics + 1):
        ax.semilogy(x, np.maximum(branch.harmonic_amplitude(coordinate, k) * f, 1e-30), label=f"k={k}")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(f"|{coordinate}| per harmonic ({units})")
    ax.legend(ncol=2, fontsize="small")
    return ax
