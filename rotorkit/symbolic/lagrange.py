"""Lagrange's equations assembled element by element.

Lagrange's equations are linear in T, V, D and Q, so each element's terms are
differentiated on their own, over the few coordinates they hold, and the
results are added. This grows linearly with the number of elements (a
whole-system ``LagrangesMethod`` grows roughly with the square of the DOF
count). For each element::

    p_i   = dT/dq'_i
    M_ij += dp_i/dq'_j
    f_i  += dT/dq_i - sum_k dp_i/dq_k q'_k - dp_i/dt - dV/dq_i - dD/dq'_i + Q_i

so that ``M(q, t) q'' = f(q, q', t)``.

The result, :class:`~rotorkit.symbolic.equations.EquationsOfMotion`, is in
:mod:`rotorkit.symbolic.equations` (importable from here too).
"""

from collections import defaultdict
from types import SimpleNamespace

import sympy as sp

from ..errors import TopologyError
from .equations import EquationsOfMotion, sparse_matrix
from .equations import MAX_DISPLAYED_COORDINATES, MAX_PRINTED_LINES  # noqa: F401 (their former home's path)

__all__ = ["EquationsOfMotion", "derive", "element_matrices", "Symbols"]

_CACHE = {}


class Symbols:
    """The symbols of one model structure: time, coordinates, speeds, parameters."""

    def __init__(self, model):
        self.t = sp.Symbol("t", real=True)
        self.coordinates = {n: sp.Symbol(n, real=True) for n in model.coordinate_names}
        self.speeds = {n: sp.Symbol(f"{n}_dot", real=True) for n in model.coordinate_names}
        self.parameters = {n: sp.Symbol(n, real=True) for n in model.parameters}

    def parameter(self, name):
        try:
            return self.parameters[name]
        except KeyError:
            raise TopologyError(f"parameter {name!r} is not defined by any element") from None


#: functions trigsimp sees; every other function application is held as an opaque symbol while it works
_TRIG = ("sin", "cos")


def _trigsimp(expr):
    """``sympy.trigsimp`` of ``expr`` over its sines and cosines only, so that it always ends.

    trigsimp rewrites exponentials and other functions too, and on a user's
    speed expression (``exp(1000*t)``, ``erf(100*t)``) it can search for
    minutes. Here every applied function other than sin and cos (with
    everything inside it) is replaced by a symbol first and put back after:
    an expression with only sines and cosines (the presets) goes through
    trigsimp exactly as before.
    """
    held = {}

    def hold(e):
        if e.is_Atom:
            return e
        if isinstance(e, sp.Function) and type(e).__name__ not in _TRIG or e.is_Pow and not e.exp.is_Number:
            if e not in held:
                held[e] = sp.Dummy(f"held{len(held)}")
            return held[e]
        args = tuple(hold(a) for a in e.args)
        return e if all(a is b for a, b in zip(args, e.args)) else e.func(*args)

    opaque = hold(expr)
    if not held:
        return sp.trigsimp(expr)
    return sp.trigsimp(opaque).xreplace({d: e for e, d in held.items()})


def _local(expr, index):
    """Indices (into ``index``'s coordinate order) of the symbols of ``index`` that ``expr`` holds, sorted."""
    if expr == 0:
        return []
    return sorted(index[s] for s in expr.free_symbols if s in index)


def _element_contribution(terms, q_index, u_index, qs, us, t):
    """Sparse (M, F, K, C) of one element's terms (F: inertial remainder, loads, non-quadratic elastic part).

    Only the element's own coordinates are visited (found from the free
    symbols of its terms), so the cost does not grow with the model size.
    """
    mass = {}
    force = defaultdict(lambda: sp.S.Zero)  # inertial remainder and loads
    elastic = defaultdict(lambda: sp.S.Zero)  # -dV/dq - dD/dq'
    T = sp.sympify(terms.kinetic)
    if T != 0:
        u_in = _local(T, u_index)
        for i in u_in:
            p = sp.diff(T, us[i])
            pfs = p.free_symbols
            for j in u_in:
                if j >= i and us[j] in pfs:
                    mij = _trigsimp(sp.expand(sp.diff(p, us[j])))
                    if mij != 0:
                        mass[(i, j)] = mij
            rest = sp.diff(p, t) + sum((sp.diff(p, qs[k]) * us[k] for k in _local(p, q_index)), sp.S.Zero)
            force[i] -= rest
        for i in _local(T, q_index):
            force[i] += sp.diff(T, qs[i])
        for i in list(force):
            force[i] = _trigsimp(sp.expand(force[i]))
    V, D = sp.sympify(terms.potential), sp.sympify(terms.dissipation)
    for i in sorted(set(_local(V, q_index)) | set(_local(D, u_index))):
        if V != 0 and qs[i] in V.free_symbols:
            elastic[i] -= sp.diff(V, qs[i])
        if D != 0 and us[i] in D.free_symbols:
            elastic[i] -= sp.diff(D, us[i])
    for q, load in terms.loads.items():
        force[q_index[q]] += load
    states = set(qs) | set(us)
    Ke = _hessian(V, qs, q_index, states)
    Ce = _hessian(D, us, u_index, states)
    if elastic:  # whatever of -dV/dq - dD/dq' is not -K q - C q' (none for quadratic V, D)
        linear = defaultdict(list)
        for (i, j), v in Ke.items():
            linear[i].append(v * qs[j])
        for (i, j), v in Ce.items():
            linear[i].append(v * us[j])
        for i, v in elastic.items():
            rest = sp.expand(v + sp.Add(*linear[i]))
            if rest != 0:
                force[i] += rest
    return mass, {i: v for i, v in force.items() if v != 0}, Ke, Ce


def _hessian(expr, variables, index, states):
    """Constant Hessian of a (quadratic) scalar at rest, as a sparse ``{(i, j): value}``.

    ``variables`` are the differentiation variables (indexed by ``index``);
    every state symbol in ``states`` is set to zero in the result, but only
    those the expression holds are visited.
    """
    expr = sp.sympify(expr)
    H = {}
    if expr == 0:
        return H
    present = _local(expr, index)
    for i in present:
        di = sp.diff(expr, variables[i])
        for j in present:
            if variables[j] in di.free_symbols:
                dij = sp.diff(di, variables[j])
                zero = {s: 0 for s in dij.free_symbols if s in states}
                value = dij.subs(zero) if zero else dij
                if value != 0:
                    H[(i, j)] = value
    return H


class _Templates:
    """Each element's contribution derived once per form, then renamed for every element of that form.

    An element's terms are written with its coordinates, speeds and
    parameters renamed to placeholders (ranked by coordinate index and by the
    element's parameter order); elements whose renamed terms are equal (the
    50 disks or beam elements of a rotor) share one derivation, renamed back
    with ``xreplace``. The derivation is equivariant under renaming, so this
    changes no equation, only the cost.
    """

    def __init__(self, qs, us, t):
        self.qs, self.us, self.t = qs, us, t
        self.q_index = {q: i for i, q in enumerate(qs)}
        self.u_index = {u: i for i, u in enumerate(us)}
        self.done = {}

    def _placeholders(self, k):
        return (sp.Symbol(f"_q{k}", real=True), sp.Symbol(f"_u{k}", real=True))

    def contribution(self, terms, own_parameters):
        T, V, D = (sp.sympify(e) for e in (terms.kinetic, terms.potential, terms.dissipation))
        loads = [(q, sp.sympify(v)) for q, v in terms.loads.items()]
        symbols = set().union(T.free_symbols, V.free_symbols, D.free_symbols, *(v.free_symbols for _, v in loads))
        symbols |= {q for q, _ in loads}
        coords = sorted({self.q_index[s] for s in symbols if s in self.q_index}
                        | {self.u_index[s] for s in symbols if s in self.u_index})
        rename = {}
        for k, i in enumerate(coords):
            rename[self.qs[i]], rename[self.us[i]] = self._placeholders(k)
        own = [s for s in own_parameters.values() if s in symbols]
        others = sorted((s for s in symbols if s not in rename and s != self.t and s not in own), key=str)
        for k, s in enumerate(own + others):
            rename[s] = sp.Symbol(f"_p{k}", **s.assumptions0)
        key = (T.xreplace(rename), V.xreplace(rename), D.xreplace(rename),
               tuple(sorted(((rename[q], v.xreplace(rename)) for q, v in loads), key=lambda kv: str(kv[0]))))
        local = self.done.get(key)
        if local is None:
            qs = tuple(self._placeholders(k)[0] for k in range(len(coords)))
            us = tuple(self._placeholders(k)[1] for k in range(len(coords)))
            renamed = SimpleNamespace(kinetic=key[0], potential=key[1], dissipation=key[2], loads=dict(key[3]))
            local = _element_contribution(renamed, {q: k for k, q in enumerate(qs)},
                                          {u: k for k, u in enumerate(us)}, qs, us, self.t)
            self.done[key] = local
        back = {v: k for k, v in rename.items()}

        def glob(d, pairs=False):
            if pairs:
                return {(coords[i], coords[j]): v.xreplace(back) for (i, j), v in d.items()}
            return {coords[i]: v.xreplace(back) for i, v in d.items()}

        mass, force, Ke, Ce = local
        return glob(mass, True), glob(force), glob(Ke, True), glob(Ce, True)


def _add_quadratic(form, q_index, M, K, C, force, totals, t=None):
    """Add a :class:`~rotorkit.elements.base.QuadraticForm`'s matrices (and energies, unless ``totals`` is None)."""
    idx = [q_index[q] for q in form.coordinates]
    m = len(idx)
    for A, target in ((form.mass, M), (form.stiffness, K), (form.damping, C)):
        if A is not None:
            for a in range(m):
                for b in range(m):
                    if A[a, b] != 0:
                        _add(target, (idx[a], idx[b]), A[a, b])
    if form.gyroscopic is not None:  # d/dt(N q) - N^T q' = N' q + (N - N^T) q' moves to the right-hand side
        N = form.gyroscopic
        timed = t is not None and any(t in e.free_symbols for e in N if e != 0)
        for a in range(m):
            row = sp.Add(*[(N[a, b] - N[b, a]) * form.speeds[b] for b in range(m) if N[a, b] != 0 or N[b, a] != 0])
            if timed:  # N(t): a changing spin speed (I_p Omega' terms)
                row += sp.Add(*[sp.diff(N[a, b], t) * form.coordinates[b] for b in range(m) if N[a, b] != 0])
            if row != 0:
                force[idx[a]] = force.get(idx[a], sp.S.Zero) - row
    if totals is None:  # matrices only (element_matrices): the energies are not needed
        return
    for name, value in (("kinetic", form.kinetic()), ("potential", form.potential()),
                        ("dissipation", form.dissipation())):
        if value != 0:
            totals[name].append(value)


def _state_gyroscopics(form, templates, speeds, M, force, totals):
    """``form`` without a gyroscopic matrix that holds a state, whose energy ``u^T N q`` is derived in full instead.

    A rotor whose speed is a degree of freedom (a Drive) puts its spin speed,
    a state, in ``N``: Lagrange's equations of ``u^T N(u) q`` then also hold
    ``dN/du`` terms (mass coupling of the spin and the tilts), which the
    matrix shortcut of :func:`_add_quadratic` leaves out. Forms whose ``N``
    holds no state (every constant-speed or speed-profile rotor) are
    returned unchanged.
    """
    import dataclasses

    N = form.gyroscopic
    if N is None or not any(e.free_symbols & speeds for e in N if e != 0):
        return form
    kinetic = form._form(N, form.speeds, form.coordinates)
    energy = SimpleNamespace(kinetic=kinetic, potential=sp.S.Zero, dissipation=sp.S.Zero, loads={})
    mass, extra, _, _ = templates.contribution(energy, {})
    for (i, j), v in mass.items():
        _add(M, (i, j), v)
        if i != j:
            _add(M, (j, i), v)
    for i, v in extra.items():
        force[i] = force.get(i, sp.S.Zero) + v
    totals["kinetic"].append(kinetic)
    return dataclasses.replace(form, gyroscopic=None)


def _add(target, key, value):
    """``target[key] += value`` on a dict of term lists (summed once at the end: no quadratic re-flattening)."""
    target.setdefault(key, []).append(value)


def derive(model):
    """Derive the equations of motion of ``model`` (cached per structure).

    The work per element is confined to the coordinates it holds and the
    system matrices are assembled sparsely, so the derivation time grows
    linearly with the number of elements (``bench/bench_derive.py`` measures
    the exponent).

    Returns
    -------
    EquationsOfMotion
    """
    key = model.structure_key
    if key not in _CACHE:
        from ..progress import announce_if_slow

        with announce_if_slow(f"deriving the equations of {model.name} ({len(model.coordinate_names)} coordinates, "
                              f"{len(model.elements)} elements)"):
            _CACHE[key] = _derive(model)
    return _CACHE[key]


def element_matrices(model):
    """Each element's own contribution, as :func:`derive` assembles it, without assembling the model.

    Yields, per element of ``model`` in order, ``(element, p, M, K, C, F)``:
    ``p`` maps the element's fields to their parameter symbols; ``M``, ``K``,
    ``C`` are ``{(i, j): expression}`` (coordinate indices; the mass filled
    on both sides of the diagonal); ``F`` is ``{i: expression}``, the
    element's generalised forces beyond ``-K q - C q'`` (loads, gyroscopic
    and other velocity terms, nonlinear forces). Summed over the elements
    these are the matrices and forces of ``derive(model)``. Identical
    elements (the beam segments of a shaft) share one derivation.

    Returns
    -------
    tuple
        ``(symbols, iterator)``: the model's :class:`Symbols` and the
        per-element iterator.
    """
    from ..context import Context

    symbols = Symbols(model)
    qs = tuple(symbols.coordinates.values())
    us = tuple(symbols.speeds.values())
    t = symbols.t
    q_index = {q: i for i, q in enumerate(qs)}
    templates = _Templates(qs, us, t)
    ctx = Context(model, symbols)

    def contributions():
        for element in model.elements:
            bound = ctx.bind(element)
            terms = element.contribute(bound)
            mass, force, Ke, Ce = templates.contribution(terms, bound.p)
            M, K, C = {}, {}, {}
            force = dict(force)
            for form in terms.quadratic:
                _add_quadratic(form, q_index, M, K, C, force, None, t)
            _add_blocks(mass, Ke, Ce, M, K, C)
            yield (element, bound.p, *({k: sp.Add(*v) for k, v in A.items()} for A in (M, K, C)),
                   {i: v for i, v in force.items() if v != 0})

    return symbols, contributions()


def _add_blocks(mass, stiffness, damping, M, K, C):
    """Add an element's mass (upper triangle, mirrored), stiffness and damping entries to the sums."""
    for (i, j), mij in mass.items():
        _add(M, (i, j), mij)
        if i != j:
            _add(M, (j, i), mij)
    for (i, j), v in stiffness.items():
        _add(K, (i, j), v)
    for (i, j), v in damping.items():
        _add(C, (i, j), v)


def _derive(model):
    from ..context import Context

    symbols = Symbols(model)
    qs = tuple(symbols.coordinates.values())
    us = tuple(symbols.speeds.values())
    t = symbols.t
    n = len(qs)
    q_index = {q: i for i, q in enumerate(qs)}
    templates = _Templates(qs, us, t)
    ctx = Context(model, symbols)
    M, K, C, F, loads = {}, {}, {}, {}, {}
    forces = {}
    totals = {"kinetic": [], "potential": [], "dissipation": []}
    switches = []
    for element in model.elements:
        bound = ctx.bind(element)
        terms = element.contribute(bound)
        switches += [(element.label(), sp.sympify(g)) for g in terms.switches]
        for name in totals:
            value = sp.sympify(getattr(terms, name))
            if value != 0:
                totals[name].append(value)
        for q, load in terms.loads.items():
            _add(loads, (q_index[q], 0), load)
        mass, force, Ke, Ce = templates.contribution(terms, bound.p)
        if terms.quadratic:  # finite elements: add the matrices, no differentiation
            force = dict(force)
            for form in terms.quadratic:
                form = _state_gyroscopics(form, templates, set(us), M, force, totals)
                _add_quadratic(form, q_index, M, K, C, force, totals, t)
        _add_blocks(mass, Ke, Ce, M, K, C)
        if force:
            forces[element.label()] = sparse_matrix(n, 1, {(i, 0): [v] for i, v in force.items()})
            for i, v in force.items():
                _add(F, i, v)
    M, K, C = sparse_matrix(n, n, M), sparse_matrix(n, n, K), sparse_matrix(n, n, C)
    K_rows, C_rows = defaultdict(list), defaultdict(list)
    for (i, j), v in K.todok().items():
        K_rows[i].append(v * qs[j])
    for (i, j), v in C.todok().items():
        C_rows[i].append(v * us[j])
    f = [sp.Add(*F.get(i, ())) - sp.Add(*K_rows[i]) - sp.Add(*C_rows[i]) for i in range(n)]
    eom = EquationsOfMotion(
        t=t,
        coordinates=qs,
        speeds=us,
        parameters=tuple(symbols.parameters.values()),
        mass_matrix=M,
        forcing=sp.ImmutableMatrix(n, 1, f),
        stiffness=K,
        damping=C,
        forces=forces,
        latex_names=_latex_names(model, symbols),
        loads=sparse_matrix(n, 1, loads),
        switches=tuple(switches),
        **{name: sp.Add(*terms) for name, terms in totals.items()},
    )
    return eom


def _latex_names(model, symbols):
    """Symbol -> LaTeX name; element labels and station/axis names are escaped text.

    Labels are identifiers such as ``bearing4_7``: inside ``\\mathrm{}`` a bare
    ``_`` would be a subscript (``bearing4`` with a subscript 7), so every
    character LaTeX treats specially is escaped.
    """
    special = {"_": r"\_", "#": r"\#", "%": r"\%", "&": r"\&", "$": r"\$", "{": r"\{", "}": r"\}"}

    def word(text):
        return "".join(special.get(ch, ch) for ch in str(text))

    names = {}
    bases = {"alpha": r"\alpha", "thx": r"\theta_{x}", "thy": r"\theta_{y}"}
    for (station, axis), (n, q) in zip(model.coordinates, symbols.coordinates.items()):
        base = bases.get(axis, axis if len(axis) == 1 else rf"\mathrm{{{word(axis)}}}")
        names[q] = f"{base}_{{{word(station)}}}"
        names[symbols.speeds[n]] = rf"\dot{{{base}}}_{{{word(station)}}}"
    for e in model.elements:
        label = word(e.label())
        for f in e.parameters():
            base = e._latex_names.get(f) or (f if len(f) == 1 else rf"\mathrm{{{word(f)}}}")
            names[symbols.parameters[f"{e.label()}_{f}"]] = f"{base}^{{\\mathrm{{{label}}}}}"
    return names
