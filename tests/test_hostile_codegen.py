"""Derivation and code generation cover what a user can write, or refuse it by name.

- The C translation of every function the symbolic layer emits (the printer's
  output for sympy's functions, rotorkit's guarded functions and constants)
  equals the Python back end to the last bit, on a grid of arguments that
  crosses each function's corners (signs, zero, integers, halves).
- A speed expression the derivation cannot simplify quickly (``exp(1000 t)``,
  ``erf(100 t)``), one with the constants ``pi`` and ``E``, or with
  ``floor``/``Mod``/``Heaviside``: derived, generated and run in seconds.
- ``nan``/``zoo`` in a speed expression: a named error when the model is built.
"""

import ctypes
import math
import signal

import numpy as np
import pytest
import sympy as sp

from rotorkit import Disk, ElasticSupport, Model, Rotor, simulate
from rotorkit.codegen import cbuild, csource
from rotorkit.codegen.generate import import_extra_math
from rotorkit.codegen.printer import EXTRA_MATH_FUNCTIONS, MATH_FUNCTIONS, RhsPrinter
from rotorkit.elements import SpeedProfile
from rotorkit.errors import ParameterError
from rotorkit.symbolic import functions as fn
from rotorkit.symbolic import tables

HAS_CC = cbuild.compiler() is not None
a, b = sp.symbols("a b", real=True)

#: every function and constant the symbolic layer emits, as the printer prints it (name -> expression of a, b)
EMITTED = {
    **{name: getattr(sp, name)(a) for name in ("sin", "cos", "tan", "exp", "sinh", "cosh", "tanh", "atan", "erf",
                                               "erfc", "asinh", "floor", "ceiling", "sign", "Abs", "Heaviside",
                                               "frac")},
    "log": sp.log(1 + a * a), "sqrt": sp.sqrt(1 + a * a), "asin": sp.asin(a / (1 + abs(a))),
    "acos": sp.acos(a / (1 + abs(a))), "acosh": sp.acosh(2 + a * a), "atanh": sp.atanh(a / (1 + abs(a))),
    "atan2": sp.atan2(a, b), "Mod": sp.Mod(a, b), "Min": sp.Min(a, b), "Max": sp.Max(a, b),
    "Piecewise": sp.Piecewise((a, a > b), (b * b, True)),
    "pow2": a**2, "pow3": a**3, "pow4": a**4, "pow-1": 1 / (1 + a * a), "pow1/2": sp.sqrt(b * b),
    "pow3/2": (1 + a * a)**sp.Rational(3, 2), "pow1/3": (1 + a * a)**sp.Rational(1, 3), "powab": (1 + a * a)**b,
    "pi": sp.pi * a + sp.E * b, "constants": 100 * sp.pi + sp.E * a + sp.GoldenRatio * b,
    "ramp": fn.ramp(a), "step": fn.step(a), "safe_div": fn.safe_div(a, b), "hypot": fn.hypot(a, b),
    "contact_ratio": fn.contact_ratio(abs(a), abs(b)), "window": fn.window(a, -0.5, b),
    "clip": tables.clip(a, -1, b), "table_value": tables.table_value(a, 0, 1, 2, 10, 20, 5),
    "table_slope": tables.table_slope(a, 0, 1, 2, 10, 20, 5),
    "table_integral": tables.table_integral(a, 0, 1, 2, 10, 20, 5),
}

#: functions whose Python value comes from CPython's own algorithm, not libm's: not translated (the c back end falls
#: back to numba with a warning naming them)
NOT_TRANSLATED = {"gamma": sp.gamma(2 + a * a), "loggamma": sp.loggamma(2 + a * a)}

GRID = np.array([-3.5, -2.0, -1.0, -0.5, -1e-300, -0.0, 0.0, 1e-300, 0.3, 0.5, 1.0, 1.5, 2.0, 2.5, 7.25, 1e3])


def module_source(names):
    """The printed expressions as the ``rhs`` of a generated module (``dydt[i]``: the i-th name's expression)."""
    printer = RhsPrinter({a: "q0", b: "q1"})
    lines = [f"from math import {', '.join(MATH_FUNCTIONS)}", "",
             "def rhs(t, y, p, dydt):", "    q0 = y[0]", "    q1 = y[1]"]
    lines += [f"    dydt[{i}] = {printer.doprint(EMITTED[name])}" for i, name in enumerate(names)]
    return import_extra_math("\n".join(lines) + "\n")


def python_rhs(names):
    namespace = {}
    exec(compile(module_source(names), "<generated>", "exec"), namespace)
    return namespace["rhs"]


@pytest.mark.skipif(not HAS_CC, reason="no C compiler")
def test_the_c_translation_of_every_emitted_function_equals_python_to_the_last_bit():
    names = list(EMITTED)
    library = cbuild.library(None, "hostile_functions", csource.translate(module_source(names), ["rhs"]))
    c_rhs = library.rhs
    c_rhs.argtypes = (ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)
    singles = {name: python_rhs([name]) for name in names}
    p, compared, differ = np.zeros(1), 0, {}
    for x in GRID:
        for y in GRID:
            state = np.array([x, y])
            got = np.zeros(len(names))
            c_rhs(0.0, state.ctypes.data, p.ctypes.data, got.ctypes.data)
            for i, name in enumerate(names):
                expected = np.zeros(1)
                try:
                    singles[name](0.0, state, p, expected)
                except (ValueError, OverflowError, ZeroDivisionError):  # no Python value (floor(inf)...): no claim
                    continue
                compared += 1
                if not (expected.view(np.int64)[0] == got[i:i + 1].view(np.int64)[0]
                        or (np.isnan(expected[0]) and np.isnan(got[i]))):
                    differ[name] = (x, y, expected[0], got[i])
    assert not differ, differ
    assert compared > 0.95 * len(GRID) ** 2 * len(names)


@pytest.mark.parametrize("name", list(NOT_TRANSLATED))
def test_functions_c_cannot_match_bit_for_bit_are_not_translated(name):
    source = (f"from math import {', '.join(MATH_FUNCTIONS)}\n\ndef rhs(t, y, p, dydt):\n    q0 = y[0]\n"
              f"    dydt[0] = {RhsPrinter({a: 'q0'}).doprint(NOT_TRANSLATED[name])}\n")
    with pytest.raises(csource.Untranslatable, match="call of"):
        csource.translate(source, ["rhs"])


def test_the_extra_math_import_is_added_only_when_used():
    base = f"from math import {', '.join(MATH_FUNCTIONS)}\n\ndef rhs(t, y, p, dydt):\n    dydt[0] = sin(t)\n"
    assert import_extra_math(base) == base  # the presets' modules stay byte for byte
    used = import_extra_math(base.replace("sin(t)", "erf(t) + floor(t)"))
    assert "from math import floor, erf\n" in used
    assert set(EXTRA_MATH_FUNCTIONS) <= set(dir(math))


@pytest.mark.parametrize("printed", ["nan", "zoo", "oo"])
def test_undefined_values_are_refused_by_name_when_printed(printed):
    with pytest.raises(ParameterError, match="undefined or infinite"):
        RhsPrinter().doprint(a + getattr(sp, printed))


# -- speed expressions end to end -----------------------------------------------
@pytest.fixture
def deadline():
    def hung(signum, frame):
        raise AssertionError("the derivation or generation did not end")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(120)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


def jeffcott(speed, angle=None):
    return Model([Rotor(name="R", stations=(1,), speed=SpeedProfile.expression(speed, angle=angle)),
                  Disk(station=1, mass=2.0, radius=0.1, eccentricity=1e-4),
                  ElasticSupport(station=1, stiffness=2e4, damping=8.0)], name="hostile_speed")


SPEEDS = {
    "exp(-1000 t)": (lambda t: 300 * (1 - sp.exp(-1000 * t)), None),
    "erf(100 t)": (lambda t: 300 * sp.erf(100 * t), lambda t: 300 * (t * sp.erf(100 * t) + (sp.exp(-10**4 * t * t) - 1)
                                                                     / (100 * sp.sqrt(sp.pi)))),
    "100 pi + E t": (lambda t: 100 * sp.pi + sp.E * t, None),
    "Abs": (lambda t: 300 + 1000 * sp.Abs(t - sp.Rational(1, 100)), lambda t: 300 * t),
    "Piecewise": (lambda t: sp.Piecewise((300 + 1000 * t, t < sp.Rational(1, 100)), (310, True)),
                  lambda t: sp.Piecewise((300 * t + 500 * t * t, t < sp.Rational(1, 100)),
                                         (310 * t - sp.Rational(5, 100), True))),
}

#: the cases that hung or recursed (the others are slow: a derivation each)
FAST = ("exp(-1000 t)", "100 pi + E t")


@pytest.mark.parametrize("name", [pytest.param(n, marks=() if n in FAST else pytest.mark.slow) for n in SPEEDS])
def test_speed_expressions_derive_generate_and_run(deadline, name):
    speed, angle = SPEEDS[name]
    model = jeffcott(speed, angle)
    result = simulate(model.compile(backend="python"), (0.0, 0.02), sample_rate=1000.0)
    assert np.all(np.isfinite(result.y))


@pytest.mark.slow
@pytest.mark.skipif(not HAS_CC, reason="no C compiler")
def test_a_speed_expression_with_erf_runs_in_c_as_in_python(deadline):
    speed, angle = SPEEDS["erf(100 t)"]
    model = jeffcott(speed, angle)
    c, py = model.compile(backend="c"), model.compile(backend="python")
    assert c.backend == "c"
    y = np.array([1e-4, -2e-4, 0.3, 0.1])
    for t in (0.0, 0.003, 0.01, 0.5):
        assert np.array_equal(c.rhs(t, y), py.rhs(t, y))


@pytest.mark.parametrize("speed, words", [
    (lambda t: sp.nan * t + 300, "nan, zoo or oo"), (lambda t: sp.zoo + t, "nan, zoo or oo"),
    (lambda t: 300 / (t - t), "nan, zoo or oo"), (lambda t: 300 + sp.floor(100 * t), "jumps"),
    (lambda t: 300 + sp.Mod(t, sp.Rational(1, 100)), "jumps"), (lambda t: 300 + sp.Heaviside(t - 1), "jumps"),
    (lambda t: 300 + sp.sign(t - 1), "jumps")], ids=["nan", "zoo", "1/0", "floor", "Mod", "Heaviside", "sign"])
def test_speed_expressions_the_equations_cannot_hold_are_named_errors(speed, words):
    with pytest.raises(ParameterError, match=words):
        jeffcott(speed, lambda t: 300 * t).equations()


@pytest.mark.slow
def test_a_speed_that_overflows_during_a_run_is_a_simulation_error(deadline):
    from rotorkit.errors import SimulationError

    model = jeffcott(lambda t: 300 * sp.exp(1000 * t), lambda t: sp.Rational(3, 10) * (sp.exp(1000 * t) - 1))
    with pytest.raises(SimulationError, match=r"step size collapsed .* more than 5e\+07 steps .*exp\(1000 t\)"):
        simulate(model.compile(backend="python"), (0.0, 100.0), engine="scipy", sample_rate=10.0)
