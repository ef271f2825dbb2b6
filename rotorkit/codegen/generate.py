"""Generate the source of a right-hand side (and its Jacobian) from :class:`EquationsOfMotion`.

The generated module holds plain-Python functions that numba can also
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
    so a step ending exactly on a jump still sees its own side of it.
``switches(t, y, p, out)``
    The elements' switch functions (contact onset/loss: zero crossings are
    kinks of the equations), for event location.
``jac(t, y, p, J)``
    The analytic Jacobian ``d(dydt)/dy`` into the zero-filled ``J``
    (2n x 2n): ``dq''/dy_k = M^-1 (df/dy_k - dM/dy_k q'')``, every column
    solved with the same factorisation of M.

Two ways to write these functions, chosen by :func:`codegen_mode`:

*unrolled* (this module; models below :data:`STRUCTURED_FROM` coordinates,
such as the AL-31F preset): every equation is scalar code.
``M(q, t) q'' = f`` is solved numerically block by block: the mass matrix
splits into independent blocks (a 3x3 block per eccentric disk with
torsion, 1x1 elsewhere); each block is factorised by unrolled Gaussian
elimination without pivoting, which is stable because M is symmetric
positive definite. No symbolic inverse is ever formed; parameter-only
pivots are divided by through reciprocals computed in ``prepare()`` (a
division's latency lies on the integrator's critical path), and
``sin(2a)``, ``cos(2a)`` beside ``sin(a)``, ``cos(a)`` take the
double-angle formulas (:func:`double_angles`). As fast as
hand-written code for lumped models, but its size (and numba's compile
time) grows with the square of a beam rotor's banded mass matrix.

*structured* (:mod:`rotorkit.codegen.structured`; larger models): the
linear part as sparse matrices and ``M0^-1`` evaluated in ``prepare()``,
only the local nonlinear terms as scalar code. Both give the same numbers
to rounding (``tests/test_structured.py``).
"""

import sympy as sp

from . import CODEGEN_MODES, STRUCTURED_FROM, codegen_mode  # noqa: F401 - importable from here as before
from .emit import BlockFactor, GeneratedCode, function_prelude, hoist, module_header, name_power_bases
from .printer import EXTRA_MATH_FUNCTIONS, MATH_FUNCTIONS, RhsPrinter

__all__ = ["GeneratedCode", "generate", "mass_blocks", "codegen_mode", "STRUCTURED_FROM"]


def mass_blocks(M):
    """Index blocks of the structurally independent parts of a symmetric matrix."""
    n = M.shape[0]
    parent = list(range(n))

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for (i, j), v in M.todok().items():  # the non-zero entries only: O(entries), not O(n^2)
        if i < j and v != 0:
            parent[find(i)] = find(j)
    groups = {}
    for i in range(n):
        groups.setdefault(find(i), []).append(i)
    return tuple(sorted((_banded_order(M, g) for g in groups.values()), key=min))


def _banded_order(M, group):
    """Elimination order of a block: index order for small blocks, reverse Cuthill-McKee for large ones.

    A beam rotor's mass matrix is one large banded block; in coordinate order
    (all x, then all tilts) its unrolled factorisation would fill in
    densely, in RCM order it stays within the band.
    """
    if len(group) <= 3:
        return tuple(group)
    import numpy as np
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    pattern = np.array([[M[a, b] != 0 for b in group] for a in group], dtype=np.int8)
    order = reverse_cuthill_mckee(csr_matrix(pattern), symmetric_mode=True)
    return tuple(group[k] for k in order)


def double_angles(exprs):
    """``sin(2a)``, ``cos(2a)`` written through ``sin(a)``, ``cos(a)`` where that saves calls.

    A manoeuvre's roll puts ``sin(θ)``, ``cos(θ)``, ``sin(2θ)`` and
    ``cos(2θ)`` in one equation: four calls of the maths library, each worth
    about ten multiplications, where two and the double-angle formulas do.
    Rewritten only where at least three of the four occur, so the number of
    calls always drops.
    """
    trig = set()
    for e in exprs:
        trig |= e.atoms(sp.sin, sp.cos)
    args = {a.args[0] for a in trig}
    rewrite = {}
    for a in args:
        half = a / 2
        if half not in args:
            continue
        present = {sp.sin(a), sp.cos(a), sp.sin(half), sp.cos(half)} & trig
        if len(present) >= 3:
            s, c = sp.sin(half), sp.cos(half)
            rewrite[sp.sin(a)] = 2 * s * c
            rewrite[sp.cos(a)] = c * c - s * s
    if not rewrite:
        return list(exprs)
    return [e.xreplace(rewrite) for e in exprs]


def _kept_pivots(blocks, keys):
    """The diagonal mass entries that the unrolled elimination divides by as they are (not updated first)."""
    names = {key: f"m{key[0]}_{key[1]}" for key in keys}
    kept = []
    for block in blocks:
        upper = BlockFactor(block, names).upper
        kept += [(b, b) for k, b in enumerate(block) if (b, b) in names and upper[k][k] == names[(b, b)]]
    return kept


def import_extra_math(source):
    """``source`` with a second ``from math import ...`` line for the :data:`EXTRA_MATH_FUNCTIONS` it calls.

    Only modules that call one (a user's speed expression with ``floor`` or
    ``erf``) get the line: the others stay byte for byte as they were.
    """
    import re

    used = [name for name in EXTRA_MATH_FUNCTIONS if re.search(rf"\b{name}\(", source)]
    if not used:
        return source
    first = f"from math import {', '.join(MATH_FUNCTIONS)}"
    return source.replace(first, f"{first}\nfrom math import {', '.join(used)}", 1)


def generate(eom, structure_key="", jacobian=True, mode="auto"):
    """Generate the module source for ``eom``.

    Parameters
    ----------
    eom : EquationsOfMotion
    structure_key : str
        Recorded in the module header.
    jacobian : bool
        Also generate ``jac(t, y, p, J)``.
    mode : {"auto", "unrolled", "structured"}
        ``unrolled``: every equation as scalar code (this module);
        ``structured``: matrices for the linear part, scalar code for the
        local terms (:mod:`rotorkit.codegen.structured`); ``auto``: by size,
        see :func:`codegen_mode`.

    Returns
    -------
    GeneratedCode
    """
    if codegen_mode(eom.n, mode) == "structured":
        import dataclasses

        from .structured import generate_structured

        code = generate_structured(eom, structure_key, jacobian)
        return dataclasses.replace(code, source=import_extra_math(code.source))
    n = eom.n
    params = eom.parameters
    param_set = set(params)
    M = eom.mass_matrix
    F, K, C = eom.nonlinear_forcing(), eom.stiffness, eom.damping
    q, u = eom.coordinates, eom.speeds
    K_rows, C_rows = [[] for _ in range(n)], [[] for _ in range(n)]
    for rows, mat, x in ((K_rows, K, q), (C_rows, C, u)):
        for (i, j), v in sorted(mat.todok().items()):
            if v != 0:
                rows[i].append(v * x[j])
    f = [F[i] - sum(K_rows[i], sp.S.Zero) - sum(C_rows[i], sp.S.Zero) for i in range(n)]
    blocks = mass_blocks(M)
    mass_keys = [(a, b) for block in blocks for a in block for b in block if a <= b and M[a, b] != 0]

    # Jacobian pieces: df_i/dy_k and dM_ij/dy_k (only entries that depend on y)
    states = list(q) + list(u)
    df, dM = {}, {}
    if jacobian:
        for i in range(n):
            for k in sorted(f[i].free_symbols & set(states), key=states.index):
                df[(i, states.index(k))] = sp.diff(f[i], k)
        for (a, b) in mass_keys:
            for k in sorted(M[a, b].free_symbols & set(states), key=states.index):
                dM[(a, b, states.index(k))] = sp.diff(M[a, b], k)

    switch_exprs_raw = [g for _, g in eom.switches]
    table = {}
    exprs = ([M[key] for key in mass_keys] + f + list(df.values()) + list(dM.values()) + switch_exprs_raw)
    exprs = [hoist(e, param_set, table) for e in double_angles(exprs)]
    # 1/m of every parameter-only diagonal mass entry, among the prepared values: a multiplication per use
    reciprocals = {(a, b): hoist(1 / M[a, b], param_set, table) for (a, b) in _kept_pivots(blocks, mass_keys)
                   if M[a, b].free_symbols <= param_set}
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("_c"), order="none")
    replacements, reduced = name_power_bases(replacements, reduced)
    it = iter(reduced)
    mass_exprs = [next(it) for _ in mass_keys]
    f_exprs = [next(it) for _ in range(n)]
    df_exprs = [next(it) for _ in df]
    dM_exprs = [next(it) for _ in dM]
    switch_exprs = [next(it) for _ in switch_exprs_raw]

    names = {eom.t: "t"}
    for i, (qi, ui) in enumerate(zip(q, u)):
        names[qi], names[ui] = f"q{i}", f"u{i}"
    for k, p in enumerate(params):
        names[p] = f"p{k}"
    derived = list(table.items())  # (expression, symbol)
    for k, (_, sym) in enumerate(derived):
        names[sym] = f"k{k}"
    printer = RhsPrinter(names)
    n_params = len(params)
    n_prepared = n_params + len(derived)

    # prepare(): derived parameter expressions, computed once per parameter set
    prep = ["def prepare(p, out):", f"    for i in range({n_params}):", "        out[i] = p[i]"]
    for k in range(n_params):
        prep.append(f"    p{k} = p[{k}]")
    prep_repl, prep_exprs = sp.cse([e for e, _ in derived], symbols=sp.numbered_symbols("_d"), order="none")
    for sym, e in prep_repl:
        prep.append(f"    {printer.doprint(sym)} = {printer.doprint(e)}")
    for k, e in enumerate(prep_exprs):
        prep.append(f"    out[{n_params + k}] = {printer.doprint(e)}")
    prep.append(f"    out[{n_prepared}] = -1e300  # time window of the equations, see rhs()")
    prep.append(f"    out[{n_prepared + 1}] = 1e300")
    prep.append("    return out")

    def prelude(name, out_arg, needed):
        return function_prelude(name, out_arg, needed, doprint=printer.doprint, replacements=replacements, q=q,
                                u=u, params=params, derived=derived, n_prepared=n_prepared,
                                all_speeds=name == "rhs")

    def mass_and_solve(out_acc):
        lines, mass_name, factors, acc = [], {}, {}, {}
        for key, e in zip(mass_keys, mass_exprs):
            name = f"m{key[0]}_{key[1]}"
            lines.append(f"    {name} = {printer.doprint(e)}")
            mass_name[key] = name
        reciprocal = {mass_name[key]: printer.doprint(r) for key, r in reciprocals.items()}
        for i, e in enumerate(f_exprs):
            lines.append(f"    f{i} = {printer.doprint(e)}")
        for block in blocks:
            factor = BlockFactor(block, mass_name, reciprocal)
            factors[block] = factor
            lines += factor.lines
            solve_lines, x = factor.solve([f"f{i}" for i in block], out_acc, "a")
            lines += solve_lines
            acc.update(zip(block, x))
        return lines, factors, acc

    # rhs(): the per-evaluation work
    body = prelude("rhs", "dydt", mass_exprs + f_exprs + list(reciprocals.values()))
    body += [f"    dydt[{i}] = u{i}" for i in range(n)]
    lines, _, _ = mass_and_solve(lambda i, name: f"    dydt[{n + i}] = {name}")
    body += lines

    jac = []
    if jacobian:
        jac = prelude("jac", "J", mass_exprs + f_exprs + df_exprs + dM_exprs + list(reciprocals.values()))
        jac += [f"    J[{i}, {n + i}] = 1.0" for i in range(n)]
        lines, factors, acc = mass_and_solve(lambda i, name: f"    a{i} = {name}")
        jac += lines
        columns = {}
        for (i, k), e in zip(df, df_exprs):
            columns.setdefault(k, {})[i] = [printer.doprint(e)]
        for (a, b, k), e in zip(dM, dM_exprs):  # - dM/dy_k q'' (M symmetric)
            dm = printer.doprint(e)
            col = columns.setdefault(k, {})
            col.setdefault(a, []).append(f"-({dm})*a{b}")
            if a != b:
                col.setdefault(b, []).append(f"-({dm})*a{a}")
        for k in sorted(columns):
            col = columns[k]
            for i, terms in col.items():
                jac.append(f"    r{i} = " + " + ".join(f"({t})" for t in terms))
            for block, factor in factors.items():
                rhs_names = [f"r{i}" if i in col else None for i in block]
                if all(r is None for r in rhs_names):
                    continue
                solve_lines, _ = factor.solve(rhs_names, lambda i, name, k=k: f"    J[{n + i}, {k}] = {name}", f"j{k}")
                jac += solve_lines

    sw = prelude("switches", "out", switch_exprs)
    sw += [f"    out[{i}] = {printer.doprint(e)}" for i, e in enumerate(switch_exprs)]
    if not switch_exprs:
        sw.append("    pass")

    header = module_header(structure_key, "unrolled", eom, q=q, u=u, params=params, derived=derived,
                           n_prepared=n_prepared, jacobian=jacobian, n_switches=len(switch_exprs)) + [""]
    source = import_extra_math("\n".join(header + prep + [""] + body + [""] + jac + [""] + sw + [""]))
    return GeneratedCode(source=source, n_coordinates=n, n_parameters=n_params, n_derived=len(derived), blocks=blocks)
