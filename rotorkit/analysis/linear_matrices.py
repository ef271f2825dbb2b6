"""Numeric ``M``, ``C``, ``K`` of a model whose equations are linear, straight from its symbolic matrices.

A model built from linear elements (beam segments, disks, linear bearings,
elastic supports, gyroscopics) has equations ``M q'' + C q' + K q = F(t)``
whose matrices the derivation already holds symbolically and sparsely
(:class:`~rotorkit.symbolic.lagrange.EquationsOfMotion`: ``mass_matrix``,
``stiffness``, ``damping``, and the element forces, e.g. the gyroscopic
``-W G q'`` and a speed-dependent bearing's ``-K(W) q - C(W) q'``). Here
they are turned, once per model structure, into one generated Python
function of the parameters and the time that returns every nonzero entry:
a speed sweep then evaluates numbers, it never differentiates the
right-hand side numerically or re-linearises.

A model with a force that is not linear in the coordinates and their
rates (Hertzian ball bearings, rub contacts) has no such matrices:
:func:`linear_matrices` returns None and the analyses linearise the
compiled system at its operating point instead
(:func:`~rotorkit.analysis.linearize.linearize`).

Rotors whose speed is a :class:`~rotorkit.elements.speed.SpeedProfile` are
analysed at a frozen speed: :func:`frozen_speed_model` replaces each
profile by the constant speed it has at a time ``t`` (or a given one), so
that ``<rotor>_speed`` is a parameter that can be swept.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import ParameterError

__all__ = ["LinearMatrices", "linear_evaluator", "linear_matrices", "frozen_speed_model", "rotor_spin_speeds",
           "station_positions"]

#: (structure, parameter values, t, free parameters) -> LinearMatrices or None (not linear); a few kept
_CACHE = {}
_CACHE_SIZE = 8


def _namespace():
    namespace = dict(vars(math))
    namespace.update({"max": max, "min": min, "abs": abs})
    return namespace


class LinearMatrices:
    """``M``, ``C``, ``K`` of a linear model as numbers, except for a few free parameters (the swept speed).

    Built by :func:`linear_evaluator`; calling it with values of the free
    parameters returns the three scipy CSR matrices (SI units). Entries that
    do not depend on the free parameters are numbers already; the others
    (gyroscopic terms, speed-dependent bearing coefficients) are small
    expressions of them, evaluated by one generated function.
    """

    def __init__(self, n, free, constant, variable, source):
        self.n = n
        self.free = free
        self._constant = constant  # per matrix: (rows, cols, values)
        self._variable = variable  # per matrix: (rows, cols), values from the generated function in order
        namespace = _namespace()
        exec(compile(source, "<rotorkit linear matrices>", "exec"), namespace)
        self._function = namespace["_entries"]

    def __call__(self, **free_values):
        from scipy import sparse

        missing = set(self.free) - set(free_values)
        if missing:
            raise ParameterError(f"LinearMatrices: values of {sorted(missing)} are needed")
        flat = np.array(self._function([float(free_values[name]) for name in self.free]), dtype=float)
        out, start = [], 0
        for (rows, cols, values), (vrows, vcols) in zip(self._constant, self._variable):
            data = np.concatenate([values, flat[start:start + vrows.size]])
            start += vrows.size
            out.append(sparse.csr_matrix((data, (np.concatenate([rows, vrows]), np.concatenate([cols, vcols]))),
                                         shape=(self.n, self.n)))
        return tuple(out)


def _build(model, values, t, free):
    """:class:`LinearMatrices` of ``model`` at ``values``, or None if a force is not linear in the states."""
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
    source = f"def _entries(p):\n    return [\n{body}    ]\n"
    return LinearMatrices(len(qs), tuple(free), constant, variable, source)


def linear_evaluator(model, t=0.0, values=None, free=()):
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
    """
    values = model.parameters if values is None else dict(values)
    free = tuple(free)
    key = (model.structure_key, tuple(sorted((k, float(v)) for k, v in values.items() if k not in free)),
           float(t), free)
    if key not in _CACHE:
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = _build(model, values, t, free)
    return _CACHE[key]


def linear_matrices(model, t=0.0, values=None):
    """``(M, C, K)`` (scipy CSR, SI units) of a linear model at time ``t``, or None if it is not linear.

    Parameters
    ----------
    model : rotorkit.Model
        Rotors with constant speeds (:func:`frozen_speed_model` freezes speed profiles).
    t : float
        Time (s).
    values : dict, optional
        Parameter name -> value (SI), default ``model.parameters``.

    Returns
    -------
    tuple of scipy.sparse.csr_matrix, shape (n, n), or None
        ``C`` holds the damping and the gyroscopic terms at the current
        speeds, ``K`` the stiffness with any cross-coupled or circulatory
        part, both including speed-dependent bearing coefficients.
    """
    evaluator = linear_evaluator(model, t, values)
    return None if evaluator is None else evaluator()


def _profile_speed(rotor, t):
    """A profile rotor's speed (rad/s) at time ``t`` (a driven rotor's: its initial speed)."""
    import sympy as sp

    if rotor.drive is not None:
        return rotor.drive.initial_speed

    from ..codegen.printer import RhsPrinter

    profile = rotor.profile
    ts = sp.Symbol("t", real=True)
    p = {k: sp.Float(v) for k, v in profile.values().items()}
    code = RhsPrinter().doprint(profile.speed(ts, p).xreplace({ts: sp.Float(float(t))}))
    return float(eval(code, {"__builtins__": {}}, _namespace()))


def rotor_spin_speeds(model, t=0.0, values=None):
    """Rotor name -> spin speed (rad/s) at time ``t`` (profiles evaluated there, ratios applied)."""
    values = model.parameters if values is None else values
    rotors = model.rotors
    out = {}
    for name in rotors:
        factor, r = 1.0, rotors[name]
        while r.speed is None:
            factor *= values[f"{r.name}_speed_ratio"]
            r = rotors[r.reference]
        if r.drive is not None:
            out[name] = factor * values[f"{r.name}_speed_initial"]
            continue
        out[name] = factor * (_profile_speed(r, t) if r.profile is not None else values[f"{r.name}_speed"])
    return out


def frozen_speed_model(model, t=0.0, speeds=None):
    """``model`` with every speed-profile rotor turned into a constant-speed one (itself if there is none).

    A rotor whose speed is a :class:`~rotorkit.elements.drive.Drive` (a
    degree of freedom) is frozen at its ``initial_speed``: the linear
    analyses hold the spin constant.

    Parameters
    ----------
    model : rotorkit.Model
    t : float
        Time (s) at which each profile gives its speed.
    speeds : dict, optional
        Rotor name -> speed (rad/s) to use instead of the profile's at ``t``.

    Raises
    ------
    ParameterError
        If ``speeds`` names a rotor without a speed profile.
    """
    speeds = dict(speeds or {})
    profiles = {name: r for name, r in model.rotors.items() if r.profile is not None or r.drive is not None}
    unknown = set(speeds) - set(profiles)
    if unknown:
        raise ParameterError(
            f"speeds={speeds!r}: {sorted(unknown)} have no speed profile; expected rotors among "
            f"{sorted(profiles) or 'none'} (set the speed of a constant-speed rotor with <rotor>_speed)")
    if not profiles:
        return model
    elements = []
    for e in model.elements:
        if e.owned_stations() and e.label() in profiles:
            value = speeds.get(e.label())
            value = _profile_speed(e, t) if value is None else float(value)
            e = dataclasses.replace(e, speed=value)
        elements.append(e)
    from ..model import Model

    return Model(elements, name=model.name)


def station_positions(model):
    """Station -> axial position (m) along each rotor from its beam and shaft lengths, or None.

    Each rotor's first station is at 0; a beam segment's nodes are equally
    spaced over its length. Stations no length reaches are left out.
    """
    edges = {}
    for e in model.elements:
        length = getattr(e, "length", None)
        if length is None or not hasattr(e, "start") or not hasattr(e, "end"):
            continue
        nodes = e.nodes() if hasattr(e, "nodes") else (e.start, e.end)
        step = float(length) / (len(nodes) - 1)
        for a, b in zip(nodes, nodes[1:]):
            edges.setdefault(a, []).append((b, step))
            edges.setdefault(b, []).append((a, -step))
    if not edges:
        return None
    positions = {}
    for station in model.stations:
        if station in positions or station not in edges:
            continue
        positions[station] = 0.0
        stack = [station]
        while stack:
            a = stack.pop()
            for b, step in edges.get(a, ()):
                if b not in positions:
                    positions[b] = positions[a] + step
                    stack.append(b)
    return {str(s): z for s, z in positions.items()}
