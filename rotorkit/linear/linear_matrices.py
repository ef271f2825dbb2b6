"""Numeric ``M``, ``C``, ``K`` of a model whose equations are linear, straight from its symbolic matrices.

A model built from linear elements (beam segments, disks, linear bearings,
elastic supports, gyroscopics) has equations ``M q'' + C q' + K q = F(t)``
whose matrices the derivation already holds symbolically and sparsely
(:class:`~rotorkit.symbolic.lagrange.EquationsOfMotion`: ``mass_matrix``,
``stiffness``, ``damping``, and the element forces, e.g. the gyroscopic
``-W G q'`` and a speed-dependent bearing's ``-K(W) q - C(W) q'``). They
are turned, once per model structure, into generated Python expressions of
the parameters and the time, one per nonzero entry, and kept in the model
cache beside the right-hand side (:mod:`rotorkit.codegen.linear_cache`):
a process with a warm cache never derives, and a speed sweep evaluates
numbers, it never differentiates the right-hand side numerically or
re-linearises. :func:`symbolic_linear_evaluator` builds the same matrices
from the derived equations in this process (the reference the cache is
tested against).

A model with a force that is not linear in the coordinates and their
rates (Hertzian ball bearings, rub contacts) has no such matrices:
:func:`linear_matrices` returns None and the analyses linearise the
compiled system at its operating point instead
(:func:`~rotorkit.analysis.linearize.linearize`).

Rotors whose speed is a :class:`~rotorkit.elements.speed.SpeedProfile` are
analysed at a frozen speed: :func:`frozen_speed_model` replaces each
profile by the constant speed it has at a time ``t`` (or a given one), so
that ``<rotor>_speed`` is a parameter that can be swept.

The spin speeds and frozen-speed models live in
:mod:`rotorkit.linear.rotor_speeds`, the station positions in
:mod:`rotorkit.linear.station_positions` and the element forces at rest in
:mod:`rotorkit.linear.element_loads`; all are importable from here.
"""

from __future__ import annotations

import numpy as np

from ..errors import ParameterError
from .element_loads import element_forces, loads_at_rest
from .rotor_speeds import expression_namespace, frozen_speed_model, rotor_spin_speeds
from .station_positions import shaft_edges, station_positions, walk_positions

__all__ = ["shaft_edges", "walk_positions", "LinearMatrices", "linear_evaluator", "linear_matrices", "symbolic_linear_evaluator", "element_forces",
           "linear_static_deflection",
           "frozen_speed_model", "rotor_spin_speeds", "station_positions", "modal_damping_spec",
           "model_modal_damping"]

#: (structure, parameter values, t, free parameters) -> LinearMatrices or None (not linear); a few kept
_CACHE = {}
_CACHE_SIZE = 8
#: up to this many coordinates the static deflection is a dense numpy solve, above it a sparse one
DENSE_STATIC_SIZE = 1000


def _scalar_rows(function, arrays):
    """``function`` (of a list of free values) at each point of ``arrays`` (k arrays of m values): shape (m, ...)."""
    m = max((a.size for a in arrays), default=1)
    arrays = [np.broadcast_to(a, (m,)) for a in arrays]
    return np.array([np.asarray(function([float(a[i]) for a in arrays]), dtype=float) for i in range(m)])


class LinearMatrices:
    """``M``, ``C``, ``K`` of a linear model as numbers, except for a few free parameters (the swept speed).

    Built by :func:`linear_evaluator`; calling it with values of the free
    parameters returns the three scipy CSR matrices (SI units). Entries that
    do not depend on the free parameters are numbers already; the others
    (gyroscopic terms, speed-dependent bearing coefficients) are small
    expressions of them, evaluated by one generated function.

    Attributes
    ----------
    n : int
        Number of coordinates.
    free : tuple of str
        The free parameters, given at each call.
    variable_entries : tuple of (numpy.ndarray, numpy.ndarray, numpy.ndarray)
        ``(matrix, rows, cols)`` of the entries that depend on the free
        parameters (``matrix``: 0 for M, 1 for C, 2 for K), in the order of
        :meth:`variable_values`.
    nonaffine : numpy.ndarray of bool
        Per variable entry: True where it is not affine in the free
        parameters (a tabulated coefficient), or not known to be.
    """

    def __init__(self, n, free, constant, variable, function, nonaffine=None, select=None):
        self.n = n
        self._select = select  # mask -> function of the free values returning the masked variable entries
        self.free = free
        self._constant = constant  # per matrix: (rows, cols, values)
        self._variable = variable  # per matrix: (rows, cols), values from the function in order
        self._function = function  # list of free values -> values of the variable entries, matrix by matrix
        which = np.concatenate([np.full(r.size, k, dtype=np.int64) for k, (r, _) in enumerate(variable)])
        self.variable_entries = (which, np.concatenate([r for r, _ in variable]),
                                 np.concatenate([c for _, c in variable]))
        self.nonaffine = np.ones(which.size, dtype=bool) if nonaffine is None else np.asarray(nonaffine, dtype=bool)

    def variable_values(self, **free_values):
        """Values of the entries that depend on the free parameters (see :attr:`variable_entries`)."""
        missing = set(self.free) - set(free_values)
        if missing:
            raise ParameterError(f"LinearMatrices: values of {sorted(missing)} are needed")
        return np.array(self._function([float(free_values[name]) for name in self.free]), dtype=float)

    def entries_function(self, mask):
        """A function of the free values (in :attr:`free` order) returning the variable entries where ``mask``."""
        mask = np.asarray(mask, dtype=bool)
        if self._select is not None:
            return self._select(mask)
        function = self._function
        return lambda free_values: np.asarray(function(list(free_values)), dtype=float)[mask]

    def entries_function_many(self, mask):
        """:meth:`entries_function` over many points at once: ``f(arrays)`` -> shape (m, k).

        ``arrays`` holds one array of m values per free parameter (in
        :attr:`free` order); the result row ``i`` equals
        ``entries_function(mask)`` at point ``i`` (the same generated
        expressions, evaluated by numpy over the points where they can be,
        point by point otherwise).
        """
        mask = np.asarray(mask, dtype=bool)
        scalar = self.entries_function(mask)
        many = self._select(mask, True) if self._select is not None else None

        def entries(arrays):
            arrays = [np.asarray(a, dtype=float).reshape(-1) for a in arrays]
            if many is not None:
                out = many(arrays)
                if out is not None:
                    return out
            return _scalar_rows(scalar, arrays).reshape(-1, int(mask.sum()))

        return entries

    def dense(self, **free_values):
        """``(M, C, K)`` as dense numpy arrays, shape (n, n): :meth:`__call__` without scipy (small models)."""
        flat = self.variable_values(**free_values)
        out, start = [], 0
        for (rows, cols, values), (vrows, vcols) in zip(self._constant, self._variable):
            A = np.zeros((self.n, self.n))
            np.add.at(A, (rows, cols), values)
            np.add.at(A, (vrows, vcols), flat[start:start + vrows.size])
            start += vrows.size
            out.append(A)
        return tuple(out)

    def with_damping(self, C):
        """A copy with the constant dense matrix ``C`` (n, n) added to the damping (a modal damping)."""
        rows, cols = np.nonzero(C)
        old = self._constant[1]
        constant = list(self._constant)
        constant[1] = (np.concatenate([old[0], rows]), np.concatenate([old[1], cols]),
                       np.concatenate([old[2], C[rows, cols]]))
        return LinearMatrices(self.n, self.free, constant, self._variable, self._function, self.nonaffine,
                              self._select)

    def __call__(self, **free_values):
        from scipy import sparse

        flat = self.variable_values(**free_values)
        out, start = [], 0
        for (rows, cols, values), (vrows, vcols) in zip(self._constant, self._variable):
            data = np.concatenate([values, flat[start:start + vrows.size]])
            start += vrows.size
            out.append(sparse.csr_matrix((data, (np.concatenate([rows, vrows]), np.concatenate([cols, vcols]))),
                                         shape=(self.n, self.n)))
        return tuple(out)


def _from_module(module, values, t, free):
    """:class:`LinearMatrices` assembled from the cached element templates (:mod:`rotorkit.codegen.linear_cache`)."""
    from ..codegen.linear_cache import template_function
    from .array_code import array_function, array_template_function

    if not module.LINEAR:
        return None
    names = module.PARAMETERS
    p = [0.0 if name.endswith("_eccentricity") else float(values[name]) for name in names]
    free_slot = {names.index(name): k for k, name in enumerate(free) if name in names}
    speed_like = all(name.endswith("_speed") for name in free)
    t = float(t)
    fixed = [[], [], []]  # per matrix: lists of (rows, cols, values) arrays
    moving = []  # per element with free entries: (template, selection, a, free slots, selection array,
    #              coordinates, not-affine flags)
    arrays, splits, functions_of = {}, {}, {}  # per template (and its free locals): computed once, shared by
    #                                              the elements of a template (the segments of a shaft)

    def template_arrays(template):
        if template not in arrays:
            arrays[template] = tuple(np.asarray(x, dtype=np.int64) for x in module.TEMPLATES[template][:3])
        return arrays[template]

    def function_of(template, selection):
        if (template, selection) not in functions_of:
            functions_of[template, selection] = template_function(module, template, selection)
        return functions_of[template, selection]

    for template, params, coords, _label in module.ELEMENTS:
        coords = np.asarray(coords, dtype=np.int64)
        a = [p[k] for k in params]
        slots = [(local, free_slot[k]) for local, k in enumerate(params) if k in free_slot]
        local_free = frozenset(local for local, _ in slots)
        split = splits.get((template, local_free))
        if split is None:  # the entries that hold a free parameter (chosen) and the others (rest)
            depends, nonaffine = module.TEMPLATES[template][4:6]
            chosen = tuple(e for e, d in enumerate(depends) if local_free.intersection(d))
            rest = tuple(e for e, d in enumerate(depends) if not local_free.intersection(d))
            flags = [bool(local_free.intersection(nonaffine[e])) or not speed_like for e in chosen]
            matrix = template_arrays(template)[0]
            split = splits[template, local_free] = (chosen, rest, np.asarray(rest, dtype=np.int64),
                                                    [matrix[np.asarray(rest, dtype=np.int64)] == w for w in range(3)],
                                                    flags)
        chosen, rest, rest_array, rest_masks, flags = split
        matrix, lrows, lcols = template_arrays(template)
        if rest:
            vals = np.array(function_of(template, rest)(a, t), dtype=float)
            for which in range(3):
                mask = rest_masks[which]
                fixed[which].append((coords[lrows[rest_array[mask]]], coords[lcols[rest_array[mask]]], vals[mask]))
        if chosen:
            moving.append((template, chosen, a, slots, np.asarray(chosen), coords, flags))
    constant, variable, order, nonaffine = [], [], [], []
    for which in range(3):
        parts = fixed[which] or [(np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0))]
        constant.append(tuple(np.concatenate([part[k] for part in parts]) for k in range(3)))
        vrows, vcols = [], []
        for m, (template, _, _, _, chosen, coords, flags) in enumerate(moving):
            matrix, lrows, lcols = template_arrays(template)
            mask = matrix[chosen] == which
            vrows.append(coords[lrows[chosen[mask]]])
            vcols.append(coords[lcols[chosen[mask]]])
            order.extend((m, int(k)) for k in np.flatnonzero(mask))
            nonaffine.extend(f for f, keep in zip(flags, mask) if keep)
        variable.append((np.concatenate(vrows) if vrows else np.zeros(0, np.int64),
                         np.concatenate(vcols) if vcols else np.zeros(0, np.int64)))
    functions = [function_of(template, selection) for template, selection, *_ in moving]
    starts = np.cumsum([0] + [len(x[1]) for x in moving])
    gather = np.array([starts[m] + k for m, k in order], dtype=np.int64)

    def function(free_values):
        out = []
        for f, (_, _, a, slots, *_rest) in zip(functions, moving):
            if slots:
                a = list(a)
                for local, k in slots:
                    a[local] = free_values[k]
            out.extend(f(a, t))
        return np.asarray(out, dtype=float)[gather] if out else np.zeros(0)

    def select(mask, many=False):
        picked = [order[i] for i in np.flatnonzero(mask)]
        by_element = {}
        for position, (m, k) in enumerate(picked):
            by_element.setdefault(m, []).append((position, k))
        parts, sources = [], []
        for m, items in by_element.items():
            template, selection, a, slots = moving[m][:4]
            chosen = tuple(selection[k] for _, k in items)
            f = template_function(module, template, chosen)
            parts.append((array_function(f) if many else f, a, slots,
                          np.array([position for position, _ in items], dtype=np.int64)))
            sources.append((template, chosen))

        def entries(free_values):
            out = np.empty(len(picked))
            for f, a, slots, positions in parts:
                if slots:
                    a = list(a)
                    for local, k in slots:
                        a[local] = free_values[k]
                out[positions] = f(a, t)
            return out

        def evaluate(functions, arrays):
            out = np.empty((len(picked), max((x.size for x in arrays), default=1)))
            for f, (_, a, slots, positions) in zip(functions, parts):
                if slots:
                    a = list(a)
                    for local, k in slots:
                        a[local] = arrays[k]
                for position, value in zip(positions, f(a, t)):
                    out[position] = value
            return out

        def entries_many(arrays):
            """Shape (m, k) over the points of ``arrays`` (one per free parameter), or None if numpy cannot."""
            try:
                with np.errstate(all="raise", under="ignore"):  # anything unusual: the scalar code decides
                    return evaluate([part[0] for part in parts], arrays).T
            except Exception:
                pass
            try:  # conditional expressions (guarded pieces): rewritten to numpy.where of both branches
                rewritten = [array_template_function(module, template, chosen) for template, chosen in sources]
                with np.errstate(all="ignore"):  # the branch not taken may divide by zero
                    out = evaluate(rewritten, arrays)
            except Exception:  # code numpy cannot run on arrays (erf...): point by point
                return None
            return out.T if np.all(np.isfinite(out)) else None

        return entries_many if many else entries

    return LinearMatrices(int(module.N_COORDINATES), tuple(free), constant, variable, function, nonaffine, select)


def symbolic_linear_evaluator(model, t=0.0, values=None, free=()):
    """:class:`LinearMatrices` of ``model`` at ``values`` straight from its derived equations, or None if not linear.

    The reference for the cached matrices (:func:`linear_evaluator`): the
    symbolic matrices with the numbers substituted, derived in this process.
    """
    values = model.parameters if values is None else dict(values)
    free = tuple(free)
    import sympy as sp

    from ..codegen.printer import RhsPrinter

    eqs = model.equations()
    qs, us = eqs.coordinates, eqs.speeds
    q_index = {q: i for i, q in enumerate(qs)}
    u_index = {u: i for i, u in enumerate(us)}
    states = set(qs) | set(us)
    free_symbols = {str(p): p for p in eqs.parameters if str(p) in free}
    numbers = {p: sp.Float(0.0 if str(p).endswith("_eccentricity") else float(values[str(p)]))
               for p in eqs.parameters if str(p) not in free}
    numbers[eqs.t] = sp.Float(float(t))
    entries = [{}, {}, {}]  # M, C, K: (i, j) -> [terms]

    def add(which, key, value):
        if value != 0:
            entries[which].setdefault(key, []).append(value)

    for (i, j), v in eqs.mass_matrix.todok().items():
        v = sp.sympify(v).xreplace(numbers)
        if v.free_symbols & states:
            return None  # a mass matrix that depends on the coordinates: not a linear model
        add(0, (i, j), v)
    for which, matrix in ((2, eqs.stiffness), (1, eqs.damping)):
        for key, v in matrix.todok().items():
            add(which, key, sp.sympify(v).xreplace(numbers))
    for (i, _), f in eqs.nonlinear_forcing().todok().items():
        f = sp.sympify(f).xreplace(numbers)
        for s in f.free_symbols & states:
            d = sp.diff(f, s)
            if d.free_symbols & states:
                return None  # contact, Hertzian bearing: linearise the compiled system instead
            if s in q_index:
                add(2, (i, q_index[s]), -d)
            else:
                add(1, (i, u_index[s]), -d)
    printer = RhsPrinter({free_symbols[name]: f"p[{k}]" for k, name in enumerate(free) if name in free_symbols})
    constant, variable, lines = [], [], []
    for table in entries:
        fixed, moving = [], []
        for key, terms in sorted(table.items()):
            value = sp.Add(*terms)
            (moving if value.free_symbols else fixed).append((key, value))
        constant.append((np.array([k[0] for k, _ in fixed], dtype=np.int64),
                         np.array([k[1] for k, _ in fixed], dtype=np.int64),
                         np.array([float(v) for _, v in fixed], dtype=float)))
        variable.append((np.array([k[0] for k, _ in moving], dtype=np.int64),
                         np.array([k[1] for k, _ in moving], dtype=np.int64)))
        lines += [printer.doprint(v) for _, v in moving]
    body = "".join(f"        ({line}),\n" for line in lines)
    namespace = expression_namespace()
    exec(compile(f"def _entries(p):\n    return [\n{body}    ]\n", "<rotorkit linear matrices>", "exec"), namespace)
    return LinearMatrices(len(qs), tuple(free), constant, variable, namespace["_entries"])


def linear_evaluator(model, t=0.0, values=None, free=(), *, modal_damping=True):
    """The :class:`LinearMatrices` of ``model`` with ``free`` parameters left open, or None if it is not linear.

    Parameters
    ----------
    model : rotorkit.Model
        Its rotors must have constant speeds (see :func:`frozen_speed_model`).
    t : float
        Time (s) of any time-dependent coefficient.
    values : dict, optional
        Parameter name -> value (SI), default ``model.parameters``; disk
        eccentricities count as 0 (unbalance is a forcing, not part of the
        matrices).
    free : tuple of str
        Parameters left open (e.g. ``("R_speed",)``), given at each call.
    modal_damping : bool
        True (default): a rotor's :class:`~rotorkit.elements.damping.ModalDamping`
        is added to ``C`` (built at rest from these values,
        :func:`model_modal_damping`); False:
        the matrices of the derived equations only.
    """
    values = model.parameters if values is None else dict(values)
    free = tuple(free)
    spec = modal_damping_spec(model) if modal_damping else None
    key = (model.structure_key, tuple(sorted((k, float(v)) for k, v in values.items() if k not in free)),
           float(t), free, spec)
    if key not in _CACHE:
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        if spec is None:
            from ..codegen.linear_cache import linear_module

            _CACHE[key] = _from_module(linear_module(model), values, t, free)
        else:
            plain = linear_evaluator(model, t, values, free, modal_damping=False)
            _CACHE[key] = None if plain is None else plain.with_damping(model_modal_damping(model, values, t))
    return _CACHE[key]


def linear_matrices(model, t=0.0, values=None, *, modal_damping=True):
    """``(M, C, K)`` (scipy CSR, SI units) of a linear model at time ``t``, or None if it is not linear.

    Parameters
    ----------
    model : rotorkit.Model
        Rotors with constant speeds (:func:`frozen_speed_model` freezes speed profiles).
    t : float
        Time (s).
    values : dict, optional
        Parameter name -> value (SI), default ``model.parameters``.
    modal_damping : bool
        Add a rotor's :class:`~rotorkit.elements.damping.ModalDamping` to ``C``
        (default), as in :func:`linear_evaluator`.

    Returns
    -------
    tuple of scipy.sparse.csr_matrix, shape (n, n), or None
        ``C`` holds the damping and the gyroscopic terms at the current
        speeds, ``K`` the stiffness with any cross-coupled or circulatory
        part, both including speed-dependent bearing coefficients.
    """
    evaluator = linear_evaluator(model, t, values, modal_damping=modal_damping)
    return None if evaluator is None else evaluator()


def linear_static_deflection(model, t=0.0, values=None):
    """Coordinates at rest under the static loads of a linear model, ``K q = F(0)``, or None if it is not linear.

    Parameters
    ----------
    model : rotorkit.Model
    t : float
        Time (s) of the loads.
    values : dict, optional
        Parameter name -> value (SI), default ``model.parameters``.

    Returns
    -------
    numpy.ndarray, shape (n,), or None
        ``q`` (m, rad) in ``model.coordinate_names`` order.

    Raises
    ------
    ParameterError
        If ``K`` is singular (a rotor without a stiffness path to a support).
    """
    from ..codegen.linear_cache import linear_module

    module = linear_module(model)
    if not module.LINEAR:
        return None
    values = model.parameters if values is None else values
    evaluator = linear_evaluator(model, t, values)
    p = [0.0 if name.endswith("_eccentricity") else float(values[name]) for name in module.PARAMETERS]
    F = loads_at_rest(module, p, float(t))
    if not np.any(F):
        return np.zeros(F.size)
    if evaluator.n <= DENSE_STATIC_SIZE:  # dense LU in numpy: no scipy import for an everyday rotor
        try:
            q = np.linalg.solve(evaluator.dense()[2], F)
        except np.linalg.LinAlgError:  # an exactly zero pivot
            q = np.full(F.size, np.nan)
    else:
        import warnings

        from scipy.sparse.linalg import MatrixRankWarning, spsolve

        with warnings.catch_warnings():
            warnings.simplefilter("error", MatrixRankWarning)
            try:
                q = spsolve(evaluator()[2].tocsc(), F)
            except MatrixRankWarning:
                q = np.full(F.size, np.nan)
    if not np.all(np.isfinite(q)):
        raise ParameterError(f"static deflection of {model.name!r}: the stiffness matrix is singular; a rotor may "
                             "have no stiffness path to a support")
    return q


def modal_damping_spec(model):
    """The :class:`~rotorkit.elements.damping.ModalDamping` of ``model``'s rotors, or None (at most one holds it)."""
    rotors = getattr(model, "rotors", None) or {}
    for rotor in rotors.values():  # duck-typed: importing rotorkit.elements here would close an import cycle
        damping = getattr(rotor, "damping", None)
        if hasattr(damping, "ratios") and hasattr(damping, "remaining"):
            return damping
    return None


def model_modal_damping(model, values=None, t=0.0):
    """The modal damping matrix (n, n) of ``model``'s :class:`~rotorkit.elements.damping.ModalDamping`, or None.

    ``C = M Phi diag(2 zeta_k w_k) Phi^T M`` from the undamped modes
    (``K_s phi = w^2 M phi``, ``K_s`` the symmetric part of the stiffness,
    ``Phi^T M Phi = I``) at rest (every rotor speed 0) at the parameter
    ``values`` (SI, default ``model.parameters``) and time ``t``; mode ``k``
    gets ``ratios[k]``, further modes ``remaining``, rigid-body modes none
    (:mod:`rotorkit.linear.modal_damping`). A model whose forces are not
    linear has no such modes: ParameterError.
    """
    spec = modal_damping_spec(model)
    if spec is None:
        return None
    M, _, w, Phi = undamped_modes(
        model, values, t, who=f"ModalDamping: model {model.name!r} has forces that are not linear (contacts, Hertzian "
                              "bearings), so it has no undamped modes to damp; expected a linear model (use Rayleigh)")
    return modal_damping_from_modes(M, w, Phi, spec.ratios, spec.remaining)


def undamped_modes(model, values=None, t=0.0, who=None):
    """``(M, K_s, w, Phi)``: mass, symmetric stiffness at rest and the undamped modes of ``model``.

    ``w`` (rad/s, ascending, shape (n,)) and ``Phi`` (n, n) mass-normalised
    (``Phi^T M Phi = I``); every rotor speed set to 0. ``who``: the message
    of the ParameterError for a model whose forces are not linear.
    """
    from scipy.linalg import eigh

    values = dict(model.parameters if values is None else values)
    for name in rotor_spin_speeds(model, t, values):
        if f"{name}_speed" in values:
            values[f"{name}_speed"] = 0.0
    matrices = linear_matrices(model, t, values, modal_damping=False)
    if matrices is None:
        raise ParameterError(who or f"modal damping: {model.name!r} has forces that are not linear; expected a "
                                    "linear model")
    M, _, K = (A.toarray() for A in matrices)
    K = (K + K.T) / 2
    w2, Phi = eigh(K, M)
    return M, K, np.sqrt(np.clip(w2, 0.0, None)), Phi


def modal_damping_from_modes(M, w, Phi, ratios, remaining):
    """``C = M Phi diag(2 zeta_k w_k) Phi^T M``: mode ``k`` gets ``ratios[k]``, further modes ``remaining``."""
    zeta = np.full(w.size, float(remaining))
    k = min(len(ratios), w.size)
    zeta[:k] = ratios[:k]
    MPhi = M @ Phi
    return (MPhi * (2.0 * zeta * w)) @ MPhi.T
