"""The generated entry code run over arrays (rotorkit.linear.array_code) against the same code run point by point.

Reference: each expression evaluated by Python on floats with :mod:`math`
(as the generated template functions are), at every point; the array
versions must give the same numbers, bit for bit (the same IEEE
operations), including the guarded pieces the printer writes as
conditional expressions (step, window, safe_div, the contact ratio).
"""

import math
import types

import numpy as np
import pytest

from rotorkit.linear.array_code import array_function, array_template_function

EXPRESSIONS = (
    "min(max(a[0], a[1]), a[2]) + sqrt(abs(a[0]))*a[2]",  # a clipped table segment
    "(1.0 if (a[0] - t) > 0.0 else 0.0)",  # step
    "((a[1])/(a[0]) if (a[0]) != 0.0 else 0.0)",  # safe_div, with a zero denominator below
    "(1.0 if (a[1]) <= (a[0]) < (a[2]) else 0.0)",  # window: a chained comparison
    "((((a[0]) - (a[1]))/(a[0]) if (a[0]) > (a[1]) else (1.0 if (a[0]) == 0.0 and (a[1]) == 0.0 else 0.0)))",
    "float(floor(a[0]*3.0)) + (2.0 if not (a[0] > 1.0) or a[1] > 5.0 else -2.0)",
    "_c1*a[1] + _c0",  # common subexpressions
)
PRELUDE = (("_c0", "(1.0 if a[0] > 0.5 else -1.0)"), ("_c1", "exp(_c0)*cos(a[0])"), ("_c2", "erf(a[0])"))
MODULE = types.SimpleNamespace(TEMPLATES=((None, None, None, EXPRESSIONS, None, None, None, None, PRELUDE),))
POINTS = np.array([-1.0, 0.0, 0.25, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0])


def scalar(code, a, t):
    namespace = dict(vars(math), max=max, min=min, abs=abs, a=a, t=t)
    for name, text in PRELUDE[:2]:
        namespace[name] = eval(text, namespace)
    return eval(code, namespace)


def test_guarded_pieces_over_arrays_equal_the_code_point_by_point():
    f = array_template_function(MODULE, 0, tuple(range(len(EXPRESSIONS))))
    with np.errstate(all="ignore"):  # safe_div computes both branches
        values = f([POINTS, 1.0, 2.0], 0.6)
    for k, code in enumerate(EXPRESSIONS):
        expected = [scalar(code, [float(x), 1.0, 2.0], 0.6) for x in POINTS]
        np.testing.assert_array_equal(np.broadcast_to(values[k], POINTS.shape), expected, err_msg=code)


def test_only_the_common_subexpressions_needed_are_computed():
    """``erf`` (not in numpy) is in the prelude, but no chosen entry uses it: the function runs over arrays."""
    f = array_template_function(MODULE, 0, (6,))
    assert len(f([POINTS, 1.0, 2.0], 0.0)) == 1


def test_code_without_conditionals_runs_as_it_is():
    namespace = dict(vars(math), max=max, min=min, abs=abs)
    exec("def entries(a, t):\n    return [min(max(a[0], 1.0), 2.0)*sqrt(a[1]), hypot(a[0], t)]\n", namespace)
    f = array_function(namespace["entries"])
    values = f([POINTS, 4.0], 3.0)
    expected = [namespace["entries"]([float(x), 4.0], 3.0) for x in POINTS]
    np.testing.assert_array_equal(np.array(values).T, expected)


def test_a_conditional_does_not_run_over_arrays_without_the_rewrite():
    namespace = dict(vars(math))
    exec(f"def entries(a, t):\n    return [{EXPRESSIONS[1]}]\n", namespace)
    with pytest.raises(ValueError, match="truth value"):
        array_function(namespace["entries"])([POINTS], 0.0)
