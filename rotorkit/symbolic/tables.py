"""Piecewise-linear tables as opaque sympy functions: ``table_value``, its slope and its exact integral.

A rotor speed given as a table (:class:`rotorkit.elements.speed.SpeedProfile`),
a bearing coefficient tabulated against speed
(:class:`rotorkit.elements.LinearBearing`): the table stays one opaque call
in the derivation (untouched by ``expand``, ``trigsimp``, ``cse``) and
prints as a sum of clipped ramps, ``min``/``max`` only. They live here, not
in the element modules, so that building a model does not import sympy.
"""

import sympy as sp

from .functions import ramp, step, window

__all__ = ["clip", "interpolate_table", "table_value", "table_slope", "table_integral"]


class clip(sp.Function):
    """``min(max(x, a), b)`` for ``a <= b``; ``d/dx`` is the window ``1[a <= x < b]``."""

    nargs = 3

    @classmethod
    def eval(cls, x, a, b):
        if x.is_number and a.is_number and b.is_number:
            return sp.Min(sp.Max(x, a), b)
        return None

    def fdiff(self, argindex=1):
        x, a, b = self.args
        if argindex == 1:
            return window(x, a, b)
        if argindex == 2:
            return step(a - x)
        return 1 - step(b - x)

    def _pythoncode(self, printer):
        x, a, b = (printer._print(v) for v in self.args)
        return f"min(max({x}, {a}), {b})"

    _numpycode = _pythoncode

    def _latex(self, printer):
        x, a, b = (printer._print(v) for v in self.args)
        return r"\operatorname{clip}\left(%s,\,%s,\,%s\right)" % (x, a, b)


def _clip_sum(x, xs, ys):
    """The piecewise-linear interpolant as a sum of clipped ramps (prints to min/max)."""
    out = ys[0]
    for i in range(len(xs) - 1):
        out += (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]) * (clip(x, xs[i], xs[i + 1]) - xs[i])
    return out


def _clip_slope(x, xs, ys):
    out = sp.S.Zero
    for i in range(len(xs) - 1):
        out += (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i]) * window(x, xs[i], xs[i + 1])
    return out


def _clip_integral(x, xs, ys):
    """Exact integral from 0 to x of :func:`_clip_sum` (piecewise quadratic)."""

    def G(u, a, b):
        return (clip(u, a, b) - a) ** 2 / 2 + (b - a) * ramp(u - b)

    out = ys[0] * x
    for i in range(len(xs) - 1):
        a, b = xs[i], xs[i + 1]
        out += (ys[i + 1] - ys[i]) / (b - a) * (G(x, a, b) - G(sp.S.Zero, a, b))
    return out


class _Table(sp.Function):
    """Base of the table functions: args ``(x, x_0..x_n, y_0..y_n)``; opaque to expand/trigsimp/cse."""

    _inline = None

    @classmethod
    def eval(cls, *args):
        if len(args) < 5 or len(args) % 2 == 0:
            raise ValueError(f"{cls.__name__} needs (x, x_0..x_n, y_0..y_n) with n >= 1")
        if all(a.is_number for a in args):
            return cls._inline(*cls._split(args))
        return None

    @staticmethod
    def _split(args):
        n = (len(args) - 1) // 2
        return args[0], list(args[1:1 + n]), list(args[1 + n:])

    def inline(self):
        """The same function as an explicit min/max expression."""
        return type(self)._inline(*self._split(self.args))

    def _pythoncode(self, printer):
        return f"({printer._print(self.inline())})"

    def _latex(self, printer):
        return r"\operatorname{%s}\left(%s\right)" % (self._latex_name, printer._print(self.args[0]))


class table_slope(_Table):
    """d/dx of :class:`table_value`: the segment slope, 0 outside the table (jumps at the knots)."""

    _inline = staticmethod(_clip_slope)
    _latex_name = "table'"

    def fdiff(self, argindex=1):
        if argindex == 1:
            return sp.S.Zero
        raise sp.ArgumentIndexError(self, argindex)


class table_value(_Table):
    """Piecewise-linear ``y(x)`` through the knots, held constant outside the table."""

    _inline = staticmethod(_clip_sum)
    _latex_name = "table"

    def fdiff(self, argindex=1):
        if argindex == 1:
            return table_slope(*self.args)
        raise sp.ArgumentIndexError(self, argindex)


class table_integral(_Table):
    """``integral_0^x table_value``: exact, piecewise quadratic."""

    _inline = staticmethod(_clip_integral)
    _latex_name = r"\int table"

    def fdiff(self, argindex=1):
        if argindex == 1:
            return table_value(*self.args)
        raise sp.ArgumentIndexError(self, argindex)


def interpolate_table(x, xs, ys):
    """Piecewise-linear ``y(x)`` through ``(xs_i, ys_i)`` (sympy), held constant outside the table.

    ``xs`` increasing. An opaque :class:`table_value` call whose generated
    code is a sum of clipped ramps (``min``/``max`` only).
    """
    return table_value(x, *xs, *ys)
