"""Numeric evaluation of the energy balance's symbolic terms on sample arrays (:mod:`rotorkit.analysis.energy`).

:class:`EnergyEvaluator` lambdifies the Jacobi integral, the energy in motion, the power channels and the
contact switches of one model structure with a NumPy printer that knows rotorkit's guarded functions
(element-wise over the samples); functions without a vectorised translation fall back to the scalar code the
model's code generator prints for them.
"""

from __future__ import annotations

import numpy as np
import sympy as sp

from ..errors import RotorkitError
from .work_quadrature import CHUNK

__all__ = ["EnergyEvaluator", "safe_div", "contact_ratio", "numpy_printer", "scalar_fallbacks", "switch_arguments",
           "TRANSLATED"]


def safe_div(a, b):
    a, b = np.broadcast_arrays(np.asarray(a, dtype=float), np.asarray(b, dtype=float))
    out = np.zeros(a.shape)
    np.divide(a, b, out=out, where=b != 0.0)
    return out


def numpy_printer():
    from sympy.printing.numpy import NumPyPrinter

    class EnergyPrinter(NumPyPrinter):
        """NumPy printer for rotorkit's guarded functions, element-wise over sample arrays."""

        def _np(self, name):
            return self._module_format(f"numpy.{name}")

        def _print_ramp(self, expr):
            return f"{self._np('maximum')}({self._print(expr.args[0])}, 0.0)"

        def _print_step(self, expr):
            return f"{self._np('where')}(({self._print(expr.args[0])}) > 0.0, 1.0, 0.0)"

        def _print_safe_div(self, expr):
            a, b = (self._print(x) for x in expr.args)
            return f"_safe_div({a}, {b})"

        def _print_window(self, expr):
            t, start, end = (self._print(x) for x in expr.args)
            return f"{self._np('where')}((({start}) <= ({t})) & (({t}) < ({end})), 1.0, 0.0)"

        def _print_contact_ratio(self, expr):
            r, delta = (self._print(a) for a in expr.args)
            return f"_contact_ratio({r}, {delta})"

        def _print_hypot(self, expr):
            x, y = (self._print(a) for a in expr.args)
            return f"{self._np('hypot')}({x}, {y})"

        def _nested(self, fn, args):
            out = self._print(args[0])
            for a in args[1:]:
                out = f"{self._np(fn)}({out}, {self._print(a)})"
            return out

        def _print_Min(self, expr):
            return self._nested("minimum", expr.args)

        def _print_Max(self, expr):
            return self._nested("maximum", expr.args)

    return EnergyPrinter


def contact_ratio(r, delta):
    """``max(r - delta, 0) / r``, with the limit 1 at ``r = delta = 0`` (as the generated code)."""
    r, delta = np.broadcast_arrays(np.asarray(r, dtype=float), np.asarray(delta, dtype=float))
    out = np.where((r == 0.0) & (delta == 0.0), 1.0, 0.0)
    inside = r > delta
    np.divide(r - delta, r, out=out, where=inside)
    return out


#: rotorkit functions with a vectorised numpy translation in the printer above
TRANSLATED = {"ramp", "step", "safe_div", "window", "hypot", "contact_ratio"}


def scalar_fallbacks(exprs):
    """Namespace entries for rotorkit functions without a numpy translation: the scalar
    code the model's code generator prints for them, applied sample by sample (slower,
    but with exactly the generated right-hand side's semantics)."""
    import math

    from ..codegen.printer import RhsPrinter

    namespace = {}
    for expr in exprs:
        for f in expr.atoms(sp.Function):
            cls = type(f)
            name = cls.__name__
            if not cls.__module__.startswith("rotorkit") or name in TRANSLATED or name in namespace:
                continue
            args = sp.symbols(f"a0:{len(f.args)}", real=True)
            try:
                code = RhsPrinter().doprint(cls(*args))
            except Exception as exc:  # noqa: BLE001 - reported with the function's name
                raise RotorkitError(f"energy balance: cannot evaluate the function {name!r} "
                                    f"(from {cls.__module__}): {exc}") from exc
            env = {n: getattr(math, n) for n in dir(math) if not n.startswith("_")}
            scalar = eval(f"lambda {', '.join(map(str, args))}: {code}", env)  # noqa: S307 - our own printer's output
            namespace[name] = np.vectorize(scalar, otypes=[float])
    return namespace


def switch_arguments(exprs):
    """Arguments of the contact switches in ``exprs`` where the power has a kink or a jump.

    ``ramp(g)`` and ``step(g)`` switch where ``g`` crosses zero, ``contact_ratio(r, delta)``
    where ``r - delta`` does; ``ramp(g)**n``
    with ``n > 1`` (Hertzian contact) is continuously differentiable there and
    is integrated as a smooth function.
    """
    found = []

    def visit(expr):
        if expr.is_Pow and type(expr.base).__name__ == "ramp" and expr.exp.is_number and expr.exp > 1:
            visit(expr.base.args[0])
            return
        name = type(expr).__name__
        switch = None
        if name in ("ramp", "step"):
            switch = expr.args[0]
        elif name == "contact_ratio":
            switch = expr.args[0] - expr.args[1]
        if switch is not None and switch not in found:
            found.append(switch)
        for arg in expr.args:
            visit(arg)

    for expr in exprs:
        visit(expr)
    return found


class EnergyEvaluator:
    """Vectorised numeric ``h``, energy in motion, power channels and contact switches of one structure."""

    def __init__(self, terms):
        self.terms = terms
        powers = list(terms.power.values())
        self.switches = switch_arguments(powers)
        exprs = [terms.jacobi, terms.motion, *powers, *self.switches]
        namespace = {"_safe_div": safe_div, "_contact_ratio": contact_ratio, **scalar_fallbacks(exprs)}
        args = [terms.t, *terms.coordinates, *terms.speeds, *terms.parameters]
        self._fn = sp.lambdify(args, exprs, modules=[namespace, "numpy"], printer=numpy_printer(), cse=True)

    def __call__(self, t, q, u, p):
        """(h, motion, {name: power}, switches) at samples ``t`` (n,), states ``q``, ``u``
        (n_coords, n) and parameters ``p``; ``switches`` has shape (n_switches, n)."""
        n, k = t.size, len(self.terms.power)
        out = np.empty((2 + k + len(self.switches), n))
        with np.errstate(all="ignore"):
            for s in range(0, n, CHUNK):
                e = min(s + CHUNK, n)
                values = self._fn(t[s:e], *q[:, s:e], *u[:, s:e], *p)
                for row, v in enumerate(values):
                    out[row, s:e] = v  # broadcasts constants
        return out[0], out[1], dict(zip(self.terms.power, out[2:2 + k])), out[2 + k:]
