"""LaTeX of the custom functions, of every element and of whole equations (notebook display)."""

import inspect
import os
from pathlib import Path

import pytest
import sympy as sp

import rotorkit as rk
from rotorkit.symbolic import functions

x, y, z = sp.symbols("x y z", real=True)
CUSTOM = [obj for _, obj in inspect.getmembers(functions, inspect.isclass)
          if issubclass(obj, sp.Function) and obj.__module__ == functions.__name__]


def _call(cls):
    return cls(*(x, y, z)[: cls.nargs.args[0] if hasattr(cls.nargs, "args") else cls.nargs])


def test_every_custom_function_is_covered():
    assert {c.__name__ for c in CUSTOM} == set(functions.__all__)


@pytest.mark.parametrize("cls", CUSTOM, ids=lambda c: c.__name__)
@pytest.mark.parametrize("power", [1, 2, sp.Rational(3, 2), sp.Float(1.5)])
def test_powers_of_custom_functions_print(cls, power):
    expr = _call(cls)
    text = sp.latex(expr**power)
    assert text and "ramp" not in text and "safe_div" not in text
    if power != 1:
        # the exponent is printed once, on a bracketed base
        assert text.count("^{") >= 1 and (str(power) in text or sp.latex(power) in text)


def test_al31f_equations_latex_with_ball_bearing():
    """The AL-31F scene has BallBearings (ramp(...)**1.5): its LaTeX used to raise a TypeError."""
    eom = rk.preset("al31f").equations()
    text = eom.latex()
    assert r"\right\rangle_{+}\right)^{\frac{3}{2}}" in text  # the Hertz power of a ramp
    assert eom._repr_latex_().startswith("$$")
