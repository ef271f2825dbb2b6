"""Generate the source of a right-hand side from :class:`EquationsOfMotion`.

The generated module holds two plain-Python functions that numba can also
compile unchanged:

``prepare(p, out)``
    Copies the parameter vector ``p`` into ``out`` and appends every
    parameter-only subexpression (``12 E I / l^3``, ``J + m e^2``, ...), so
    they are computed once per parameter set, not at every evaluation.
``rhs(t, y, p, dydt)``
    ``y = [q, q']``; writes ``dydt = [q', q'']`` with ``p`` the prepared
    vector. Its last two entries bound the time the equations see
    (``t`` is clamped to ``[p[-2], p[-1]]``): an integrator working on one
    segment between time discontinuities sets them just inside the segment,
    so a step ending exactly on a jump still sees its own side of it. ``M(q, t) q'' = f`` is solved numerically block by block: the
    mass matrix splits into independent blocks (a 3x3 block per eccentric
    disk with torsion, 1x1 elsewhere); each block is solved by unrolled
    Gaussian elimination without pivoting, which is stable because M is
    symmetric positive definite. No symbolic inverse is ever formed.
"""

from dataclasses import dataclass

import sympy as sp

from .printer import MATH_FUNCTIONS, RhsPrinter

__all__ = ["GeneratedCode", "generate", "mass_blocks"]


@dataclass(frozen=True)
class GeneratedCode:
    """Source text and layout of a generated RHS module."""

    source: str
    n_coordinates: int
    n_parameters: int
    n_derived: int
    blocks: tuple


def mass_blocks(M):
    """Index blocks of the structurally independent parts of a symmetric matrix."""
    n = M.shape[0]
    parent = list(range(n))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for i in range(n):
        for j in range(i + 1, n):
            if M[i, j] != 0:
                parent[find(i)] = find(j)
    groups = {}
    for i in range(n):
        groups.setdefault(find(i), []).append(i)
    return tuple(sorted(tuple(g) for g in groups.values()))


def _hoist(expr, params, table):
    """Replace parameter-only subexpressions of ``expr`` by symbols kept in ``table``."""
    if expr.is_Atom:
        return expr
    if expr.free_symbols and expr.free_symbols <= params:
        if expr not in table:
            table[expr] = sp.Symbol(f"_k{len(table)}", real=True)
        return table[expr]
    if expr.is_Mul or expr.is_Add:
        fixed = [a for a in expr.args if a.free_symbols <= params]
        moving = [_hoist(a, params, table) for a in expr.args if not a.free_symbols <= params]
        fixed_part = expr.func(*fixed) if fixed else None
        if fixed_part is not None and not fixed_part.is_Atom:
            fixed_part = _hoist(fixed_part, params, table)
        args = moving + ([fixed_part] if fixed_part is not None else [])
        return expr.func(*args, evaluate=False) if len(args) > 1 else args[0]
    return expr.func(*[_hoist(a, params, table) for a in expr.args])


def _name_power_bases(replacements, reduced):
    """Give the base of every ``b**(3/2)``-like power a name, so it prints as ``b*sqrt(b)``."""
    counter = iter(range(10**9))
    out = []

    def split(expr):
        extra = []

        def name_base(power):
            sym = sp.Symbol(f"_b{next(counter)}", real=True)
            extra.append((sym, power.base))
            return sp.Pow(sym, power.exp, evaluate=False)

        new = expr.replace(
            lambda e: e.is_Pow and e.exp.is_Rational and e.exp.q == 2 and e.exp > 1 and not e.base.is_Symbol,
            name_base,
        )
        return extra, new

    for sym, e in replacements:
        extra, new = split(e)
        out.extend(extra)
        out.append((sym, new))
    new_reduced = []
    for e in reduced:
        extra, new = split(e)
        out.extend(extra)
        new_reduced.append(new)
    return out, new_reduced


def _solve_block(block, mass_name, rhs_name, n):
    """Lines that solve one SPD block by unrolled elimination; writes dydt[n + i]."""
    size = len(block)
    if size == 1:
        i = block[0]
        return [f"    dydt[{n + i}] = {rhs_name[i]} / {mass_name[(i, i)]}"]
    A = [[mass_name.get((min(block[r], block[c]), max(block[r], block[c]))) for c in range(size)] for r in range(size)]
    b = [rhs_name[i] for i in block]
    lines, counter = [], [0]

    def fresh():
        counter[0] += 1
        return f"_e{block[0]}_{counter[0]}"

    for k in range(size):
        for r in range(k + 1, size):
            if A[r][k] is None:
                continue
            factor = fresh()
            lines.append(f"    {factor} = {A[r][k]} / {A[k][k]}")
            for c in range(k + 1, size):
                if A[k][c] is None:
                    continue
                new = fresh()
                lines.append(f"    {new} = " + (f"{A[r][c]} - " if A[r][c] is not None else "-") + f"{factor}*{A[k][c]}")
                A[r][c] = new
            new = fresh()
            lines.append(f"    {new} = {b[r]} - {factor}*{b[k]}")
            b[r] = new
    x = [None] * size
    for k in reversed(range(size)):
        terms = [f" - {A[k][c]}*{x[c]}" for c in range(k + 1, size) if A[k][c] is not None]
        x[k] = fresh()
        lines.append(f"    {x[k]} = ({b[k]}{''.join(terms)}) / {A[k][k]}")
        lines.append(f"    dydt[{n + block[k]}] = {x[k]}")
    return lines


def generate(eom, structure_key=""):
    """Generate the RHS module source for ``eom``.

    Parameters
    ----------
    eom : EquationsOfMotion
    structure_key : str
        Recorded in the module header.

    Returns
    -------
    GeneratedCode
    """
    n = eom.n
    params = eom.parameters
    param_set = set(params)
    M = eom.mass_matrix
    F, K, C = eom.nonlinear_forcing(), eom.stiffness, eom.damping
    f = [F[i] - sum((K[i, j] * eom.coordinates[j] for j in range(n) if K[i, j] != 0), sp.S.Zero)
         - sum((C[i, j] * eom.speeds[j] for j in range(n) if C[i, j] != 0), sp.S.Zero) for i in range(n)]
    blocks = mass_blocks(M)

    table = {}
    mass_entries = {}
    for block in blocks:
        for a in block:
            for b in block:
                if a <= b and M[a, b] != 0:
                    mass_entries[(a, b)] = _hoist(M[a, b], param_set, table)
    forcing = [_hoist(f[i], param_set, table) for i in range(n)]

    keys = list(mass_entries)
    exprs = [mass_entries[k] for k in keys] + forcing
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("_c"), order="none")
    replacements, reduced = _name_power_bases(replacements, reduced)

    names = {eom.t: "t"}
    for i, (q, u) in enumerate(zip(eom.coordinates, eom.speeds)):
        names[q], names[u] = f"q{i}", f"u{i}"
    for k, p in enumerate(params):
        names[p] = f"p{k}"
    derived = list(table.items())  # (expression, symbol)
    for k, (_, sym) in enumerate(derived):
        names[sym] = f"k{k}"
    printer = RhsPrinter(names)

    # prepare(): derived parameter expressions, computed once per parameter set
    n_params = len(params)
    prep = [f"def prepare(p, out):", f"    for i in range({n_params}):", "        out[i] = p[i]"]
    for k, p in enumerate(params):
        prep.append(f"    p{k} = p[{k}]")
    prep_repl, prep_exprs = sp.cse([e for e, _ in derived], symbols=sp.numbered_symbols("_d"), order="none")
    for sym, e in prep_repl:
        prep.append(f"    {printer.doprint(sym)} = {printer.doprint(e)}")
    for k, e in enumerate(prep_exprs):
        prep.append(f"    out[{n_params + k}] = {printer.doprint(e)}")
    n_prepared = n_params + len(derived)
    prep.append(f"    out[{n_prepared}] = -1e300  # time window of the equations, see rhs()")
    prep.append(f"    out[{n_prepared + 1}] = 1e300")

    # rhs(): the per-evaluation work
    used = set().union(*(e.free_symbols for e in reduced), *(e.free_symbols for _, e in replacements)) if exprs else set()
    body = ["def rhs(t, y, p, dydt):", f"    t = min(max(t, p[{n_prepared}]), p[{n_prepared + 1}])"]
    for i, (q, u) in enumerate(zip(eom.coordinates, eom.speeds)):
        body.append(f"    u{i} = y[{n + i}]")
        body.append(f"    dydt[{i}] = u{i}")
        if q in used:
            body.append(f"    q{i} = y[{i}]")
    for k, p in enumerate(params):
        if p in used:
            body.append(f"    p{k} = p[{k}]")
    for k, (_, sym) in enumerate(derived):
        if sym in used:
            body.append(f"    k{k} = p[{n_params + k}]")
    for sym, e in replacements:
        body.append(f"    {printer.doprint(sym)} = {printer.doprint(e)}")
    mass_name, rhs_name = {}, {}
    for key, e in zip(keys, reduced[: len(keys)]):
        name = f"m{key[0]}_{key[1]}"
        body.append(f"    {name} = {printer.doprint(e)}")
        mass_name[key] = name
    for i, e in enumerate(reduced[len(keys):]):
        body.append(f"    f{i} = {printer.doprint(e)}")
        rhs_name[i] = f"f{i}"
    for block in blocks:
        body.extend(_solve_block(block, mass_name, rhs_name, n))

    header = [
        f'"""Right-hand side generated by rotorkit (structure {structure_key}). Do not edit."""',
        f"from math import {', '.join(MATH_FUNCTIONS)}",
        "",
        f"N_COORDINATES = {n}",
        f"N_PARAMETERS = {n_params}",
        f"N_DERIVED = {len(derived)}",
        f"N_PREPARED = {len(derived) + n_params + 2}",
        f"STATE_NAMES = {tuple([str(q) for q in eom.coordinates] + [str(u) for u in eom.speeds])!r}",
        f"PARAMETER_NAMES = {tuple(str(p) for p in params)!r}",
        f"DERIVED_PARAMETERS = {tuple(tuple(sorted(str(s) for s in e.free_symbols)) for e, _ in derived)!r}",
        "",
    ]
    source = "\n".join(header + prep + ["    return out", ""] + body + [""])
    return GeneratedCode(source=source, n_coordinates=n, n_parameters=n_params, n_derived=len(derived), blocks=blocks)
