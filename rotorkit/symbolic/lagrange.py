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
"""

from collections import defaultdict
from dataclasses import dataclass, field

import sympy as sp

from ..errors import TopologyError

__all__ = ["EquationsOfMotion", "derive", "Symbols"]

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


@dataclass(frozen=True)
class EquationsOfMotion:
    """The derived equations ``M(q, t) q'' = f(q, q', t)`` of one model structure.

    Parameters stay symbols: numbers go in at compile/run time.

    Attributes
    ----------
    t : sympy.Symbol
    coordinates, speeds : tuple of sympy.Symbol
        q and q' (``x2``, ``x2_dot``, ...).
    parameters : tuple of sympy.Symbol
        In the model's parameter order.
    mass_matrix : sympy.ImmutableMatrix
        M(q, t), n x n, symmetric positive definite.
    forcing : sympy.ImmutableMatrix
        f(q, q', t) = F - C q' - K q, n x 1 (everything but M q'').
    stiffness, damping : sympy.ImmutableMatrix
        K and C of the linear part (Hessians of V and D at q = 0).
    forces : dict
        Element label -> n x 1 matrix of that element's generalised force
        apart from K q and C q' (contact, bearing, manoeuvre, unbalance);
        F is their sum.
    latex_names : dict
        Symbol -> LaTeX name used for rendering.
    kinetic, potential, dissipation : sympy.Expr
        The model's total T(q, q', t), V(q, t) and Rayleigh D(q') (for
        energy balances: the Jacobi integral ``h = q' dT/dq' - T + V``
        changes at the rate ``-dL/dt - 2 D + Q . q'``).
    loads : sympy.ImmutableMatrix
        Sum of the elements' generalised loads Q (n x 1).
    switches : tuple
        (element label, expression) pairs whose zero crossings are kinks of
        the equations (contact onset and loss).
    """

    t: sp.Symbol
    coordinates: tuple
    speeds: tuple
    parameters: tuple
    mass_matrix: sp.ImmutableMatrix
    forcing: sp.ImmutableMatrix
    stiffness: sp.ImmutableMatrix
    damping: sp.ImmutableMatrix
    forces: dict = field(default_factory=dict)
    latex_names: dict = field(default_factory=dict)
    kinetic: sp.Expr = sp.S.Zero
    potential: sp.Expr = sp.S.Zero
    dissipation: sp.Expr = sp.S.Zero
    loads: sp.ImmutableMatrix = None
    switches: tuple = ()

    @property
    def n(self):
        """Number of coordinates."""
        return len(self.coordinates)

    def linear_mass_matrix(self):
        """The constant part of M (entries free of q and t), as printed in papers."""
        dynamic = set(self.coordinates) | {self.t}

        def constant_part(expr):
            return sp.Add(*[a for a in sp.Add.make_args(sp.expand(expr)) if not a.free_symbols & dynamic])

        return self.mass_matrix.applyfunc(constant_part)

    def nonlinear_forces(self):
        """Element label -> its generalised force vector (beyond K q and C q')."""
        return dict(self.forces)

    def nonlinear_forcing(self):
        """F = f + C q' + K q: the sum of :attr:`forces` (n x 1)."""
        F = sp.zeros(self.n, 1)
        for vec in self.forces.values():
            F += vec
        return sp.ImmutableMatrix(F)

    def free_parameters(self):
        """Parameters that appear in the equations."""
        used = self.mass_matrix.free_symbols | self.forcing.free_symbols
        return tuple(p for p in self.parameters if p in used)

    def latex(self):
        """LaTeX of ``M q'' + C q' + K q = F`` with the pieces defined below it."""
        names = self.latex_names
        lx = lambda e: sp.latex(e, symbol_names=names)  # noqa: E731
        q = sp.Matrix(self.coordinates)
        lines = [
            r"\mathbf{M}(\mathbf{q},t)\,\ddot{\mathbf{q}} + \mathbf{C}\,\dot{\mathbf{q}} + "
            r"\mathbf{K}\,\mathbf{q} = \mathbf{F}(\mathbf{q},\dot{\mathbf{q}},t)",
            r"\mathbf{q} = " + lx(q.T) + "^T",
            r"\mathbf{M} = " + lx(self.mass_matrix),
            r"\mathbf{C} = " + lx(self.damping),
            r"\mathbf{K} = " + lx(self.stiffness),
        ]
        for label, vec in self.forces.items():
            nz = [(self.coordinates[i], v) for i, v in enumerate(vec) if v != 0]
            for coord, v in nz:
                lines.append(r"F^{\mathrm{%s}}_{%s} = %s" % (label.replace("_", r"\_"), lx(coord), lx(v)))
        return "\\begin{gathered}\n" + " \\\\\n".join(lines) + "\n\\end{gathered}"

    def _repr_latex_(self):
        return "$$" + self.latex() + "$$"

    def __str__(self):
        q = [str(c) for c in self.coordinates]
        out = [f"Equations of motion, {self.n} coordinates: M(q, t) q'' + C q' + K q = F(q, q', t)",
               f"q = [{', '.join(q)}]"]
        for title, mat in (("M", self.mass_matrix), ("C", self.damping), ("K", self.stiffness)):
            out.append(f"\n{title} (nonzero entries, symmetric: upper triangle):")
            for i in range(self.n):
                for j in range(i, self.n):
                    if mat[i, j] != 0:
                        out.append(f"  {title}[{q[i]}, {q[j]}] = {mat[i, j]}")
        for label, vec in self.forces.items():
            out.append(f"\nF from {label}:")
            for i, v in enumerate(vec):
                if v != 0:
                    out.append(f"  F[{q[i]}] = {v}")
        return "\n".join(out)


def _element_contribution(terms, index, qs, us, t):
    """Sparse (M, f_inertia_and_loads, f_elastic) of one element's terms."""
    mass = {}
    force = defaultdict(lambda: sp.S.Zero)  # inertial remainder and loads
    elastic = defaultdict(lambda: sp.S.Zero)  # -dV/dq - dD/dq'
    T = sp.sympify(terms.kinetic)
    if T != 0:
        fs = T.free_symbols
        u_in = [i for i, u in enumerate(us) if u in fs]
        for i in u_in:
            p = sp.diff(T, us[i])
            pfs = p.free_symbols
            for j in u_in:
                if j >= i and us[j] in pfs:
                    mij = sp.trigsimp(sp.expand(sp.diff(p, us[j])))
                    if mij != 0:
                        mass[(i, j)] = mij
            rest = sp.diff(p, t) + sum((sp.diff(p, qs[k]) * us[k] for k in range(len(qs)) if qs[k] in pfs), sp.S.Zero)
            force[i] -= rest
        for i, q in enumerate(qs):
            if q in fs:
                force[i] += sp.diff(T, q)
        for i in list(force):
            force[i] = sp.trigsimp(sp.expand(force[i]))
    V, D = sp.sympify(terms.potential), sp.sympify(terms.dissipation)
    for i, q in enumerate(qs):
        if V != 0 and q in V.free_symbols:
            elastic[i] -= sp.diff(V, q)
        if D != 0 and us[i] in D.free_symbols:
            elastic[i] -= sp.diff(D, us[i])
    for q, load in terms.loads.items():
        force[index[q]] += load
    return mass, force, elastic


def _hessian(expr, variables, n, zero):
    """Constant Hessian of a (quadratic) scalar, as an n x n matrix."""
    H = sp.zeros(n, n)
    expr = sp.sympify(expr)
    if expr == 0:
        return H
    present = [(i, v) for i, v in enumerate(variables) if v in expr.free_symbols]
    for i, vi in present:
        di = sp.diff(expr, vi)
        for j, vj in present:
            if vj in di.free_symbols:
                H[i, j] = sp.diff(di, vj).subs(zero)
    return H


def derive(model):
    """Derive the equations of motion of ``model`` (cached per structure).

    Returns
    -------
    EquationsOfMotion
    """
    key = model.structure_key
    if key in _CACHE:
        return _CACHE[key]
    from ..model import Context

    symbols = Symbols(model)
    qs = tuple(symbols.coordinates.values())
    us = tuple(symbols.speeds.values())
    t = symbols.t
    n = len(qs)
    index = {q: i for i, q in enumerate(qs)}
    zero = {s: 0 for s in qs + us}
    ctx = Context(model, symbols)
    M = sp.zeros(n, n)
    K = sp.zeros(n, n)
    C = sp.zeros(n, n)
    F = sp.zeros(n, 1)
    forces = {}
    q_vec, u_vec = sp.Matrix(qs), sp.Matrix(us)
    totals = {"kinetic": sp.S.Zero, "potential": sp.S.Zero, "dissipation": sp.S.Zero}
    loads = sp.zeros(n, 1)
    switches = []
    for element in model.elements:
        terms = element.contribute(ctx.bind(element))
        switches += [(element.label(), sp.sympify(g)) for g in terms.switches]
        for name in totals:
            totals[name] += sp.sympify(getattr(terms, name))
        for q, load in terms.loads.items():
            loads[index[q]] += load
        mass, force, elastic = _element_contribution(terms, index, qs, us, t)
        for (i, j), mij in mass.items():
            M[i, j] += mij
            if i != j:
                M[j, i] += mij
        Ke = _hessian(terms.potential, qs, n, zero)
        Ce = _hessian(terms.dissipation, us, n, zero)
        K += Ke
        C += Ce
        if elastic:  # whatever of -dV/dq - dD/dq' is not -K q - C q' (none for quadratic V, D)
            linear = -(Ke * q_vec + Ce * u_vec)
            for i, v in elastic.items():
                rest = sp.expand(v - linear[i])
                if rest != 0:
                    force[i] += rest
        vec = sp.zeros(n, 1)
        for i, v in force.items():
            vec[i] = v
        if any(v != 0 for v in vec):
            forces[element.label()] = sp.ImmutableMatrix(vec)
            F += vec
    f = F - K * q_vec - C * u_vec
    eom = EquationsOfMotion(
        t=t,
        coordinates=qs,
        speeds=us,
        parameters=tuple(symbols.parameters.values()),
        mass_matrix=sp.ImmutableMatrix(M),
        forcing=sp.ImmutableMatrix(f),
        stiffness=sp.ImmutableMatrix(K),
        damping=sp.ImmutableMatrix(C),
        forces=forces,
        latex_names=_latex_names(model, symbols),
        loads=sp.ImmutableMatrix(loads),
        switches=tuple(switches),
        **totals,
    )
    _CACHE[key] = eom
    return eom


def _latex_names(model, symbols):
    names = {}
    bases = {"alpha": r"\alpha", "thx": r"\theta_{x}", "thy": r"\theta_{y}"}
    for (station, axis), (n, q) in zip(model.coordinates, symbols.coordinates.items()):
        base = bases.get(axis, axis)
        names[q] = f"{base}_{{{station}}}"
        names[symbols.speeds[n]] = rf"\dot{{{base}}}_{{{station}}}"
    for e in model.elements:
        for f in e.parameters():
            base = e._latex_names.get(f, f.replace("_", r"\_"))
            names[symbols.parameters[f"{e.label()}_{f}"]] = f"{base}^{{\\mathrm{{{e.label()}}}}}"
    return names
