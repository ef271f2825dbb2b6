"""The generated module of a reduced system: local scalar code on physical boundary coordinates, dense reduced matrices.

The reduced state is ``z = [q_B, q_K, eta, q_B', q_K', eta']``: the natural
boundary ``B`` (every coordinate on which a local term acts or depends, see
:func:`natural_boundary`), the coordinates the user keeps physical ``K``,
then the interior's generalised coordinates. The generated ``rhs(t, z, p,
dz)`` evaluates

``z'' = A_0 [z; z'] + sum_k s_k(t) A_k [z; z'] + g_0 + Q f_L(t, q_B, q_B')``

with ``A_k = M_r^-1 T^T G_k diag(T, T)`` (``G_k``: the full model's linear
right-hand side per time factor ``s_k``, as split by
:class:`rotorkit.codegen.structured.Split`), ``g_0 = M_r^-1 T^T f_0`` (the
constant loads), ``Q = M_r^-1 T[L, :]^T`` and ``f_L`` the local terms of the
rows ``L`` (contacts, unbalance, ...), generated as scalar code reading the
physical boundary coordinates straight from ``z``. The reduced size ``R`` is
read from the prepared vector, so one module (one numba compilation) serves
every number of modes and every kept set.

Prepared vector: ``[parameters | derived | R | A_0 | A_1 ... | g_0 | Q | t_lo, t_hi]``, the
matrices column by column;
``linear_parts(p)`` (plain numpy, run once per parameter set) gives the base
(parameters and derived values) and the full model's ``M0``, ``G_k`` and ``f_0``.
"""

import sympy as sp

from ..codegen.printer import RhsPrinter
from ..codegen.structured import Split
from ..errors import TopologyError

__all__ = ["natural_boundary", "generate_reduced"]


def _tuple(values):
    return "(" + ", ".join(str(int(v)) for v in values) + ("," if len(values) == 1 else "") + ")"


def _local_parts(split, eom):
    """(local rows, their terms, the time factors, the switch functions) of a split."""
    rows = split.local_rows
    f_loc = [sp.Add(*split.local[i]) for i in rows]
    factors = [s for s in split.groups if s != 1]
    switches = [g for _, g in eom.switches]
    return rows, f_loc, factors, switches


def natural_boundary(split, eom):
    """Coordinates (indices, sorted) that must stay physical: local rows and every coordinate local terms read."""
    rows, f_loc, factors, switches = _local_parts(split, eom)
    index = {s: k % eom.n for k, s in enumerate(split.states)}
    used = set(rows)
    for e in f_loc + factors + switches:
        used |= {index[s] for s in e.free_symbols if s in index}
    return tuple(sorted(used))


def generate_reduced(eom, structure_key=""):
    """Source of the reduced module of ``eom`` (see the module docstring); ``GeneratedCode``-like text."""
    from ..codegen.emit import hoist, module_header, name_power_bases

    split = Split(eom)
    if split.S:
        names = ", ".join(str(eom.coordinates[i]) for i in split.S)
        raise TopologyError(f"{eom.name if hasattr(eom, 'name') else 'model'}: reduction does not handle a "
                            f"state-dependent mass matrix (coordinates {names}: an eccentric disk with torsion); "
                            "set the disk's eccentricity to 0 or its torsion off, or simulate the full model")
    n, t = eom.n, eom.t
    q, u = eom.coordinates, eom.speeds
    params = eom.parameters
    param_set = set(params)
    n_params = len(params)
    rows, f_loc, factors, switch_raw = _local_parts(split, eom)
    boundary = natural_boundary(split, eom)
    position = {i: k for k, i in enumerate(boundary)}
    groups = [split.groups[sp.S.One]] + [split.groups[s] for s in factors]

    states = list(split.states)
    df = {}  # (local index, state index in the full state) -> d f_l / d state
    for k, e in enumerate(f_loc):
        for st in sorted(e.free_symbols & set(states), key=states.index):
            df[(k, states.index(st))] = sp.diff(e, st)
    table = {}
    exprs = [hoist(e, param_set, table) for e in f_loc + factors + switch_raw + list(df.values())]
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("_c"), order="none")
    replacements, reduced = name_power_bases(replacements, reduced)
    floc_exprs = reduced[: len(rows)]
    factor_exprs = reduced[len(rows): len(rows) + len(factors)]
    switch_exprs = reduced[len(rows) + len(factors): len(rows) + len(factors) + len(switch_raw)]
    df_exprs = reduced[len(rows) + len(factors) + len(switch_raw):]
    derived = list(table.items())
    n_base = n_params + len(derived)

    names = {t: "t"}
    for i, (qi, ui) in enumerate(zip(q, u)):
        names[qi], names[ui] = f"q{i}", f"u{i}"
    for k, p in enumerate(params):
        names[p] = f"p{k}"
    for k, (_, sym) in enumerate(derived):
        names[sym] = f"k{k}"
    pr = RhsPrinter(names).doprint

    def prelude(name, out_arg, needed):
        used = set()
        for e in needed:
            used |= e.free_symbols
        keep = []
        for sym, e in reversed(replacements):
            if sym in used:
                keep.append((sym, e))
                used |= e.free_symbols
        keep.reverse()
        lines = [f"def {name}(t, y, p, {out_arg}):", "    t = min(max(t, p[len(p) - 2]), p[len(p) - 1])",
                 f"    R = int(p[{n_base}])"]
        for i, (qi, ui) in enumerate(zip(q, u)):
            if qi in used:
                lines.append(f"    q{i} = y[{position[i]}]")
            if ui in used:
                lines.append(f"    u{i} = y[R + {position[i]}]")
        lines += [f"    p{k} = p[{k}]" for k, p in enumerate(params) if p in used]
        lines += [f"    k{k} = p[{n_params + k}]" for k, (_, sym) in enumerate(derived) if sym in used]
        lines += [f"    {pr(sym)} = {pr(e)}" for sym, e in keep]
        return lines

    # linear_parts(p): numpy, once per parameter set
    lin = ["def linear_parts(p):", "    import numpy as np", ""]
    lin += [f"    p{k} = p[{k}]" for k in range(n_params)]
    mass_keys = sorted(split.mass0)
    const_rows = sorted(split.constant)
    group_keys = [sorted(g) for g in groups]
    values = [e for e, _ in derived]
    values += [sp.Add(*g[key]) for g, keys in zip(groups, group_keys) for key in keys]
    values += [sp.Add(*split.constant[i]) for i in const_rows]
    values += [split.mass0[key] for key in mass_keys]
    repl, vals = sp.cse(values, symbols=sp.numbered_symbols("_d"), order="none")
    lin += [f"    {pr(s)} = {pr(e)}" for s, e in repl]
    vit = iter(vals)
    lin += [f"    base = np.empty({n_base})", f"    base[:{n_params}] = p[:{n_params}]"]
    lin += [f"    base[{n_params + k}] = {pr(next(vit))}" for k in range(len(derived))]
    lin.append(f"    g = np.zeros(({len(groups)}, {n}, {2 * n}))")
    for k, keys in enumerate(group_keys):
        lin += [f"    g[{k}, {i}, {j}] = {pr(next(vit))}" for i, j in keys]
    lin.append(f"    f0 = np.zeros({n})")
    lin += [f"    f0[{i}] = {pr(next(vit))}" for i in const_rows]
    lin.append(f"    m0 = np.zeros(({n}, {n}))")
    lin += [f"    m0[{a}, {b}] = {pr(next(vit))}" for a, b in mass_keys]
    lin.append("    return base, m0, g, f0")

    # rhs(t, z, p, dz)
    n_groups = len(groups)
    body = prelude("rhs", "dydt", list(floc_exprs) + list(factor_exprs))
    body += [f"    s{k} = {pr(e)}" for k, e in enumerate(factor_exprs)]
    body += [f"    fl{k} = {pr(e)}" for k, e in enumerate(floc_exprs)]
    # column-major blocks: axpy loops over contiguous columns (vectorised; a dot product's sum would not be)
    body += ["    R2 = 2 * R", f"    a = {n_base + 1}", f"    og = a + {n_groups} * R * R2", "    oq = og + R",
             "    for i in range(R):", "        dydt[i] = y[R + i]", "        dydt[R + i] = p[og + i]",
             "    for j in range(R2):", "        v = y[j]", "        col = a + j * R", "        for i in range(R):",
             "            dydt[R + i] += p[col + i] * v"]
    for k in range(1, n_groups):
        body += ["    for j in range(R2):", f"        v = s{k - 1} * y[j]", f"        col = a + {k} * R * R2 + j * R",
                 "        for i in range(R):", "            dydt[R + i] += p[col + i] * v"]
    for k in range(len(rows)):
        body += [f"    col = oq + {k} * R", "    for i in range(R):", f"        dydt[R + i] += p[col + i] * fl{k}"]

    # jac(t, z, p, J): J (zeros on entry) = [[0, I], [A_0 + sum_k s_k A_k + Q d f_L / d z]]
    jac = prelude("jac", "J", list(factor_exprs) + list(df_exprs))
    jac += [f"    s{k} = {pr(e)}" for k, e in enumerate(factor_exprs)]
    jac += ["    R2 = 2 * R", f"    a = {n_base + 1}", f"    og = a + {n_groups} * R * R2", "    oq = og + R",
            "    for i in range(R):", "        J[i, R + i] = 1.0", "    for j in range(R2):", "        col = a + j * R",
            "        for i in range(R):", "            J[R + i, j] += p[col + i]"]
    for k in range(1, n_groups):
        jac += ["    for j in range(R2):", f"        col = a + {k} * R * R2 + j * R", "        for i in range(R):",
                f"            J[R + i, j] += s{k - 1} * p[col + i]"]
    for ((k, c), e) in zip(df, df_exprs):
        column = f"{position[c]}" if c < n else f"R + {position[c - n]}"
        jac += [f"    d = {pr(e)}", f"    col = oq + {k} * R", "    for i in range(R):",
                f"        J[R + i, {column}] += p[col + i] * d"]

    fac = prelude("time_factors", "out", list(factor_exprs))
    fac += [f"    out[{k}] = {pr(e)}" for k, e in enumerate(factor_exprs)] or ["    pass"]

    sw = prelude("switches", "out", list(switch_exprs))
    sw += [f"    out[{k}] = {pr(e)}" for k, e in enumerate(switch_exprs)] or ["    pass"]

    header = module_header(structure_key, "reduced", eom, q=q, u=u, params=params, derived=derived,
                           n_prepared=n_base, jacobian=True, n_switches=len(switch_exprs),
                           imports=("numpy as np",))
    header += [f"LOCAL_ROWS = {_tuple(rows)}", f"BOUNDARY = {_tuple(boundary)}", f"N_BASE = {n_base}",
               f"N_GROUPS = {n_groups}", "", ""]
    return "\n".join(header + lin + [""] + body + [""] + jac + [""] + fac + [""] + sw + [""])
