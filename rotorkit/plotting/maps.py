"""Maps of a sweep Dataset: an order's amplitude over two parameters, status maps, bifurcation diagrams.

Each function takes the :class:`xarray.Dataset` of
:func:`rotorkit.sweep.load_sweep` (or :func:`~rotorkit.sweep.run_sweep`),
draws on ``ax`` (a new figure if None) and returns the Axes. Axis labels carry
the parameter's ``long_name`` and ``units`` attributes.
"""

from __future__ import annotations

import numpy as np

from ..errors import ParameterError

__all__ = ["plot_order_map", "plot_status_map", "plot_bifurcation"]

#: colour of each status in a status map
STATUS_COLORS = {"ok": "#4daf4a", "failed": "#e41a1c", "runaway": "#ff7f00", "missing": "#bbbbbb"}


def _axes(ax):
    from .basic import new_axes

    return new_axes(ax, figsize=(6.4, 4.8))


def _scales(ax, logx, logy):
    """Log axes where asked; linear ones get tick labels that carry their own exponent (no bare 1e7 offset)."""
    from matplotlib.ticker import FuncFormatter

    for log, axis, set_scale in ((logx, ax.xaxis, ax.set_xscale), (logy, ax.yaxis, ax.set_yscale)):
        if log:
            set_scale("log")
        else:
            axis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:.4g}"))


def axis_label(ds, name):
    """``long name (unit)`` of a coordinate or variable."""
    attrs = ds[name].attrs
    unit = attrs.get("units", "")
    text = attrs.get("long_name", name)
    return f"{text} ({unit})" if unit and unit != "1" else f"{text} (-)"


def _grid_pair(ds, x, y):
    dims = list(ds.status.dims)
    if x is None or y is None:
        if len(dims) != 2 or "point" in dims:
            raise ParameterError(f"a map needs a 2-D grid sweep (its dimensions are {dims}); select the others "
                                 "first (ds.sel(name=value)) or pass x= and y=")
        x, y = (x or dims[1], y or dims[0]) if x is None else (x, y or [d for d in dims if d != x][0])
    for name in (x, y):
        if name not in dims:
            raise ParameterError(f"{name!r} is not a dimension of the sweep ({', '.join(dims)})")
    if len(dims) != 2:
        raise ParameterError(f"the sweep has the dimensions {dims}; select all but {x!r} and {y!r} first")
    return x, y


def _edges(values, log):
    v = np.log10(values) if log else np.asarray(values, dtype=float)
    if v.size == 1:
        e = np.array([v[0] - 0.5, v[0] + 0.5])
    else:
        mid = (v[1:] + v[:-1]) / 2
        e = np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])
    return 10**e if log else e


def plot_order_map(ds, order, signal=None, *, x=None, y=None, ax=None, log=False, logx=False, logy=False,
                   colorbar=True, cmap="viridis"):
    """Colour map of the peak amplitude of ``order`` over two swept parameters.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep over a grid of (at least) two parameters.
    order : str
        One of the sweep's orders (``"1/2"``).
    signal : str, optional
        One of the sweep's signals (default the first).
    x, y : str, optional
        Parameters on the axes (default: the grid's second and first).
    log : bool
        Logarithmic colour scale. ``logx``, ``logy``: logarithmic axes.

    Returns
    -------
    matplotlib.axes.Axes
        With one QuadMesh (points without a value left blank).
    """
    orders = [str(o) for o in ds.order.values]
    if order not in orders:
        raise ParameterError(f"order {order!r} was not stored; the sweep's orders are {orders or 'none'} "
                             "(run it with orders=[...] / --order)")
    signal = str(ds.signal.values[0]) if signal is None else signal
    if signal not in [str(s) for s in ds.signal.values]:
        raise ParameterError(f"signal {signal!r}: the sweep's signals are {[str(s) for s in ds.signal.values]}")
    x, y = _grid_pair(ds, x, y)
    data = ds.order_amplitude.sel(order=order, signal=signal).transpose(y, x)
    ax = _axes(ax)
    from matplotlib.colors import LogNorm

    table = np.ma.masked_invalid(data.values)
    norm = None
    if log and table.count() and table.max() > 0:
        norm = LogNorm(vmin=max(table.max() * 1e-4, table[table > 0].min()), vmax=table.max())
    mesh = ax.pcolormesh(_edges(ds[x].values, logx), _edges(ds[y].values, logy), table, shading="flat", norm=norm,
                         cmap=cmap)
    _scales(ax, logx, logy)
    ax.set_xlabel(axis_label(ds, x))
    ax.set_ylabel(axis_label(ds, y))
    unit = dict(zip([str(s) for s in ds.signal.values], [str(u) for u in ds.signal_units.values]))[signal]
    ax.set_title(f"{signal}: peak amplitude at order {order} (blank: no spectrum)", fontsize=9)
    if colorbar:
        ax.figure.colorbar(mesh, ax=ax, label=f"{signal} amplitude at order {order} ({unit})")
    return ax


def plot_status_map(ds, *, x=None, y=None, ax=None, logx=False, logy=False):
    """Where the points ran, failed or ran away: one colour per status over two parameters."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    x, y = _grid_pair(ds, x, y)
    status = ds.status.transpose(y, x).values
    kinds = list(STATUS_COLORS)
    codes = np.vectorize(lambda s: kinds.index(s) if s in kinds else kinds.index("missing"))(status)
    ax = _axes(ax)
    ax.pcolormesh(_edges(ds[x].values, logx), _edges(ds[y].values, logy), codes, shading="flat",
                  cmap=ListedColormap(list(STATUS_COLORS.values())), vmin=-0.5, vmax=len(kinds) - 0.5)
    _scales(ax, logx, logy)
    ax.set_xlabel(axis_label(ds, x))
    ax.set_ylabel(axis_label(ds, y))
    present = [k for k in kinds if np.any(status == k)]
    counts = {k: int(np.sum(status == k)) for k in present}
    # the whole axes is data: the legend goes beside it
    ax.legend(handles=[Patch(color=STATUS_COLORS[k], label=f"{k} ({counts[k]})") for k in present],
              loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", borderaxespad=0.0)
    ax.set_title(f"status of the {status.size} points: ok, failed or ran away", fontsize=9)
    return ax


def plot_bifurcation(ds, signal=None, *, parameter=None, ax=None, scale=1.0, unit=None, logx=False, **kwargs):
    """Bifurcation diagram: the once-per-revolution samples of ``signal`` against one swept parameter.

    A period-1 response gives one dot per value, period 2 two, a quasi-periodic
    or chaotic one a spread; points without samples (failed, run away) are
    marked on the axis.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep with one parameter (select the others first).
    signal : str, optional
        One of the sweep's Poincare signals (default the first).
    scale : float
        Factor applied to the samples (e.g. 1e6 for um); pass ``unit``.
    """
    signals = [str(s) for s in ds.poincare_signal.values]
    if not signals:
        raise ParameterError("the sweep stored no once-per-revolution samples (poincare=[...])")
    signal = signals[0] if signal is None else signal
    if signal not in signals:
        raise ParameterError(f"signal {signal!r}: the sweep's Poincare signals are {signals}")
    dims = list(ds.status.dims)
    if len(dims) != 1:
        raise ParameterError(f"the sweep has the dimensions {dims}; select all but one parameter first")
    if parameter is None:
        parameter = dims[0] if dims[0] != "point" else ds.attrs["parameters"][0]
    values = np.asarray(ds[parameter].values, dtype=float)
    samples = ds.poincare.sel(poincare_signal=signal).values * scale
    xs = np.repeat(values, samples.shape[1])
    ys = samples.ravel()
    keep = np.isfinite(ys)
    ax = _axes(ax)
    ax.plot(xs[keep], ys[keep], linestyle="none", marker=kwargs.pop("marker", "."),
            markersize=kwargs.pop("markersize", 2), color=kwargs.pop("color", "k"), **kwargs)
    status = np.asarray(ds.status.values)
    for kind in ("failed", "runaway"):
        mask = status == kind
        if mask.any():
            ax.plot(values[mask], np.zeros(mask.sum()), linestyle="none", marker="x",
                    color={"failed": "C3", "runaway": "C1"}[kind], label=kind)
    _scales(ax, logx, False)
    ax.set_xlabel(axis_label(ds, parameter))
    su = dict(zip(signals, [str(u) for u in ds.poincare_units.values]))
    shown = unit or (su.get(signal, "") if scale == 1.0 else "")
    if not shown:
        from .basic import scaled_unit

        shown = scaled_unit(su.get(signal, "") or "-", scale)
    ax.set_ylabel(f"{signal} once per revolution ({shown})")
    ax.set_title(f"bifurcation diagram: {samples.shape[1]} once-per-revolution samples of {signal} per point",
                 fontsize=9)
    if (status == "failed").any() or (status == "runaway").any():
        ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize="small", borderaxespad=0.0)
    return ax
