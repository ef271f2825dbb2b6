"""Speed profiles: a rotor speed that is a function of time (run-up, coast-down).

A :class:`SpeedProfile` gives a rotor's spin speed ``Omega(t)`` and its
exact spin angle ``phi(t) = integral_0^t Omega``. Two kinds:

``SpeedProfile.table(times, speeds)``
    Piecewise linear through the points ``(t_i, Omega_i)``; before the first
    point the speed is ``Omega_0``, after the last ``Omega_n`` (held
    constant, never extrapolated linearly). The angle is the exact
    integral, piecewise quadratic. The breakpoints and speeds are parameters
    of the model (``<rotor>_speed_t<i>``, ``<rotor>_speed_w<i>``): changing
    them needs no new derivation. The acceleration jumps at the
    breakpoints, which are therefore time events: the integrator restarts
    there.
``SpeedProfile.expression(function, parameters=...)``
    ``Omega = function(t, **parameters)`` built from sympy functions; the
    angle is integrated symbolically once (or given as ``angle=``).
    The named values become parameters ``<rotor>_speed_<name>``.

In generated code the table is a sum of clipped ramps::

    Omega(t) = Omega_0 + sum_i s_i (clip(t, t_i, t_i+1) - t_i),   s_i = (Omega_i+1 - Omega_i) / (t_i+1 - t_i)
    phi(t)   = Omega_0 t + sum_i s_i (G_i(t) - G_i(0)),
    G_i(t)   = (clip(t, t_i, t_i+1) - t_i)^2 / 2 + (t_i+1 - t_i) max(t - t_i+1, 0)

which prints to ``min``/``max`` only (no helper functions, no lookup); the
derivative of ``clip`` is the window ``1[t_i <= t < t_i+1]``, so
``Omega' = sum_i s_i 1[t_i <= t < t_i+1]`` appears in the equations as the
angular acceleration (tangential unbalance load ``m e Omega'``).

Examples
--------
>>> run_up = SpeedProfile.table(times=[0.0, 2.0], speeds=[0.0, 400.0])
>>> sorted(run_up.values())
['t0', 't1', 'w0', 'w1']
>>> import sympy as sp
>>> t = sp.Symbol("t")
>>> p = {k: sp.Float(v) for k, v in run_up.values().items()}
>>> float(run_up.speed(t, p).subs(t, 1.0)), float(run_up.angle(t, p).subs(t, 1.0))
(200.0, 100.0)
"""

import math
import numbers
from dataclasses import dataclass, field
from typing import Callable

import numpy as np
import sympy as sp

from ..errors import ParameterError
from ..symbolic.functions import ramp, step, window
from ..units import to_si

__all__ = ["SpeedProfile", "clip", "interpolate_table", "table_value", "table_slope", "table_integral", "check_table"]


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


def _finite(value, name):
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
    xs = tuple(_finite(to_si(v, unit_x, f"{owner} {name_x}[{i}]"), f"{owner} {name_x}[{i}]")
               for i, v in enumerate(xs))
    ys = tuple(_finite(to_si(v, unit_y, f"{owner} {name_y}[{i}]"), f"{owner} {name_y}[{i}]")
               for i, v in enumerate(ys))
    for i in range(len(xs) - 1):
        if not xs[i + 1] > xs[i]:
            raise ParameterError(
                f"{owner}: {name_x} = {list(xs)!r} is not strictly increasing at index {i + 1} "
                f"({xs[i + 1]!r} <= {xs[i]!r}); sort the table and drop repeated entries"
            )
    return xs, ys


@dataclass(frozen=True, slots=True, kw_only=True)
class SpeedProfile:
    """A rotor speed as a function of time; give it as ``Rotor(speed=...)``.

    Build one with :meth:`table` or :meth:`expression` (see the module
    docstring for the exact formulas and the behaviour outside a table).
    """

    kind: str = "table"
    times: tuple = ()
    speeds: tuple = ()
    function: Callable | None = None
    angle_function: Callable | None = None
    constants: tuple = field(default=())  # (name, SI value) pairs of an expression profile

    @classmethod
    def table(cls, times, speeds):
        """Piecewise-linear speed through ``(times[i], speeds[i])`` (s, rad/s), held constant outside."""
        return cls(kind="table", times=times, speeds=speeds)

    @classmethod
    def expression(cls, function, *, parameters=None, angle=None):
        """``Omega(t) = function(t, **parameters)`` (rad/s), e.g. ``lambda t, a: a * t``.

        ``parameters`` maps names to numbers (SI); they become model
        parameters ``<rotor>_speed_<name>``. ``angle`` optionally gives the
        spin angle ``phi(t, **parameters)`` with ``phi(0) = 0``, if sympy
        cannot integrate ``function``.
        """
        parameters = {} if parameters is None else parameters
        if not isinstance(parameters, dict):
            raise ParameterError(f"SpeedProfile.expression: parameters = {parameters!r}: expected a dict name -> number")
        return cls(kind="expression", function=function, angle_function=angle,
                   constants=tuple(parameters.items()))

    def __post_init__(self):
        who = "SpeedProfile"
        if self.kind == "table":
            ts, ws = check_table(self.times, "times", "speeds", self.speeds, unit_x="s", unit_y="rad/s",
                                 owner=f"{who}.table")
            object.__setattr__(self, "times", ts)
            object.__setattr__(self, "speeds", ws)
        elif self.kind == "expression":
            if not callable(self.function):
                raise ParameterError(f"{who}.expression: function = {self.function!r}: expected a function of t")
            consts = []
            for name, value in self.constants:
                if not isinstance(name, str) or not name.isidentifier() or name == "t":
                    raise ParameterError(f"{who}.expression: parameter name {name!r}: expected an identifier other than 't'")
                consts.append((name, _finite(value, f"{who}.expression parameter {name!r}")))
            object.__setattr__(self, "constants", tuple(consts))
            t = sp.Symbol("t", real=True)
            p = {k: sp.Symbol(k, real=True) for k in self.values()}
            self.speed(t, p)
            self.angle(t, p)  # fail early
        else:
            raise ParameterError(f"SpeedProfile.kind = {self.kind!r}: expected 'table' or 'expression'")

    # -- parameters ------------------------------------------------------
    def values(self):
        """Field (without the ``speed_`` prefix) -> SI value."""
        if self.kind == "table":
            out = {f"t{i}": v for i, v in enumerate(self.times)}
            out.update({f"w{i}": v for i, v in enumerate(self.speeds)})
            return out
        return dict(self.constants)

    def units(self):
        """Field -> SI unit."""
        if self.kind == "table":
            return {k: ("s" if k[0] == "t" else "rad/s") for k in self.values()}
        return {k: "" for k in self.values()}

    def time_event_fields(self):
        """Fields whose values are times at which the acceleration jumps."""
        return tuple(f"t{i}" for i in range(len(self.times))) if self.kind == "table" else ()

    def with_values(self, **values):
        """A copy with some values changed (keys as in :meth:`values`)."""
        current = self.values()
        unknown = set(values) - set(current)
        if unknown:
            raise ParameterError(f"SpeedProfile: unknown values {sorted(unknown)}; known: {sorted(current)}")
        current.update(values)
        if self.kind == "table":
            n = len(self.times)
            return SpeedProfile.table([current[f"t{i}"] for i in range(n)], [current[f"w{i}"] for i in range(n)])
        return SpeedProfile(kind="expression", function=self.function, angle_function=self.angle_function,
                            constants=tuple((k, current[k]) for k, _ in self.constants))

    def structure(self):
        """What the equations' form depends on (not the values)."""
        if self.kind == "table":
            return ("table", len(self.times))
        t = sp.Symbol("t", real=True)
        p = {k: sp.Symbol(k, real=True) for k in self.values()}
        return ("expression", sp.srepr(self.speed(t, p)), sp.srepr(self.angle(t, p)))

    # -- expressions -------------------------------------------------------
    def speed(self, t, p):
        """Omega(t) as a sympy expression; ``p`` maps :meth:`values` keys to symbols."""
        if self.kind == "table":
            n = len(self.times)
            return table_value(t, *[p[f"t{i}"] for i in range(n)], *[p[f"w{i}"] for i in range(n)])
        return self._call(self.function, "function", t, p)

    def angle(self, t, p):
        """phi(t) = integral_0^t Omega, exactly."""
        if self.kind == "table":
            n = len(self.times)
            return table_integral(t, *[p[f"t{i}"] for i in range(n)], *[p[f"w{i}"] for i in range(n)])
        if self.angle_function is not None:
            return self._call(self.angle_function, "angle", t, p)
        from sympy.integrals.manualintegrate import manualintegrate  # bounded effort, unlike integrate()

        antiderivative = manualintegrate(self.speed(t, p), t)
        phi = antiderivative - antiderivative.subs(t, 0)
        if phi.has(sp.Integral):
            raise ParameterError(
                "SpeedProfile.expression: sympy cannot integrate the speed to the spin angle; give "
                "angle=lambda t, ...: <integral from 0 to t> or use SpeedProfile.table"
            )
        return phi

    def _call(self, fn, what, t, p):
        try:
            expr = sp.sympify(fn(t, **{k: p[k] for k, _ in self.constants}))
        except Exception as exc:
            raise ParameterError(
                f"SpeedProfile.expression: {what} must accept t and the named parameters "
                f"({', '.join(k for k, _ in self.constants) or 'none'}) and return a sympy expression; "
                f"calling it failed: {exc}"
            ) from exc
        extra = expr.free_symbols - {t} - set(p.values())
        if extra:
            raise ParameterError(f"SpeedProfile.expression: {what} uses unknown symbols {sorted(map(str, extra))}; "
                                 "pass them in parameters={...}")
        return expr
