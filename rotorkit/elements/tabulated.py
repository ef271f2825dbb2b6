"""Tables of numbers an element is given (a bearing's coefficients against the speed, a speed against time).

:func:`check_table` checks one (same lengths, enough points, strictly
increasing abscissae, finite values) and returns it as SI floats. It lives
apart from :mod:`rotorkit.elements.speed` (which re-exports it) so that an
element with a table does not load the speed-profile class.
"""

import math
import numbers

import numpy as np

from ..errors import ParameterError
from ..units import to_si

__all__ = ["check_table", "finite_number"]


def finite_number(value, name):
    """``value`` as a float; ParameterError naming ``name`` if it is not a finite real number (or is a bool)."""
    if isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} = {value!r}: expected a number")
    if not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise ParameterError(f"{name} = {value!r}: expected a finite number")
    return float(value)


def check_table(xs, name_x, name_y, ys, *, unit_x, unit_y, owner, min_points=2):
    """Validate a table: same lengths, >= ``min_points`` points, strictly increasing ``xs``; SI floats out."""
    for nm, seq in ((name_x, xs), (name_y, ys)):
        if isinstance(seq, (str, bytes)) or not hasattr(seq, "__len__"):
            raise ParameterError(f"{owner}: {nm} = {seq!r}: expected a sequence of numbers")
    if len(xs) != len(ys):
        raise ParameterError(
            f"{owner}: {name_x} has {len(xs)} entries but {name_y} has {len(ys)}; give one value per {name_x} entry"
        )
    if len(xs) < min_points:
        raise ParameterError(f"{owner}: {name_x} = {list(xs)!r}: expected at least {min_points} points")
    xs = tuple(finite_number(to_si(v, unit_x, f"{owner} {name_x}[{i}]"), f"{owner} {name_x}[{i}]")
               for i, v in enumerate(xs))
    ys = tuple(finite_number(to_si(v, unit_y, f"{owner} {name_y}[{i}]"), f"{owner} {name_y}[{i}]")
               for i, v in enumerate(ys))
    for i in range(len(xs) - 1):
        if not xs[i + 1] > xs[i]:
            raise ParameterError(
                f"{owner}: {name_x} = {list(xs)!r} is not strictly increasing at index {i + 1} "
                f"({xs[i + 1]!r} <= {xs[i]!r}); sort the table and drop repeated entries"
            )
    return xs, ys
