"""The generated entry functions of the linear matrices, run over arrays of a parameter (all speeds at once).

The cached linear module of a model (:mod:`rotorkit.codegen.linear_cache`)
holds each element template's entries as Python expressions of its
parameters ``a`` and the time ``t``, written for floats and :mod:`math`.
A sweep over the speed evaluates a few of them (a tabulated bearing's
coefficients) at hundreds of speeds; here the same expressions run once
with the speed an array:

- :func:`array_function` runs the compiled code of a template function
  as it is, its math names bound to numpy's ufuncs (``min`` and ``max`` to
  ``numpy.minimum`` and ``numpy.maximum``, ``sqrt`` to ``numpy.sqrt``...):
  the same IEEE operations, element by element;
- :func:`array_template_function` rewrites code that cannot run on
  arrays as it is, the conditional expressions of guarded pieces
  (``step``, ``window``, ``safe_div``: PCHIP tables, speed profiles) into
  ``numpy.where`` of both branches and chained comparisons into
  ``numpy.logical_and`` (both branches are computed: call it under
  ``numpy.errstate(all="ignore")`` and check the result).

Code that still cannot run on arrays (a function numpy lacks, such as
``erf``) raises when called: the callers evaluate it point by point then.
"""

from __future__ import annotations

import ast
import copy
import functools
import math
import re
import types

import numpy as np

__all__ = ["array_function", "array_template_function"]

#: math functions of the generated code -> their numpy ufuncs
NUMPY_FUNCTIONS = {
    "sin": "sin", "cos": "cos", "tan": "tan", "exp": "exp", "log": "log", "sqrt": "sqrt", "atan2": "arctan2",
    "sinh": "sinh", "cosh": "cosh", "tanh": "tanh", "asin": "arcsin", "acos": "arccos", "atan": "arctan",
    "floor": "floor", "ceil": "ceil", "copysign": "copysign", "asinh": "arcsinh", "acosh": "arccosh",
    "atanh": "arctanh", "log2": "log2", "log10": "log10", "log1p": "log1p", "expm1": "expm1", "fmod": "fmod",
    "max": "maximum", "min": "minimum", "abs": "abs", "fabs": "fabs", "hypot": "hypot",
}
_FUNCTIONS = {}


@functools.cache
def _namespace():
    namespace = dict(vars(math))
    namespace.update({name: getattr(np, target) for name, target in NUMPY_FUNCTIONS.items()})
    namespace.update({"_where": np.where, "_not": np.logical_not,
                      "_all": lambda *a: functools.reduce(np.logical_and, a),
                      "_any": lambda *a: functools.reduce(np.logical_or, a)})
    return namespace


def array_function(function):
    """``function`` (generated code of ``(a, t)``) with numpy ufuncs for its math names: arrays in, arrays out."""
    return types.FunctionType(function.__code__, _namespace(), function.__name__)


class _ArrayCode(ast.NodeTransformer):
    """Conditional expressions to ``numpy.where``, chained comparisons and ``and``/``or``/``not`` to numpy's logic."""

    def _call(self, name, args):
        return ast.Call(func=ast.Name(id=name, ctx=ast.Load()), args=list(args), keywords=[])

    def visit_IfExp(self, node):
        self.generic_visit(node)
        return self._call("_where", (node.test, node.body, node.orelse))

    def visit_Compare(self, node):
        self.generic_visit(node)
        if len(node.ops) == 1:
            return node
        parts, left = [], node.left
        for op, right in zip(node.ops, node.comparators):
            parts.append(ast.Compare(left=copy.deepcopy(left), ops=[op], comparators=[right]))
            left = right
        return self._call("_all", parts)

    def visit_BoolOp(self, node):
        self.generic_visit(node)
        return self._call("_all" if isinstance(node.op, ast.And) else "_any", node.values)

    def visit_UnaryOp(self, node):
        self.generic_visit(node)
        return self._call("_not", (node.operand,)) if isinstance(node.op, ast.Not) else node

    def visit_Call(self, node):
        self.generic_visit(node)  # float(floor(x)): floor's value is a float array already
        if isinstance(node.func, ast.Name) and node.func.id == "float" and len(node.args) == 1:
            return node.args[0]
        return node


def _rewritten(code):
    tree = _ArrayCode().visit(ast.parse(code, mode="eval"))
    return ast.unparse(ast.fix_missing_locations(tree))


def array_template_function(module, template, selection):
    """``f(a, t)`` of the entries ``selection`` of one template of ``module``, rewritten to run over arrays.

    Parameters
    ----------
    module : module
        A linear module (:func:`rotorkit.codegen.linear_cache.linear_module`).
    template : int
        Index into ``module.TEMPLATES``.
    selection : tuple of int
        Entry indices of the template, in the order of the returned values.
    """
    key = (id(module), template, tuple(selection))
    function = _FUNCTIONS.get(key)
    if function is None:
        expressions = [module.TEMPLATES[template][3][i] for i in selection]
        prelude = module.TEMPLATES[template][8]
        used = set(re.findall(r"\b_c\d+\b", " ".join(expressions)))
        for name, code in reversed(prelude):  # the common subexpressions these entries need
            if name in used:
                used.update(re.findall(r"\b_c\d+\b", code))
        head = "".join(f"    {name} = {_rewritten(code)}\n" for name, code in prelude if name in used)
        body = "".join(f"        ({_rewritten(code)}),\n" for code in expressions)
        local = {}
        exec(compile(f"def _entries(a, t):\n{head}    return [\n{body}    ]\n", "<rotorkit linear matrices, arrays>",
                     "exec"), _namespace(), local)
        function = _FUNCTIONS[key] = local["_entries"]
        if len(_FUNCTIONS) > 256:
            _FUNCTIONS.pop(next(iter(_FUNCTIONS)))
    return function
