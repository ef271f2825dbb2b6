"""A Python code printer whose output runs both in CPython and under numba.

Guarded pieces (:mod:`rotorkit.symbolic.functions`) print to conditional
expressions, small integer powers to products, and math functions to bare
names imported from :mod:`math`.
"""

from sympy.printing.pycode import PythonCodePrinter

__all__ = ["RhsPrinter", "MATH_FUNCTIONS", "EXTRA_MATH_FUNCTIONS"]

MATH_FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "atan2", "sinh", "cosh", "tanh", "asin", "acos", "atan")
#: further functions of :mod:`math` the printer can emit (floor, sign, erf, ... of a user's speed expression);
#: a generated module imports those it uses on a second line, so modules that use none are unchanged
EXTRA_MATH_FUNCTIONS = ("floor", "ceil", "copysign", "erf", "erfc", "gamma", "lgamma", "asinh", "acosh", "atanh",
                        "log2", "log10", "log1p", "expm1", "fmod")


class RhsPrinter(PythonCodePrinter):
    """Prints expressions for the generated RHS module."""

    def __init__(self, names=None):
        super().__init__({"fully_qualified_modules": False, "standard": "python3"})
        self._names = names or {}

    def _print_Symbol(self, expr):
        return self._names.get(expr, expr.name)

    def _print_Function(self, expr):
        name = type(expr).__name__
        if name in MATH_FUNCTIONS:
            return f"{name}({', '.join(self._print(a) for a in expr.args)})"
        return super()._print_Function(expr)

    def _print_sin(self, expr):
        return f"sin({self._print(expr.args[0])})"

    def _print_cos(self, expr):
        return f"cos({self._print(expr.args[0])})"

    def _print_ramp(self, expr):
        return f"max({self._print(expr.args[0])}, 0.0)"

    def _print_step(self, expr):
        return f"(1.0 if ({self._print(expr.args[0])}) > 0.0 else 0.0)"

    def _print_safe_div(self, expr):
        a, b = (self._print(x) for x in expr.args)
        return f"(({a})/({b}) if ({b}) != 0.0 else 0.0)"

    def _print_hypot(self, expr):
        x, y = (self._print(a) for a in expr.args)
        return f"sqrt(({x})*({x}) + ({y})*({y}))"

    def _print_contact_ratio(self, expr):
        r, delta = (self._print(a) for a in expr.args)
        return (f"((({r}) - ({delta}))/({r}) if ({r}) > ({delta}) else "
                f"(1.0 if ({r}) == 0.0 and ({delta}) == 0.0 else 0.0))")

    def _print_window(self, expr):
        t, start, end = (self._print(x) for x in expr.args)
        return f"(1.0 if ({start}) <= ({t}) < ({end}) else 0.0)"

    def _print_Min(self, expr):
        return self._nested("min", expr.args)

    def _print_Max(self, expr):
        return self._nested("max", expr.args)

    def _nested(self, fn, args):
        out = self._print(args[0])
        for a in args[1:]:
            out = f"{fn}({out}, {self._print(a)})"
        return out

    def _print_Pow(self, expr, rational=False):
        base, exp = expr.args
        if exp.is_Integer and 2 <= int(exp) <= 4:
            b = self._print(base) if base.is_Atom else f"({self._print(base)})"
            return "(" + "*".join([b] * int(exp)) + ")"
        if exp.is_Integer and int(exp) == -1:
            return f"(1.0/({self._print(base)}))"
        if exp == 0.5 or (exp.is_Rational and exp.p == 1 and exp.q == 2):
            return f"sqrt({self._print(base)})"
        if exp.is_Rational and exp.q == 2 and exp.p in (3, 5) and base.is_Symbol:
            b = self._print(base)
            return f"({b}*sqrt({b}))" if exp.p == 3 else f"({b}*{b}*sqrt({b}))"
        if exp.is_Rational and not exp.is_Integer:
            return f"(({self._print(base)})**{float(exp)!r})"
        return super()._print_Pow(expr, rational=rational)

    def _print_Rational(self, expr):
        return repr(float(expr))

    def _print_Float(self, expr):
        return repr(float(expr))

    def _print_Integer(self, expr):
        return repr(float(expr))

    def _print_Pi(self, expr):
        return repr(3.141592653589793)

    def _print_floor(self, expr):  # math.floor returns an int: a float, so the arithmetic stays in doubles
        return f"float(floor({self._print(expr.args[0])}))"

    def _print_ceiling(self, expr):
        return f"float(ceil({self._print(expr.args[0])}))"

    def _print_Exp1(self, expr):
        return repr(2.718281828459045)

    def _undefined(self, expr):
        from ..errors import ParameterError

        raise ParameterError(f"the equations hold {expr} (an undefined or infinite value, e.g. 1/0 or 0/0 in a "
                             "SpeedProfile expression); the generated code cannot compute it: check the expressions "
                             "of the model's speed profiles and loads")

    _print_NaN = _print_ComplexInfinity = _print_Infinity = _print_NegativeInfinity = _undefined
