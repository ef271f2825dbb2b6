"""The linear matrices of a model, derived once and kept in the model cache beside its right-hand side.

A model whose forces are linear in the coordinates and their rates (beam
segments, disks, linear bearings, elastic supports, gyroscopics) has
equations ``M q'' + C q' + K q = F(t)``. Each element contributes a small
block of ``M``, ``C`` and ``K`` whose entries are expressions of its own
parameters (and the rotor speed, the time). These blocks are derived once
per model *structure*, written as Python source with the element's
parameters as a local vector ``a`` (elements whose blocks are the same up
to that renaming, e.g. the segments of a shaft, share one *template*), and
stored in the model cache (:mod:`rotorkit.codegen.cache`: the same signed,
verified entries as the right-hand side) under ``<structure key>_linear``::

    N_COORDINATES, STATE_NAMES  the model's coordinates and states
    LINEAR        False when a force is not linear in the states (contacts,
                  Hertzian bearings): nothing else is stored then
    PARAMETERS    parameter names, the global parameter vector's order
    TEMPLATES     per template: matrix (0 M, 1 C, 2 K), local rows and
                  columns, expressions of ``a`` and ``t``, the local
                  parameters each entry holds (-1: the time) and those it is
                  not affine in (a tabulated coefficient against the speed);
                  then the local rows and expressions of the element's
                  force at rest (``q = q' = 0``: gravity on its mass, a
                  preload), for its static reaction; last the template's
                  common subexpressions ``(name, expression)``, computed
                  before the entries
    ELEMENTS      per element: template, global indices of its parameters
                  (its ``a``), global indices of its coordinates, its label

A process with a warm cache evaluates the templates and assembles the
matrices numerically: it never derives. Disk eccentricities count as 0
here (unbalance is a forcing, not part of the matrices).

:func:`linear_module` returns the module (this process's copy, the disk
cache's, or generated and stored now); :func:`template_function` compiles
a function of ``(a, t)`` returning chosen entries of one template.
"""

from __future__ import annotations

__all__ = ["linear_module", "template_function", "generate_linear_source", "equations_text"]

#: version of the generated layout; an entry of another version is generated again
LINEAR_FORMAT = 3
_MODULES = {}
_FUNCTIONS = {}


def _key(model):
    return model.structure_key + "_linear"


def linear_module(model):
    """The generated module holding the linear matrices of ``model``'s structure (see the module docstring).

    From this process, else from the disk cache, else derived now
    (``model.equations()``, once) and stored there.
    """
    from . import cache

    key = _key(model)
    module = _MODULES.get(key)
    if module is None:
        module = cache.load(key)
        if module is not None and getattr(module, "LINEAR_FORMAT", None) != LINEAR_FORMAT:
            module = None  # written by another rotorkit version: generated again below
    if module is None:
        from ..progress import announce_if_slow

        with announce_if_slow(f"generating the linear matrices of {model.name} (first use of this model structure; "
                              "cached on disk afterwards)"):
            module = cache.store(key, generate_linear_source(model))
    _MODULES[key] = module
    return module


def _affine(expr, s):
    """True if ``expr`` is affine in the symbol ``s`` by its form (a sum of terms at most linear in it)."""
    if s not in expr.free_symbols or expr == s:
        return True
    if expr.is_Add:
        return all(_affine(a, s) for a in expr.args)
    if expr.is_Mul:
        holding = [a for a in expr.args if s in a.free_symbols]
        return len(holding) == 1 and _affine(holding[0], s)
    return False


def _linear_parts(expr, states):
    """``{state: coefficient, None: the rest}`` of an expression linear in ``states`` by its form, or None.

    Sums and products are walked (a product may hold the states in one
    factor only); anything else that holds a state (a power, a function, a
    product of two states) gives None and is left to differentiation.
    """
    import sympy as sp

    if not expr.free_symbols & states:
        return {None: expr}
    if expr in states:
        return {expr: sp.S.One}
    if expr.is_Add:
        out = {}
        for arg in expr.args:
            parts = _linear_parts(arg, states)
            if parts is None:
                return None
            for key, value in parts.items():
                out[key] = out.get(key, sp.S.Zero) + value
        return out
    if expr.is_Mul:
        holding = [a for a in expr.args if a.free_symbols & states]
        if len(holding) != 1:
            return None
        parts = _linear_parts(holding[0], states)
        if parts is None:
            return None
        factor = sp.Mul(*(a for a in expr.args if a is not holding[0]))
        return {key: factor * value for key, value in parts.items()}
    return None


def generate_linear_source(model):
    """Python source of the linear-matrix module of ``model``'s structure, or of one that says it is not linear.

    Each element's own matrices (:func:`rotorkit.symbolic.lagrange.element_matrices`,
    its velocity- and coordinate-linear forces differentiated into ``C``
    and ``K``) are written with the element's parameters renamed to a local
    vector ``a``; elements with the same renamed entries (the segments of a
    shaft, the disks) share one *template*, printed once. The module lists
    the templates and, per element, its template, the global indices of its
    parameters and of its coordinates: the matrices are assembled
    numerically from them.

    Parameters
    ----------
    model : rotorkit.Model

    Returns
    -------
    str
        The module text (see the module docstring for its names).
    """
    import sympy as sp

    from ..symbolic.lagrange import element_matrices
    from .printer import MATH_FUNCTIONS, RhsPrinter

    symbols, contributions = element_matrices(model)
    qs, us, t = tuple(symbols.coordinates.values()), tuple(symbols.speeds.values()), symbols.t
    n = len(qs)
    states = set(qs) | set(us)
    q_index = {q: i for i, q in enumerate(qs)}
    u_index = {u: i for i, u in enumerate(us)}
    names = tuple(symbols.parameters)
    index = {symbols.parameters[name]: k for k, name in enumerate(names)}
    zero = {sym: sp.S.Zero for name, sym in symbols.parameters.items() if name.endswith("_eccentricity")}
    header = [
        '"""Linear matrices M, C, K of one model structure, generated by rotorkit (do not edit)."""',
        f"from math import {', '.join(MATH_FUNCTIONS)}",
        f"LINEAR_FORMAT = {LINEAR_FORMAT}",
        f"N_COORDINATES = {n}",
        f"COORDINATE_NAMES = {tuple(str(q) for q in qs)!r}",
        f"STATE_NAMES = {tuple(str(q) for q in qs) + tuple(f'{q}_dot' for q in qs)!r}",
    ]
    not_linear = "\n".join(header + ["LINEAR = False", ""])
    templates, template_index, elements = [], {}, []
    at_rest = {s: sp.S.Zero for s in states}
    for element, own, M, K, C, F in contributions:
        entries = {}  # (matrix, i, j) -> [terms]
        loads = {}  # i -> the element's force at rest (q = q' = 0): gravity on its mass, a preload
        for which, table in ((0, M), (2, K), (1, C)):
            for (i, j), v in table.items():
                v = sp.sympify(v).xreplace(zero)
                if which == 0 and v.free_symbols & states:
                    return not_linear  # a mass matrix that depends on the coordinates
                if v != 0:
                    entries.setdefault((which, i, j), []).append(v)
        for i, f in F.items():
            f = sp.sympify(f).xreplace(zero)
            parts = _linear_parts(f, states)  # by the form of the terms: no differentiation
            if parts is None:  # not written as a sum of state times coefficient: differentiate
                parts = {None: f.xreplace(at_rest)}
                for s in f.free_symbols & states:
                    d = sp.diff(f, s)
                    if d.free_symbols & states:
                        return not_linear  # contact, Hertzian bearing
                    parts[s] = d
            for s, d in parts.items():
                if d == 0:
                    continue
                if s is None:
                    loads[i] = d
                else:
                    key = (2, i, q_index[s]) if s in q_index else (1, i, u_index[s])
                    entries.setdefault(key, []).append(-d)
        values = {key: sp.Add(*terms) for key, terms in entries.items()}
        values = {key: v for key, v in values.items() if v != 0}
        if not values and not loads:
            continue
        held = set().union(*(v.free_symbols for v in values.values()), *(v.free_symbols for v in loads.values()))
        coords = sorted({i for _, i, _ in values} | {j for _, _, j in values} | set(loads))
        local = {c: k for k, c in enumerate(coords)}
        mine = [s for s in own.values() if s in held]
        params = mine + sorted((s for s in held if s in index and s not in mine), key=str)
        rename = {s: sp.Symbol(f"_a{k}", real=True) for k, s in enumerate(params)}
        renamed = tuple(sorted(((w, local[i], local[j], v.xreplace(rename)) for (w, i, j), v in values.items()),
                               key=lambda e: e[:3]))
        renamed_loads = tuple(sorted((local[i], v.xreplace(rename)) for i, v in loads.items()))
        key = tuple(e[:3] for e in renamed), tuple(e[3] for e in renamed), renamed_loads
        if key not in template_index:
            template_index[key] = len(templates)
            templates.append((renamed, renamed_loads))
        elements.append((template_index[key], tuple(index[s] for s in params), tuple(coords), element.label()))
    printed = []
    for renamed, renamed_loads in templates:
        held = set().union(*(e[3].free_symbols for e in renamed), *(v.free_symbols for _, v in renamed_loads))
        placeholders = sorted(held - {t}, key=lambda s: int(s.name[2:]))
        printer = RhsPrinter({**{s: f"a[{s.name[2:]}]" for s in placeholders}, t: "t"})
        printer._settings["order"] = "none"
        depends, nonaffine = [], []
        for *_, v in renamed:
            held = v.free_symbols
            depends.append(tuple(int(s.name[2:]) for s in placeholders if s in held) + ((-1,) if t in held else ()))
            nonaffine.append(tuple(int(s.name[2:]) for s in placeholders if s in held and not _affine(v, s)))
        # common subexpressions of the template (a beam's entries share its shear factor, areas, inertias)
        exprs = [e[3] for e in renamed] + [v for _, v in renamed_loads]
        replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("_c"), order="none")
        prelude = tuple((str(sym), printer.doprint(value)) for sym, value in replacements)
        printed.append((tuple(e[0] for e in renamed), tuple(e[1] for e in renamed), tuple(e[2] for e in renamed),
                        tuple(printer.doprint(v) for v in reduced[:len(renamed)]), tuple(depends), tuple(nonaffine),
                        tuple(i for i, _ in renamed_loads), tuple(printer.doprint(v) for v in reduced[len(renamed):]),
                        prelude))
    lines = header + [
        "LINEAR = True",
        f"PARAMETERS = {names!r}",
        "# per template: (matrix 0 M / 1 C / 2 K, local rows, local cols, expressions of a and t,",
        "#                local parameters each entry holds (-1: t), those it is not affine in,",
        "#                local rows of the force at rest, its expressions of a and t,",
        "#                common subexpressions (name, expression) computed first)",
        "TEMPLATES = (",
        *(f"    {entry!r}," for entry in printed),
        ")",
        "# per element: (template, global parameter indices (a), global coordinate indices (local rows, cols), label)",
        f"ELEMENTS = {tuple(elements)!r}",
        "",
    ]
    return "\n".join(lines)


def template_function(module, template, selection=None, loads=False):
    """A function ``f(a, t)`` returning the values of entries ``selection`` (default all) of one template.

    Parameters
    ----------
    module : module
        From :func:`linear_module` (its ``LINEAR`` is True).
    template : int
        Index into ``module.TEMPLATES``.
    selection : sequence of int, optional
        Entry indices of the template, in the order of the returned values.
    loads : bool
        True: the expressions of the force at rest instead of the matrix entries.
    """
    import math

    expressions = module.TEMPLATES[template][7 if loads else 3]
    prelude = module.TEMPLATES[template][8]
    selection = tuple(range(len(expressions))) if selection is None else tuple(int(i) for i in selection)
    key = (id(module), template, selection, loads)
    function = _FUNCTIONS.get(key)
    if function is None:
        needed = _needed(prelude, [expressions[i] for i in selection])
        head = "".join(f"    {name} = {code}\n" for name, code in prelude if name in needed)
        body = "".join(f"        ({expressions[i]}),\n" for i in selection)
        namespace = dict(vars(math))
        namespace.update({"max": max, "min": min, "abs": abs})
        text = f"def _entries(a, t):\n{head}    return [\n{body}    ]\n"
        exec(_compiled(module, text), namespace)
        function = _FUNCTIONS[key] = namespace["_entries"]
        if len(_FUNCTIONS) > 256:
            _FUNCTIONS.pop(next(iter(_FUNCTIONS)))
    return function


def _compiled(module, text):
    """The code of a template function: from the signed bytecode of the module's cache entry, or compiled."""
    import hashlib

    from .cache import compile_verified

    entry = getattr(module, "__rotorkit_entry__", None)
    name = "f" + hashlib.sha256(text.encode("utf-8")).hexdigest()[:24]
    return compile_verified(text, "<rotorkit linear matrices>", entry, name)


def _needed(prelude, expressions):
    """Names of the common subexpressions that ``expressions`` use, directly or through one another."""
    import re

    used = set(re.findall(r"\b_c\d+\b", " ".join(expressions)))
    for name, code in reversed(prelude):
        if name in used:
            used.update(re.findall(r"\b_c\d+\b", code))
    return used


def equations_text(model, latex=False):
    """The printed equations of ``model`` (``str(model.equations())`` or its LaTeX), cached per structure.

    The text depends only on the structure (parameters are printed as
    symbols), so it is stored in the model cache on first use
    (``<structure key>_text`` or ``_latex``) and read back afterwards
    without deriving.
    """
    from . import cache

    key = model.structure_key + ("_latex" if latex else "_text")
    module = _MODULES.get(key) or cache.load(key)
    if module is None or not isinstance(getattr(module, "TEXT", None), str):
        eqs = model.equations()
        text = eqs.latex() if latex else str(eqs)
        names = tuple(str(q) for q in eqs.coordinates)
        source = "\n".join([
            '"""The printed equations of one model structure, generated by rotorkit (do not edit)."""',
            f"N_COORDINATES = {len(names)}",
            f"STATE_NAMES = {names + tuple(f'{q}_dot' for q in names)!r}",
            f"TEXT = {text!r}",
            "",
        ])
        module = cache.store(key, source)
    _MODULES[key] = module
    return module.TEXT
