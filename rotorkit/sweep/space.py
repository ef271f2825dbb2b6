"""Parameter spaces of a sweep: a grid, an explicit list of points, a Latin hypercube.

A space is plain data: parameter names and per-axis values (a grid), or an
``(n_points, n_parameters)`` table (a list or a Latin hypercube sample). It
never builds a model; point ``i`` is computed on demand (:meth:`point`), so a
sweep streams its points instead of holding them all. Spaces larger than
``max_points`` are refused with their size before anything runs.

Examples
--------
>>> parse_range("rub_stiffness=5e5:2e7:3")
('rub_stiffness', (500000.0, 10250000.0, 20000000.0))
>>> grid = Grid({"rub_stiffness": [1e6, 2e6], "lp_speed": [1000.0, 1500.0, 2000.0]})
>>> grid.size, grid.shape, grid.point(4)
(6, (2, 3), {'rub_stiffness': 2000000.0, 'lp_speed': 1500.0})
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ParameterError

__all__ = ["parse_range", "Grid", "PointList", "latin_hypercube", "as_space", "MAX_POINTS"]

#: default largest number of points of a sweep (each point is a simulation and a file; pass max_points= to change)
MAX_POINTS = 100_000


def _number(text, spec, what):
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(f"sweep range {spec!r}: {what} {text.strip()!r} is not a number (SI units)") from None
    if not math.isfinite(value):
        raise ParameterError(f"sweep range {spec!r}: {what} {text.strip()!r} is not finite")
    return value


def _size_error(n, what, max_points):
    return ParameterError(
        f"{what} has {int(n):,} points, more than max_points={max_points:,}: each point is one simulation "
        f"(and one file); split the sweep, sample it (latin_hypercube / --lhs N), or pass a larger max_points"
    )


def parse_range(text, max_points=MAX_POINTS):
    """Parse a swept parameter ``name=spec`` into ``(name, values)``.

    Parameters
    ----------
    text : str
        ``name=start:stop:n`` for ``n`` linearly spaced values (both ends
        included), ``name=log:start:stop:n`` for log spacing (``start``,
        ``stop`` > 0), or an explicit list ``name=v1,v2,...``. Values are SI
        numbers (e.g. ``rub_stiffness=5e5:2e7:40``).
    max_points : int
        Largest ``n`` accepted (the values are built as a tuple).

    Returns
    -------
    (str, tuple of float)

    Raises
    ------
    ParameterError
        A missing ``=``, a name that is not an identifier, a value that is
        not a finite number, ``n`` not an integer >= 2 or above
        ``max_points``, equal ends, a log range with a non-positive end, an
        empty list item or duplicates.

    Examples
    --------
    >>> parse_range("rub_stiffness=log:1e6:1e8:3")
    ('rub_stiffness', (1000000.0, 10000000.0, 100000000.0))
    """
    if not isinstance(text, str):
        raise ParameterError(f"sweep range {text!r}: expected a string such as 'rub_stiffness=5e5:2e7:40'")
    if "=" not in text:
        raise ParameterError(
            f"sweep range {text!r}: expected name=start:stop:n, name=log:start:stop:n or name=v1,v2,... "
            "(e.g. rub_stiffness=5e5:2e7:40)"
        )
    name, spec = (s.strip() for s in text.split("=", 1))
    if not name.isidentifier():
        raise ParameterError(f"sweep range {text!r}: {name!r} is not a parameter name")
    if not spec:
        raise ParameterError(f"sweep range {text!r}: no values after '='")
    log = spec.lower().startswith("log:")
    if log or ":" in spec:
        parts = spec[4:].split(":") if log else spec.split(":")
        if len(parts) != 3:
            form = "log:start:stop:n" if log else "start:stop:n"
            raise ParameterError(f"sweep range {text!r}: expected {name}={form} (three fields, got {len(parts)})")
        start = _number(parts[0], text, "start")
        stop = _number(parts[1], text, "stop")
        raw_n = parts[2].strip()
        if not raw_n.isdigit() or int(raw_n) < 2:
            raise ParameterError(
                f"sweep range {text!r}: the number of values {raw_n!r} must be an integer >= 2 "
                f"(for a single value write {name}=<value>)"
            )
        if len(raw_n) > 18 or int(raw_n) > max_points:
            raise _size_error(float(raw_n), f"sweep range {text!r}", max_points)
        n = int(raw_n)
        if start == stop:
            raise ParameterError(f"sweep range {text!r}: start and stop are equal ({start:g})")
        if log:
            if start <= 0 or stop <= 0:
                raise ParameterError(f"sweep range {text!r}: a log range needs start > 0 and stop > 0")
            values = np.geomspace(start, stop, n)
            values[0], values[-1] = start, stop
        else:
            values = np.linspace(start, stop, n)
        return name, tuple(float(v) for v in values)
    items = spec.split(",")
    if len(items) > max_points:
        raise _size_error(len(items), f"sweep range {name}=...", max_points)
    if any(not item.strip() for item in items):
        raise ParameterError(f"sweep range {text!r}: empty item in the list of values")
    values = tuple(_number(item, text, "value") for item in items)
    _check_unique(values, f"sweep range {text!r}")
    return name, values


def _check_unique(values, where):
    seen = set()
    for v in values:
        if v in seen:
            raise ParameterError(f"{where}: the value {v:g} appears twice; each value is one point")
        seen.add(v)


def _check_name(name):
    if not isinstance(name, str) or not name.isidentifier():
        raise ParameterError(f"parameter name {name!r}: expected the name of a parameter, e.g. 'rub_stiffness'")
    return name


def _check_values(name, values, max_points):
    if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
        raise ParameterError(f"values={values!r}: expected a sequence of numbers for {name!r}")
    if len(values) > max_points:
        raise _size_error(len(values), f"the values of {name!r}", max_points)
    out = []
    for v in np.asarray(list(values), dtype=object).ravel():
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, numbers.Real) or not math.isfinite(float(v)):
            raise ParameterError(f"values for {name!r} contain {v!r}: expected finite numbers (SI)")
        out.append(float(v))
    if not out:
        raise ParameterError(f"values for {name!r} are empty: expected at least one value")
    _check_unique(out, f"values for {name!r}")
    return tuple(out)


class Grid:
    """Every combination of per-parameter values (the first parameter varies slowest).

    Parameters
    ----------
    axes : mapping of str to sequence of float
        Parameter name -> its distinct values (SI).
    max_points : int
        Refuse a grid with more points (checked from the axis lengths alone).
    """

    kind = "grid"

    def __init__(self, axes, max_points=MAX_POINTS):
        if not hasattr(axes, "items") or not axes:
            raise ParameterError(f"axes={axes!r}: expected a dict of parameter name -> values")
        names = [_check_name(n) for n in axes]
        lengths = [len(v) if hasattr(v, "__len__") else 0 for v in axes.values()]
        size = math.prod(lengths)
        if size > max_points:
            shape = " x ".join(f"{n:,}" for n in lengths)
            raise _size_error(size, f"the grid {shape} over {', '.join(names)}", max_points)
        self.names = tuple(names)
        self.axes = {n: _check_values(n, v, max_points) for n, v in axes.items()}
        self.shape = tuple(len(v) for v in self.axes.values())
        self.size = math.prod(self.shape)

    @property
    def dims(self):
        """Dimensions of the dataset: one per parameter."""
        return self.names

    def point(self, index):
        """Parameter name -> value of point ``index`` (0 <= index < size)."""
        where = np.unravel_index(int(index), self.shape)
        return {n: self.axes[n][int(i)] for n, i in zip(self.names, where)}

    def describe(self):
        """Plain data for the manifest."""
        return {"kind": self.kind, "names": list(self.names), "axes": {n: list(v) for n, v in self.axes.items()}}


class PointList:
    """An explicit list of points: rows of an ``(n_points, n_parameters)`` table.

    Parameters
    ----------
    names : sequence of str
    points : array_like, shape (n_points, n_parameters)
        One row per point (SI values); rows must be distinct.
    max_points : int
    kind : str
        ``"list"``, or ``"lhs"`` for a Latin hypercube sample.
    """

    def __init__(self, names, points, max_points=MAX_POINTS, kind="list"):
        self.names = tuple(_check_name(n) for n in names)
        if len(set(self.names)) != len(self.names):
            raise ParameterError(f"names={list(names)}: a parameter appears twice")
        if hasattr(points, "__len__") and len(points) > max_points:
            raise _size_error(len(points), "the list of points", max_points)
        try:
            table = np.array(points, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError("points: expected a table of numbers, one row per point") from None
        if table.ndim == 1 and len(self.names) == 1:
            table = table[:, None]
        if table.ndim != 2 or table.shape[1] != len(self.names) or table.shape[0] == 0:
            raise ParameterError(f"points: expected shape (n_points, {len(self.names)}), got {table.shape}")
        if not np.all(np.isfinite(table)):
            raise ParameterError("points contain non-finite values: expected finite numbers (SI)")
        if len(np.unique(table, axis=0)) != len(table):
            raise ParameterError("points: a point appears twice; each point is one simulation")
        table.setflags(write=False)
        self.table, self.kind = table, kind
        self.size, self.shape = table.shape[0], (table.shape[0],)

    @property
    def dims(self):
        return ("point",)

    @property
    def axes(self):
        """Parameter name -> its values per point."""
        return {n: tuple(float(v) for v in self.table[:, j]) for j, n in enumerate(self.names)}

    def point(self, index):
        return {n: float(v) for n, v in zip(self.names, self.table[int(index)])}

    def describe(self):
        return {"kind": self.kind, "names": list(self.names), "points": self.table.tolist()}


def latin_hypercube(bounds, n, seed=0, log=(), max_points=MAX_POINTS):
    """A Latin hypercube sample of ``n`` points within ``bounds``.

    Parameters
    ----------
    bounds : mapping of str to (float, float)
        Parameter name -> (low, high), SI.
    n : int
        Number of points (each range is cut in ``n`` strata, one point each).
    seed : int
        Seed of the random generator (the sample is stored in the manifest,
        so a resume does not depend on it).
    log : iterable of str
        Parameters sampled uniformly in their logarithm (bounds > 0).

    Returns
    -------
    PointList

    Examples
    --------
    >>> s = latin_hypercube({"k": (0.0, 1.0)}, 4, seed=1)
    >>> sorted(int(4 * v) for v in s.table[:, 0])  # one point per stratum
    [0, 1, 2, 3]
    """
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise ParameterError(f"n={n!r}: expected the number of points, an integer >= 1")
    if n > max_points:
        raise _size_error(n, "the Latin hypercube", max_points)
    rng = np.random.default_rng(seed)
    names, columns = list(bounds), []
    for name in names:
        lo, hi = (float(v) for v in bounds[name])
        if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
            raise ParameterError(f"bounds[{name!r}] = {bounds[name]!r}: expected (low, high) with low < high")
        u = (rng.permutation(n) + rng.random(n)) / n
        if name in log:
            if lo <= 0:
                raise ParameterError(f"bounds[{name!r}] = {bounds[name]!r}: a log-sampled range needs low > 0")
            columns.append(np.exp(np.log(lo) + u * (np.log(hi) - np.log(lo))))
        else:
            columns.append(lo + u * (hi - lo))
    return PointList(names, np.column_stack(columns), max_points=max_points, kind="lhs")


def as_space(space, values=None, max_points=MAX_POINTS):
    """A :class:`Grid` or :class:`PointList` from what :func:`run_sweep` accepts.

    ``space`` is a Grid or PointList, a dict of name -> values (a grid), or
    one parameter name with its ``values`` (a 1-D grid).
    """
    if isinstance(space, (Grid, PointList)):
        if space.size > max_points:
            raise _size_error(space.size, "the sweep", max_points)
        return space
    if isinstance(space, str):
        if values is None:
            raise ParameterError(f"space={space!r}: a single parameter needs its values")
        return Grid({_check_name(space): values}, max_points)
    if values is not None:
        raise ParameterError("values= goes with a single parameter name; a dict already holds the values")
    if hasattr(space, "items"):
        return Grid(space, max_points)
    raise ParameterError(f"space={space!r}: expected a parameter name, a dict name -> values, a Grid or a PointList")


def space_from_description(data):
    """The space a manifest describes."""
    if data["kind"] == "grid":
        return Grid({n: data["axes"][n] for n in data["names"]}, max_points=math.inf)
    return PointList(data["names"], data["points"], max_points=math.inf, kind=data["kind"])
