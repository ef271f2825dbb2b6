"""The derived equations of motion ``M(q, t) q'' = f(q, q', t)`` of one model structure, as data.

:class:`EquationsOfMotion` holds the matrices and terms that
:func:`rotorkit.symbolic.lagrange.derive` assembles (parameters stay
symbols), with their text and LaTeX forms; :func:`sparse_matrix` builds the
immutable sparse matrices it holds.
"""

from collections import defaultdict
from dataclasses import dataclass, field

import sympy as sp

__all__ = ["EquationsOfMotion", "sparse_matrix", "immutable_sparse_matrix", "MAX_DISPLAYED_COORDINATES",
           "MAX_PRINTED_LINES"]


#: a model with more coordinates shows a summary in a notebook instead of its LaTeX
MAX_DISPLAYED_COORDINATES = 40
#: lines ``str(equations)`` prints at most
MAX_PRINTED_LINES = 400


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
    mass_matrix : sympy.ImmutableSparseMatrix
        M(q, t), n x n, symmetric positive definite (sparse, like K, C,
        loads and the force vectors: a large model stores only its
        non-zero entries).
    forcing : sympy.ImmutableMatrix
        f(q, q', t) = F - C q' - K q, n x 1 (everything but M q'').
    stiffness, damping : sympy.ImmutableSparseMatrix
        K and C of the linear part (Hessians of V and D at q = 0).
    forces : dict
        Element label -> n x 1 sparse matrix of that element's generalised force
        apart from K q and C q' (contact, bearing, manoeuvre, unbalance);
        F is their sum.
    latex_names : dict
        Symbol -> LaTeX name used for rendering.
    kinetic, potential, dissipation : sympy.Expr
        The model's total T(q, q', t), V(q, t) and Rayleigh D(q') (for
        energy balances: the Jacobi integral ``h = q' dT/dq' - T + V``
        changes at the rate ``-dL/dt - 2 D + Q . q'``).
    loads : sympy.ImmutableSparseMatrix
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
        terms = defaultdict(list)
        for vec in self.forces.values():
            for (i, _), v in vec.todok().items():
                terms[i].append(v)
        return sparse_matrix(self.n, 1, {(i, 0): v for i, v in terms.items()})

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
        if self.n > MAX_DISPLAYED_COORDINATES:  # a notebook shows the summary (repr) instead of pages of LaTeX
            return None
        return "$$" + self.latex() + "$$"

    def __repr__(self):
        """A one-line summary, whatever the size (``str()`` lists the entries, :meth:`latex` renders them)."""
        return (f"<EquationsOfMotion: {self.n} coordinates, {len(self.parameters)} parameters, "
                f"{len(self.mass_matrix.todok())} non-zero mass entries, "
                f"forces from {len(self.forces)} elements>")

    def __str__(self):
        q = [str(c) for c in self.coordinates]
        out = [f"Equations of motion, {self.n} coordinates: M(q, t) q'' + C q' + K q = F(q, q', t)",
               f"q = [{', '.join(q) if len(q) <= 12 else ', '.join(q[:6]) + ', ..., ' + q[-1]}]"]
        for title, mat in (("M", self.mass_matrix), ("C", self.damping), ("K", self.stiffness)):
            out.append(f"\n{title} (nonzero entries, symmetric: upper triangle):")
            for (i, j), v in sorted(mat.todok().items()):
                if j >= i and v != 0:
                    out.append(f"  {title}[{q[i]}, {q[j]}] = {v}")
        for label, vec in self.forces.items():
            out.append(f"\nF from {label}:")
            for i, v in enumerate(vec):
                if v != 0:
                    out.append(f"  F[{q[i]}] = {v}")
        if len(out) > MAX_PRINTED_LINES:  # a model of thousands of coordinates: the start and a count
            rest = len(out) - MAX_PRINTED_LINES
            out = out[:MAX_PRINTED_LINES] + [f"... {rest} more entries (the matrices are mass_matrix, damping, "
                                             "stiffness and forces)"]
        return "\n".join(out)


def sparse_matrix(n, m, entries):
    """An immutable sparse n x m sympy matrix from ``{(i, j): [terms]}`` (no cost per zero entry)."""
    values = {key: sp.Add(*terms) for key, terms in entries.items()}
    return immutable_sparse_matrix(n, m, {key: v for key, v in values.items() if v != 0})


def immutable_sparse_matrix(n, m, values):
    """``ImmutableSparseMatrix(n, m, values)`` without sorting the entries by their expressions.

    sympy's constructor builds a ``Dict`` whose items it puts in canonical
    order with ``ordered``, which compares the entries' expressions: for a
    beam rotor's matrices that was about a third of the derivation. Here the
    items are ordered by their (row, column) keys, which is canonical too
    (keys are unique); the matrix is the same (``==``, entries, ``todok``).
    """
    from sympy.core.basic import Basic

    rep = sp.SparseMatrix(n, m, values)._rep
    items = [sp.Tuple(sp.Tuple(*key), v) for key, v in sorted(rep.to_sympy().to_dok().items(), key=lambda kv: kv[0])]
    content = Basic.__new__(sp.Dict, *items)
    content.elements = frozenset(items)
    content._dict = dict(items)
    obj = Basic.__new__(sp.ImmutableSparseMatrix, sp.Integer(n), sp.Integer(m), content)
    obj._rows, obj._cols, obj._rep = n, m, rep
    return obj
