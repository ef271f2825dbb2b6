"""Tables as opaque sympy functions: piecewise linear (``table_value``, its slope, its integral) and PCHIP.

A rotor speed given as a table (:class:`rotorkit.elements.speed.SpeedProfile`),
a bearing coefficient tabulated against speed
(:class:`rotorkit.elements.LinearBearing`): the table stays one opaque call
in the derivation (untouched by ``expand``, ``trigsimp``, ``cse``) and
prints as a sum of clipped ramps, ``min``/``max`` only. They live here, not
in the element modules, so that building a model does not import sympy.

PCHIP (:class:`pchip_value`, :class:`pchip_slope`) is the monotone cubic
Hermite interpolant of Fritsch and Carlson (1980) with the knot derivatives
of Fritsch and Butland (1984), as ``scipy.interpolate.PchipInterpolator``
computes them: the weighted harmonic mean of the neighbouring secant slopes
at an interior knot (0 where they differ in sign or one is 0), the
shape-preserving one-sided three-point formula at the ends, the secant
slope for a two-point table. The knot values are parameters, so the
derivatives are expressions with :func:`~rotorkit.symbolic.functions.step`
guards (no division by zero in generated code: the guarded denominators are
1 where the branch is not taken); the interpolant prints as a sum of clipped
cubics, ``min``/``max`` and conditionals only, in every back end.

Extrapolation (:func:`interpolate_table`): ``"hold"`` keeps the end values
outside the table; ``"linear"`` continues along the end slope (the end
segment's for linear tables, the end knot derivative for PCHIP; scipy's
``PchipInterpolator`` would continue the end cubic instead).
"""

import sympy as sp

from .functions import ramp, step, window

__all__ = ["clip", "interpolate_table", "table_value", "table_slope", "table_integral", "pchip_value",
           "pchip_slope", "pchip_derivatives", "INTERPOLATIONS", "EXTRAPOLATIONS"]

INTERPOLATIONS = ("linear", "pchip")
EXTRAPOLATIONS = ("hold", "linear")


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


def pchip_derivatives(xs, ys):
    """PCHIP knot derivatives ``d_k`` (sympy expressions of the knots), as scipy's ``PchipInterpolator``."""
    n = len(xs)
    h = [xs[k + 1] - xs[k] for k in range(n - 1)]
    m = [(ys[k + 1] - ys[k]) / h[k] for k in range(n - 1)]
    if n == 2:
        return [m[0], m[0]]
    d = []
    for k in range(1, n - 1):  # weighted harmonic mean where the secants agree in sign, else 0
        w1, w2 = 2 * h[k] + h[k - 1], h[k] + 2 * h[k - 1]
        same = step(m[k - 1] * m[k])
        d.append(same * (w1 + w2) * m[k - 1] * m[k] / (same * (w1 * m[k] + w2 * m[k - 1]) + 1 - same))

    def edge(h0, h1, m0, m1):  # one-sided three-point estimate, kept shape-preserving
        e = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        clamp = step(-m0 * m1) * step(sp.Abs(e) - 3 * sp.Abs(m0))
        return step(e * m0) * (e + clamp * (3 * m0 - e))

    return [edge(h[0], h[1], m[0], m[1])] + d + [edge(h[-1], h[-2], m[-1], m[-2])]


def _hermite(t, x0, x1, y0, y1, d0, d1):
    """The cubic Hermite segment through ``(x0, y0)``, ``(x1, y1)`` with end slopes ``d0``, ``d1``, at ``t``."""
    hk = x1 - x0
    u = (t - x0) / hk
    return (y0 * (2 * u**3 - 3 * u**2 + 1) + hk * d0 * (u**3 - 2 * u**2 + u) + y1 * (-2 * u**3 + 3 * u**2)
            + hk * d1 * (u**3 - u**2))


def _hermite_slope(t, x0, x1, y0, y1, d0, d1):
    hk = x1 - x0
    u = (t - x0) / hk
    return ((y0 - y1) * (6 * u**2 - 6 * u) / hk + d0 * (3 * u**2 - 4 * u + 1) + d1 * (3 * u**2 - 2 * u))


def _pchip_sum(x, xs, ys):
    """PCHIP as ``y_0 + sum_i [H_i(clip(x, x_i, x_i+1)) - y_i]``: held at the end values outside."""
    d = pchip_derivatives(xs, ys)
    out = ys[0]
    for i in range(len(xs) - 1):
        out += _hermite(clip(x, xs[i], xs[i + 1]), xs[i], xs[i + 1], ys[i], ys[i + 1], d[i], d[i + 1]) - ys[i]
    return out


def _pchip_slope(x, xs, ys):
    d = pchip_derivatives(xs, ys)
    out = sp.S.Zero
    for i in range(len(xs) - 1):
        out += window(x, xs[i], xs[i + 1]) * _hermite_slope(x, xs[i], xs[i + 1], ys[i], ys[i + 1], d[i], d[i + 1])
    return out


class pchip_slope(_Table):
    """d/dx of :class:`pchip_value` inside the table, 0 outside (its own derivative is taken as 0)."""

    _inline = staticmethod(_pchip_slope)
    _latex_name = "pchip'"

    def fdiff(self, argindex=1):
        if argindex == 1:
            return sp.S.Zero
        raise sp.ArgumentIndexError(self, argindex)


class pchip_value(_Table):
    """PCHIP ``y(x)`` through the knots (as scipy's ``PchipInterpolator``), held constant outside the table."""

    _inline = staticmethod(_pchip_sum)
    _latex_name = "pchip"

    def fdiff(self, argindex=1):
        if argindex == 1:
            return pchip_slope(*self.args)
        raise sp.ArgumentIndexError(self, argindex)


def interpolate_table(x, xs, ys, interpolation="linear", extrapolation="hold"):
    """``y(x)`` through ``(xs_i, ys_i)`` (sympy), ``xs`` increasing.

    Parameters
    ----------
    interpolation : {"linear", "pchip"}
        Piecewise linear (an opaque :class:`table_value` call, a sum of
        clipped ramps in code) or PCHIP (:class:`pchip_value`).
    extrapolation : {"hold", "linear"}
        Outside the table: the end values, or the end values continued
        along the end slopes (``ramp`` terms added to the held table).
    """
    if interpolation not in INTERPOLATIONS:
        raise ValueError(f"interpolation = {interpolation!r}: expected one of {INTERPOLATIONS}")
    if extrapolation not in EXTRAPOLATIONS:
        raise ValueError(f"extrapolation = {extrapolation!r}: expected one of {EXTRAPOLATIONS}")
    if interpolation == "linear":
        value = table_value(x, *xs, *ys)
        first = (ys[1] - ys[0]) / (xs[1] - xs[0])
        last = (ys[-1] - ys[-2]) / (xs[-1] - xs[-2])
    else:
        value = pchip_value(x, *xs, *ys)
        if extrapolation == "linear":
            d = pchip_derivatives(xs, ys)
            first, last = d[0], d[-1]
    if extrapolation == "linear":
        value = value - first * ramp(xs[0] - x) + last * ramp(x - xs[-1])
    return value
