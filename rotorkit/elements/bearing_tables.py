"""Coefficient tables of a linear bearing or seal: against rotor speed, whirl frequency, or both.

The table machinery of :class:`~rotorkit.elements.linear_bearing.LinearBearing`
(and so of :class:`~rotorkit.elements.seal.Seal`): checking a table, naming its
entries as parameters, changing entries, the interpolated coefficient in the
equations, and the CSV form.

Tabulated coefficients (:meth:`LinearBearing.tabulated`,
:meth:`LinearBearing.from_csv`) are interpolated in the speed of the rotor
of ``station``: ``interpolation="linear"`` (piecewise linear, the default)
or ``"pchip"`` (monotone cubic, as ``scipy.interpolate.PchipInterpolator``
and ROSS); outside the table ``extrapolation="hold"`` (default) keeps the
end values and ``"linear"`` continues along the end slopes (see
:mod:`rotorkit.symbolic.tables`). The table entries are
parameters ``<label>_speed<i>``, ``<label>_kxx<i>``, ...; a rotor whose speed
follows a :class:`~rotorkit.elements.speed.SpeedProfile` sees the
coefficients change along the run.

Coefficients against the whirl frequency (``frequencies=``, rad/s, with or
without ``speeds``): a table ``kxx[j]`` per frequency, or a grid
``kxx[i][j]`` (speed ``i``, frequency ``j``), the same interpolation and
extrapolation along each axis (tensor product: each speed row interpolated
in the frequency first, then the rows in the speed; bilinear for
``"linear"``). The table is read at the frequency ::

    nu = whirl_ratio * Omega + whirl_frequency

two parameters of the bearing: ``whirl=None`` (default) gives ``whirl_ratio =
1``, ``whirl_frequency = 0``, the synchronous frequency of an unbalance
response; ``whirl=<value>`` a fixed frequency (``whirl_ratio = 0``). The
modal analysis that reads each mode's coefficients at that mode's own
frequency is :func:`rotorkit.linear.matched_whirl.matched_whirl_modes`.
The grid entries are parameters ``<label>_frequency<j>``,
``<label>_kxx<i>_<j>`` (``<label>_kxx<j>`` without speeds).

The CSV form (:meth:`LinearBearing.from_csv`, :meth:`LinearBearing.to_csv`):
a header naming the columns (``speed``, ``frequency`` and coefficients, each
optionally with its unit in brackets), then one row per speed, per
frequency, or per (speed, frequency) pair of a grid.

Here a table is given as a dict ``coefficient -> values``: a list per axis
entry, or for a grid a list of rows (one per speed) of values (one per
frequency).
"""

import re

from ..errors import ParameterError
from .tabulated import check_table

__all__ = ["INTERPOLATIONS", "EXTRAPOLATIONS", "WHIRL_PARAMETERS", "check_tables", "whirl_parameters",
           "table_parameters", "split_entry", "replace_entries", "interpolated_coefficient", "read_csv_table",
           "write_csv_table"]

INTERPOLATIONS = ("linear", "pchip")
EXTRAPOLATIONS = ("hold", "linear")
#: the two parameters of a frequency table giving the frequency at which it is read
WHIRL_PARAMETERS = ("whirl_ratio", "whirl_frequency")
_ENTRY = re.compile(r"([a-z]+?)(\d+)(?:_(\d+))?")


def check_tables(speeds, frequencies, tables, units, who):
    """The axes and the tables checked (lengths, increasing axes, finite values) and converted to SI floats.

    Parameters
    ----------
    speeds, frequencies : sequence of float or None
        The axes (rad/s, increasing); at least one is given.
    tables : dict
        Coefficient -> values (see the module docstring).
    units : dict
        Coefficient -> its SI unit.
    who : str
        The owner named in error messages.

    Returns
    -------
    tuple
        ``(speeds, frequencies, tables)`` as tuples of floats (None for an absent axis).
    """
    axes = {}
    for axis, values in (("speeds", speeds), ("frequencies", frequencies)):
        if values is not None:
            axes[axis] = check_table(values, axis, axis, values, unit_x="rad/s", unit_y="rad/s", owner=who)[0]
    speeds, frequencies = axes.get("speeds"), axes.get("frequencies")
    out = {}
    for f, values in tables.items():
        unit = units[f]
        if speeds is None or frequencies is None:
            name, xs = ("speeds", speeds) if frequencies is None else ("frequencies", frequencies)
            out[f] = check_table(xs, name, f, values, unit_x="rad/s", unit_y=unit, owner=who)[1]
            continue
        if isinstance(values, (str, bytes)) or not hasattr(values, "__len__") or len(values) != len(speeds):
            raise ParameterError(f"{who}: {f} = {values!r}: expected {len(speeds)} rows (one per speed) of "
                                 f"{len(frequencies)} values (one per frequency)")
        out[f] = tuple(check_table(frequencies, "frequencies", f"{f}[{i}]", row, unit_x="rad/s", unit_y=unit,
                                   owner=who)[1] for i, row in enumerate(values))
    return speeds, frequencies, out


def whirl_parameters(whirl):
    """``{"whirl_ratio": ..., "whirl_frequency": ...}`` of a fixed whirl frequency (rad/s) or None (synchronous)."""
    return {"whirl_ratio": 1.0 if whirl is None else 0.0, "whirl_frequency": 0.0 if whirl is None else whirl}


def table_parameters(speeds, frequencies, whirl, tables):
    """Parameter name -> value of a table: ``speed<i>``, ``frequency<j>``, the whirl pair, ``kxx<i>``/``kxx<i>_<j>``."""
    out = {}
    if speeds is not None:
        out.update({f"speed{i}": v for i, v in enumerate(speeds)})
    if frequencies is not None:
        out.update({f"frequency{j}": v for j, v in enumerate(frequencies)})
        out.update(whirl_parameters(whirl))
    grid = speeds is not None and frequencies is not None
    for f, values in tables.items():
        if grid:
            out.update({f"{f}{i}_{j}": v for i, row in enumerate(values) for j, v in enumerate(row)})
        else:
            out.update({f"{f}{i}": v for i, v in enumerate(values)})
    return out


def split_entry(name):
    """``"kxx3"`` -> ``("kxx", 3, None)``, ``"kxx3_1"`` -> ``("kxx", 3, 1)`` (speed row, frequency column)."""
    match = _ENTRY.fullmatch(name)
    if match is None:
        return name, None, None
    j = match.group(3)
    return match.group(1), int(match.group(2)), None if j is None else int(j)


def replace_entries(speeds, frequencies, whirl, tables, fields, who):
    """The table with some entries changed: ``fields`` maps parameter names (as :func:`table_parameters`) to values.

    Returns ``(speeds, frequencies, whirl, tables)`` (lists). The whirl pair
    must stay synchronous (ratio 1, frequency 0) or fixed (ratio 0):
    ParameterError otherwise.
    """
    grid = speeds is not None and frequencies is not None
    tables = {f: [list(r) for r in values] if grid else list(values) for f, values in tables.items()}
    axes = {"speed": None if speeds is None else list(speeds),
            "frequency": None if frequencies is None else list(frequencies)}
    pair = whirl_parameters(whirl)
    for name, value in fields.items():
        if name in WHIRL_PARAMETERS:
            pair[name] = value
            continue
        base, i, j = split_entry(name)
        if base in axes:
            axes[base][i] = value
        elif j is None:
            tables[base][i] = value
        else:
            tables[base][i][j] = value
    if pair["whirl_ratio"] == 0.0:
        fixed = pair["whirl_frequency"]
    elif pair["whirl_ratio"] == 1.0 and pair["whirl_frequency"] == 0.0:
        fixed = None
    else:
        raise ParameterError(f"{who}: whirl_ratio = {pair['whirl_ratio']!r} with whirl_frequency = "
                             f"{pair['whirl_frequency']!r}: expected whirl_ratio 1 with whirl_frequency 0 "
                             "(synchronous) or whirl_ratio 0 (a fixed frequency)")
    return axes["speed"], axes["frequency"], fixed, tables


def interpolated_coefficient(p, name, speed, n_speeds, n_frequencies, interpolation, extrapolation):
    """Coefficient ``name`` of a table as an expression of the rotor ``speed`` (sympy).

    ``p`` maps the parameter names (:func:`table_parameters`) to their
    symbols; ``n_speeds``, ``n_frequencies``: the lengths of the axes (None
    for an absent one).
    """
    from ..symbolic.tables import interpolate_table

    how = (interpolation, extrapolation)
    if n_frequencies is None:
        return interpolate_table(speed, [p[f"speed{i}"] for i in range(n_speeds)],
                                 [p[f"{name}{i}"] for i in range(n_speeds)], *how)
    nu = p["whirl_ratio"] * speed + p["whirl_frequency"]
    freqs = [p[f"frequency{j}"] for j in range(n_frequencies)]
    if n_speeds is None:
        return interpolate_table(nu, freqs, [p[f"{name}{j}"] for j in range(len(freqs))], *how)
    rows = [interpolate_table(nu, freqs, [p[f"{name}{i}_{j}"] for j in range(len(freqs))], *how)
            for i in range(n_speeds)]  # each speed row at the frequency, then across the speeds
    return interpolate_table(speed, [p[f"speed{i}"] for i in range(len(rows))], rows, *how)


def read_csv_table(path, units, who):
    """A table read from a CSV file (the format of :meth:`LinearBearing.from_csv`).

    Parameters
    ----------
    path : str or path-like
        The file.
    units : dict
        Coefficient -> SI unit, for every coefficient a column may name (in
        the order error messages list them).
    who : str
        The owner named in error messages.

    Returns
    -------
    tuple
        ``(speeds, frequencies, tables)``: the axes (None when the file has
        no such column) and coefficient -> values; with both axes, a full
        grid (sorted axes, rows per speed).
    """
    from ..units import to_si

    import csv

    with open(path, newline="") as handle:
        rows = [row for row in csv.reader(handle) if row and any(c.strip() for c in row)
                and not row[0].lstrip().startswith("#")]
    if len(rows) < 3:
        raise ParameterError(f"{who}: expected a header and at least two rows of numbers, got {len(rows)} rows")
    columns = []
    for text in rows[0]:
        match = re.fullmatch(r"\s*([A-Za-z_]\w*)\s*(?:\[\s*([^\]]*?)\s*\])?\s*", text)
        key = match.group(1).lower() if match else text.strip()
        key = {"speeds": "speed", "frequencies": "frequency"}.get(key, key)
        if not match or (key not in ("speed", "frequency") and key not in units):
            raise ParameterError(f"{who}: column {text.strip()!r}: expected 'speed' or a coefficient "
                                 f"({', '.join(units)}) or 'frequency', optionally with a unit in brackets, "
                                 "e.g. 'kxx [N/m]'")
        columns.append((key, match.group(2)))
    keys = [k for k, _ in columns]
    if "speed" not in keys and "frequency" not in keys:
        raise ParameterError(f"{who}: no 'speed' column (nor 'frequency'); the header is {rows[0]!r}")
    table = {key: [] for key, _ in columns}
    for line, row in enumerate(rows[1:], start=2):
        if len(row) != len(columns):
            raise ParameterError(f"{who}: data row {line - 1} has {len(row)} values, expected {len(columns)}")
        for (key, unit), text in zip(columns, row):
            si = "rad/s" if key in ("speed", "frequency") else units[key]
            try:
                value = float(text)
            except ValueError:
                raise ParameterError(f"{who}: data row {line - 1}, column {key!r}: {text.strip()!r} is not a "
                                     "number") from None
            table[key].append(to_si(f"{value!r} {unit}", si, f"{who} {key}") if unit else value)
    if "frequency" not in table:
        speeds = table.pop("speed")
        return speeds, None, table
    frequencies = table.pop("frequency")
    if "speed" not in table:
        return None, frequencies, table
    speeds = table.pop("speed")  # one row per (speed, frequency) pair of a full grid, in any order
    axis_s, axis_f = sorted(set(speeds)), sorted(set(frequencies))
    cells = {}
    for k, pair in enumerate(zip(speeds, frequencies)):
        if pair in cells:
            raise ParameterError(f"{who}: speed {pair[0]!r} and frequency {pair[1]!r} appear twice (data rows "
                                 f"{cells[pair] + 1} and {k + 1})")
        cells[pair] = k
    missing = [(w, f) for w in axis_s for f in axis_f if (w, f) not in cells]
    if missing:
        raise ParameterError(f"{who}: a table against speed and frequency needs every pair; missing speed "
                             f"{missing[0][0]!r} with frequency {missing[0][1]!r} ({len(missing)} pairs missing)")
    grid = {key: [[values[cells[(w, f)]] for f in axis_f] for w in axis_s] for key, values in table.items()}
    return axis_s, axis_f, grid


def write_csv_table(path, speeds, frequencies, tables, units):
    """Write a table (SI units in the header) for :func:`read_csv_table`; a grid one row per (speed, frequency).

    ``units`` maps each coefficient of ``tables`` to its SI unit.
    """
    axes = ((["speed [rad/s]"] if speeds is not None else [])
            + (["frequency [rad/s]"] if frequencies is not None else []))
    if speeds is not None and frequencies is not None:
        rows = [([w, f], [tables[c][i][j] for c in tables]) for i, w in enumerate(speeds)
                for j, f in enumerate(frequencies)]
    else:
        xs = speeds if speeds is not None else frequencies
        rows = [([x], [tables[c][i] for c in tables]) for i, x in enumerate(xs)]
    import csv

    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(axes + [f"{f} [{units[f]}]" for f in tables])
        for head, values in rows:
            writer.writerow([repr(v) for v in head + values])
