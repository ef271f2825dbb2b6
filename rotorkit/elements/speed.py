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

from dataclasses import dataclass, field
from typing import Callable

from ..errors import ParameterError
from .tabulated import check_table, finite_number

__all__ = ["SpeedProfile", "check_table"]

#: the table functions (sympy functions) moved to :mod:`rotorkit.symbolic.tables`, so that building a model does
#: not import sympy; still importable from here, loaded on first use
_SYMBOLIC = ("clip", "interpolate_table", "table_value", "table_slope", "table_integral")


def __getattr__(name):
    if name in _SYMBOLIC:
        from ..symbolic import tables

        return getattr(tables, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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

    #: SI units of a table's columns (model files write them with their unit)
    _units = {"times": ("s", None), "speeds": ("rad/s", None)}

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
                consts.append((name, finite_number(value, f"{who}.expression parameter {name!r}")))
            object.__setattr__(self, "constants", tuple(consts))
            import sympy as sp

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
        import sympy as sp

        t = sp.Symbol("t", real=True)
        p = {k: sp.Symbol(k, real=True) for k in self.values()}
        return ("expression", sp.srepr(self.speed(t, p)), sp.srepr(self.angle(t, p)))

    # -- expressions -------------------------------------------------------
    def speed(self, t, p):
        """Omega(t) as a sympy expression; ``p`` maps :meth:`values` keys to symbols."""
        if self.kind == "table":
            from ..symbolic.tables import table_value

            n = len(self.times)
            return table_value(t, *[p[f"t{i}"] for i in range(n)], *[p[f"w{i}"] for i in range(n)])
        return self._call(self.function, "function", t, p)

    def angle(self, t, p):
        """phi(t) = integral_0^t Omega, exactly."""
        if self.kind == "table":
            from ..symbolic.tables import table_integral

            n = len(self.times)
            return table_integral(t, *[p[f"t{i}"] for i in range(n)], *[p[f"w{i}"] for i in range(n)])
        if self.angle_function is not None:
            return self._call(self.angle_function, "angle", t, p)
        import sympy as sp
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
        import sympy as sp

        try:
            expr = sp.sympify(fn(t, **{k: p[k] for k, _ in self.constants}))
        except Exception as exc:
            raise ParameterError(
                f"SpeedProfile.expression: {what} must accept t and the named parameters "
                f"({', '.join(k for k, _ in self.constants) or 'none'}) and return a sympy expression; "
                f"calling it failed: {exc}"
            ) from exc
        if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo):
            raise ParameterError(f"SpeedProfile.expression: {what} gives {expr} (nan, zoo or oo: undefined or "
                                 "infinite, e.g. 0/0 or 1/0); expected a finite speed expression of t")
        extra = expr.free_symbols - {t} - set(p.values())
        if extra:
            raise ParameterError(f"SpeedProfile.expression: {what} uses unknown symbols {sorted(map(str, extra))}; "
                                 "pass them in parameters={...}")
        if what == "function":  # the equations hold Omega'(t): it must be a function the code can compute
            slope = sp.diff(expr, t)
            if slope.has(sp.Derivative, sp.Subs, sp.DiracDelta):
                raise ParameterError(
                    f"SpeedProfile.expression: the speed {expr} jumps (its derivative is {slope}); floor, ceiling, "
                    "Mod, frac, sign and Heaviside make steps the equations of motion cannot hold. Write the "
                    "change as a continuous expression (e.g. Piecewise of ramps) or use SpeedProfile.table")
        return expr
