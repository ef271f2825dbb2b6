"""Structure-aware code generation for large models: matrices for the linear part, scalar code for the rest.

The equations ``M(q, t) q'' = F(q, q', t) - K q - C q'`` of a beam rotor are
mostly linear with constant coefficients; only a few coordinates carry
nonlinear or time-dependent terms (contacts, Hertzian bearings, unbalance,
manoeuvre loads, eccentric torsional disks). This module splits them:

* **linear part**: every term ``c(p) s(t) y_j`` of the right-hand side
  (stiffness, damping, gyroscopic coupling, ...) with ``c`` a parameter-only
  coefficient and ``s`` one of a few time factors (``1``, the rotor speed of a
  speed profile); kept as sparse matrices, one per time factor, whose values
  ``prepare()`` evaluates once per parameter set;
* **constant mass matrix** ``M0 = M(q = 0, t = 0)``: ``prepare()`` evaluates
  it and stores its inverse and, for larger models, its band Cholesky factor
  (:func:`generate_structured`, :func:`band_pays`);
* **local part**: what remains of ``F`` (rows ``L``), written as scalar
  generated code as in the unrolled path, and applied through the columns
  ``M0^-1[:, L]``;
* **state-dependent mass** (an eccentric disk with torsion):
  ``M = M0 + E(q, t)`` with ``E`` non-zero on a few coordinates ``S`` only;
  solved exactly by the Woodbury identity
  ``x = z - P (H + E)^-1 E z_S`` with ``z = M0^-1 f``,
  ``H = (M0^-1[S, S])^-1`` and ``P = M0^-1[:, S] H`` from ``prepare()``;
  ``H + E`` is the Schur complement of ``M`` on ``S``, symmetric positive
  definite, so its small unrolled factorisation needs no pivoting.

The generated module keeps the contract of :mod:`rotorkit.codegen.generate`
(``prepare``, ``rhs``, ``jac``, ``switches``; same header constants, plus
``CODEGEN = 'structured'``). ``rhs`` and ``jac`` are loops over index arrays
(module constants) and over the prepared vector, so their size, and numba's
compile time, grows with the number of *local* terms, not with the model.
``prepare`` uses numpy (it runs in Python, never under numba).
"""

from collections import defaultdict

import sympy as sp

from .printer import RhsPrinter

__all__ = ["generate_structured", "split_equations", "Split"]

BLOCK_INVERSE = '''def _spd_inverse(a):
    """Inverse of a symmetric positive definite matrix (equilibrated Cholesky); NaN if it is not one."""
    out = np.full(a.shape, np.nan)
    if a.size == 0:
        return out
    if not np.all(np.isfinite(a)) or np.any(np.diag(a) <= 0.0):
        return out
    d = 1.0 / np.sqrt(np.diag(a))
    try:
        c = np.linalg.cholesky(a * d[:, None] * d[None, :])
    except np.linalg.LinAlgError:
        return out
    ci = np.linalg.inv(c)
    out = (ci.T @ ci) * d[:, None] * d[None, :]
    return 0.5 * (out + out.T)


def _band_factor(a, b):
    """Cholesky factor of the SPD band matrix ``a`` (half-bandwidth ``b``) in band storage; NaN if not SPD.

    Row k holds ``1 / L[k, k]`` in column 0 and ``L[k, k - d]`` in column d.
    """
    n = a.shape[0]
    lb = np.zeros((n, b + 1))
    for k in range(n):
        for d in range(min(b, k), 0, -1):
            j = k - d
            v = a[k, j] - sum(lb[k, d + e] * lb[j, e] for e in range(1, min(b - d, j) + 1))
            lb[k, d] = v * lb[j, 0]
        v = a[k, k] - sum(lb[k, d] * lb[k, d] for d in range(1, min(b, k) + 1))
        if not (v > 0.0 and np.isfinite(v)):
            return np.full((n, b + 1), np.nan)
        lb[k, 0] = 1.0 / np.sqrt(v)
    return lb


def _block_inverse(m0, r, s):
    """(W, Pm, H) of M0 split into the constant coordinates r and the state-dependent-mass ones s.

    W: M0[r, r]^-1 embedded in n x n (zero rows and columns s); Pm: T = M0[r, r]^-1 M0[r, s] in rows r and
    -I in rows s (n x len(s)); H = M0[s, s] - M0[s, r] T, the Schur complement. Without s: W = M0^-1.
    """
    n = m0.shape[0]
    w = np.zeros((n, n))
    w[np.ix_(r, r)] = _spd_inverse(m0[np.ix_(r, r)])
    pm = np.zeros((n, len(s)))
    h = np.zeros((len(s), len(s)))
    if len(s):
        t = w[np.ix_(r, r)] @ m0[np.ix_(r, s)]
        pm[r, :] = t
        pm[s, np.arange(len(s))] = -1.0
        h = m0[np.ix_(s, s)] - m0[np.ix_(s, r)] @ t
        h = 0.5 * (h + h.T)
        if not np.all(np.isfinite(h)) or not np.all(np.isfinite(_spd_inverse(h))):
            h[:] = np.nan
    return w, pm, h
'''


class Split:
    """The equations split into linear matrices and local scalar terms (symbolic)."""

    def __init__(self, eom):
        n = eom.n
        q, u, t = eom.coordinates, eom.speeds, eom.t
        states = list(q) + list(u)
        self.n, self.states, self.t = n, states, t
        self.state_index = {s: k for k, s in enumerate(states)}
        self.params = set(eom.parameters)
        self.groups = {sp.S.One: defaultdict(list)}  # time factor -> {(row, state): [coefficients]}
        self.constant = defaultdict(list)  # row -> parameter-only force terms
        self.local = defaultdict(list)  # row -> remaining terms
        for mat, sign_x in ((eom.stiffness, q), (eom.damping, u)):
            for (i, j), v in mat.todok().items():
                if v != 0:
                    self._term(i, -v * sign_x[j], coefficient=-v, state=sign_x[j])
        for (i, _), v in eom.nonlinear_forcing().todok().items():
            for term in sp.Add.make_args(v):
                self._term(i, term)
        M = eom.mass_matrix
        zero = {s: 0 for s in states}
        zero[t] = 0
        self.mass0, self.mass_extra = {}, {}
        for (a, b), v in M.todok().items():
            if v == 0:
                continue
            if v.free_symbols <= self.params:
                self.mass0[(a, b)] = v
            else:
                v0 = v.xreplace(zero)
                if v0 != 0:
                    self.mass0[(a, b)] = v0
                self.mass_extra[(a, b)] = v - v0
        self.S = tuple(sorted({a for a, _ in self.mass_extra} | {b for _, b in self.mass_extra}))

    def _params_only(self, e):
        return e.free_symbols <= self.params

    def _term(self, row, term, coefficient=None, state=None):
        if coefficient is None:
            found = term.free_symbols & self.state_index.keys()
            if not found:
                if self._params_only(term):
                    self.constant[row].append(term)
                else:
                    self.local[row].append(term)
                return
            if len(found) == 1:
                (state,) = found
                c, rest = term.as_independent(state, as_Add=False)
                if rest == state:
                    coefficient = c
            if coefficient is None:
                if term.is_Mul and any(a.is_Add and a.free_symbols & found for a in term.args):
                    expanded = sp.expand_mul(term)
                    if expanded.is_Add:
                        for part in expanded.args:
                            self._term(row, part)
                        return
                self.local[row].append(term)
                return
        if coefficient.free_symbols & self.state_index.keys():
            self.local[row].append(term)
            return
        if self._params_only(coefficient):
            self.groups[sp.S.One][(row, self.state_index[state])].append(coefficient)
            return
        fixed, varying = coefficient.as_independent(self.t, as_Add=False)
        if self._params_only(fixed) and varying.free_symbols and not varying.free_symbols & self.state_index.keys():
            self.groups.setdefault(varying, defaultdict(list))[(row, self.state_index[state])].append(fixed)
            return
        self.local[row].append(term)

    @property
    def local_rows(self):
        return tuple(sorted(i for i, terms in self.local.items() if sp.Add(*terms) != 0))


def split_equations(eom):
    """The :class:`Split` of ``eom`` (linear matrices, constant mass, local terms)."""
    return Split(eom)


def _csr(n, entries):
    """Row pointers, columns and the keys in CSR order of ``{(row, col): value}``."""
    keys = sorted(entries)
    ptr = [0] * (n + 1)
    for i, _ in keys:
        ptr[i + 1] += 1
    for i in range(n):
        ptr[i + 1] += ptr[i]
    return ptr, [j for _, j in keys], keys


def _tuple(values):
    return "(" + ", ".join(str(int(v)) for v in values) + ("," if len(values) == 1 else "") + ")"


SOLVES = ("auto", "dense", "band")


def mass_band(split):
    """(order, half-bandwidth) of ``M0`` on the constant-mass coordinates, in reverse Cuthill-McKee order."""
    import numpy as np
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    rows = [i for i in range(split.n) if i not in split.S]
    index = {i: k for k, i in enumerate(rows)}
    pairs = [(index[a], index[b]) for (a, b) in split.mass0 if a in index and b in index]
    if not rows:
        return (), 0
    a, b = zip(*pairs) if pairs else ((), ())
    pattern = csr_matrix((np.ones(len(pairs)), (a, b)), shape=(len(rows), len(rows)))
    perm = reverse_cuthill_mckee(pattern + pattern.T, symmetric_mode=True)
    position = np.empty(len(rows), dtype=int)
    position[perm] = np.arange(len(rows))
    width = max((abs(int(position[i]) - int(position[j])) for i, j in pairs), default=0)
    return tuple(rows[k] for k in perm), width


def band_pays(n_rows, width):
    """Whether the band solve beats the dense ``M0^-1`` product in the right-hand side.

    About ``4 n (b + 1)`` multiply-adds in short indirect loops against ``n^2``
    in one vectorised loop. Measured on the quiet machine
    (``bench/bench_fe.py --sections solve``, beam rotors with ``b = 3``),
    band / dense: 0.84-1.22 at 100 coordinates, 0.97-1.03 at 140, 0.69-0.81
    at 200, 0.46 at 400. From ``n = 40 (b + 1)`` on (160 for beam rotors).
    """
    return 40 * (width + 1) <= n_rows


def generate_structured(eom, structure_key="", jacobian=True, solve="auto"):
    """Generate the structured module source for ``eom`` (see the module docstring).

    ``solve`` picks how ``rhs`` applies ``M0^-1``: ``"dense"``, one product
    with the stored inverse (``n^2`` multiply-adds in a vectorised loop), or
    ``"band"``, forward and back substitution with the band Cholesky factor
    of ``M0`` in reverse Cuthill-McKee order (``4 n (b + 1)`` for half-bandwidth
    ``b``; a beam rotor's ``b`` is a few coordinates); ``"auto"`` takes the
    band where :func:`band_pays`. The Jacobian always uses the dense inverse,
    whose columns ``M0^-1 K`` it needs anyway.

    Returns
    -------
    GeneratedCode
    """
    from .emit import BlockFactor, GeneratedCode, function_prelude, hoist, module_header, name_power_bases

    from ..errors import ParameterError

    if solve not in SOLVES:
        raise ParameterError(f"solve={solve!r} is unknown; expected 'auto', 'dense' or 'band'")
    split = Split(eom)
    n, t = eom.n, eom.t
    q, u = eom.coordinates, eom.speeds
    states = split.states
    params = eom.parameters
    param_set = set(params)
    n_params = len(params)
    L = split.local_rows
    S = split.S
    ns = len(S)
    f_loc = {i: sp.Add(*split.local[i]) for i in L}
    factors = [s for s in split.groups if s != 1]
    groups = [split.groups[sp.S.One]] + [split.groups[s] for s in factors]
    extra_keys = sorted((a, b) for (a, b) in split.mass_extra if a <= b)
    extra = [split.mass_extra[k] for k in extra_keys]

    df, dE = {}, {}
    if jacobian:
        for i in L:
            for s in sorted(f_loc[i].free_symbols & set(states), key=states.index):
                df[(i, states.index(s))] = sp.diff(f_loc[i], s)
        for key, e in zip(extra_keys, extra):
            for s in sorted(e.free_symbols & set(states), key=states.index):
                dE[key + (states.index(s),)] = sp.diff(e, s)

    switch_raw = [g for _, g in eom.switches]
    table = {}
    exprs = [f_loc[i] for i in L] + extra + factors + list(df.values()) + list(dE.values()) + switch_raw
    exprs = [hoist(e, param_set, table) for e in exprs]
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("_c"), order="none")
    replacements, reduced = name_power_bases(replacements, reduced)
    it = iter(reduced)
    floc_exprs = [next(it) for _ in L]
    extra_exprs = [next(it) for _ in extra]
    factor_exprs = [next(it) for _ in factors]
    df_exprs = [next(it) for _ in df]
    dE_exprs = [next(it) for _ in dE]
    switch_exprs = [next(it) for _ in switch_raw]

    names = {t: "t"}
    for i, (qi, ui) in enumerate(zip(q, u)):
        names[qi], names[ui] = f"q{i}", f"u{i}"
    for k, p in enumerate(params):
        names[p] = f"p{k}"
    derived = list(table.items())
    for k, (_, sym) in enumerate(derived):
        names[sym] = f"k{k}"
    printer = RhsPrinter(names)
    pr = printer.doprint

    # layout of the prepared vector
    offset = n_params + len(derived)
    group_csr, group_off = [], []
    for g in groups:
        ptr, cols, keys = _csr(n, g)
        group_csr.append((ptr, cols, keys))
        group_off.append(offset)
        offset += len(keys)
    off_f0 = offset
    has_f0 = bool(split.constant)
    offset += (n + ns) if has_f0 else 0
    off_minv = offset
    offset += n * n
    off_h, off_pm = offset, offset + ns * ns
    offset += ns * ns + n * ns
    order, width = mass_band(split)
    band = solve == "band" or (solve == "auto" and band_pays(len(order), width))
    off_band = offset
    offset += len(order) * (width + 1) if band else 0
    n_prepared = offset

    # prepare(): parameters, hoisted subexpressions, matrix values, M0^-1
    prep = ["def prepare(p, out):", "    import numpy as np", "", f"    for i in range({n_params}):",
            "        out[i] = p[i]"]
    prep += [f"    p{k} = p[{k}]" for k in range(n_params)]
    mass_keys = sorted(split.mass0)
    values = [e for e, _ in derived]
    values += [sp.Add(*g[key]) for g, (_, _, keys) in zip(groups, group_csr) for key in keys]
    f0_rows = sorted(split.constant)
    values += [sp.Add(*split.constant[i]) for i in f0_rows]
    values += [split.mass0[key] for key in mass_keys]
    repl, vals = sp.cse(values, symbols=sp.numbered_symbols("_d"), order="none")
    prep += [f"    {pr(s)} = {pr(e)}" for s, e in repl]
    vit = iter(vals)
    for k in range(len(derived)):
        prep.append(f"    out[{n_params + k}] = {pr(next(vit))}")
    for off, (_, _, keys) in zip(group_off, group_csr):
        for e in range(len(keys)):
            prep.append(f"    out[{off + e}] = {pr(next(vit))}")
    prep.append(f"    f0 = np.zeros({n})")
    for i in f0_rows:
        prep.append(f"    f0[{i}] = {pr(next(vit))}")
    prep.append(f"    m0 = np.zeros(({n}, {n}))")
    for (a, b) in mass_keys:
        prep.append(f"    m0[{a}, {b}] = {pr(next(vit))}")
    prep += [
        f"    s = np.array({list(S)!r}, dtype=np.int64)",
        f"    r = np.array({[i for i in range(n) if i not in S]!r}, dtype=np.int64)",
        "    w, pm, h = _block_inverse(m0, r, s)",
        f"    out[{off_minv}:{off_minv + n * n}] = w.ravel()",
        f"    out[{off_h}:{off_h + ns * ns}] = h.ravel()",
        f"    out[{off_pm}:{off_pm + n * ns}] = pm.ravel()",
    ]
    if has_f0 and band:  # the constant forces join f before the solve
        prep += [f"    out[{off_f0}:{off_f0 + n}] = f0"]
    elif has_f0:
        prep += [f"    out[{off_f0}:{off_f0 + n}] = w @ f0", f"    out[{off_f0 + n}:{off_f0 + n + ns}] = -(pm.T @ f0)"]
    if band:
        prep += [f"    order = np.array({list(order)!r}, dtype=np.int64)",
                 f"    out[{off_band}:{off_band + len(order) * (width + 1)}] = "
                 f"_band_factor(m0[np.ix_(order, order)], {width}).ravel()"]
    prep += [f"    out[{n_prepared}] = -1e300  # time window of the equations, see rhs()",
             f"    out[{n_prepared + 1}] = 1e300", "    return out"]

    def prelude(name, out_arg, needed):
        return function_prelude(name, out_arg, needed, doprint=pr, replacements=replacements, q=q, u=u,
                                params=params, derived=derived, n_prepared=n_prepared)

    def schur_factor():
        """Lines factorising ``H + E(q, t)`` (the Schur complement of M on S), unrolled, no pivoting (SPD)."""
        lines, mass_name = [], {}
        for r, a in enumerate(S):
            for c, b in enumerate(S):
                if r <= c:
                    e = extra_names.get((a, b))
                    lines.append(f"    h{a}_{b} = p[{off_h + r * ns + c}]" + (f" + {e}" if e else ""))
                    mass_name[(a, b)] = f"h{a}_{b}"
        factor = BlockFactor(S, mass_name)
        return lines + factor.lines, factor

    def schur_solve(factor, rhs_names, target, tag, indent=""):
        """Lines solving ``(H + E) x_S = g`` and applying ``target -= Pm x_S`` (Pm: T in rows R, -I in rows S)."""
        solve, x = factor.solve(rhs_names, lambda i, name: "", tag)
        lines = [indent + line for line in solve if line]
        terms = [f"p[{off_pm} + i * {ns} + {r}] * {x[r]}" for r in range(ns) if x[r] is not None]
        if terms:
            lines += [f"{indent}    for i in range({n}):", f"{indent}        {target('i')} -= " + " + ".join(terms)]
        return lines

    def local_lines():
        """The time factors ``s_k`` and the local forces ``fl_i``."""
        return ([f"    s{k} = {pr(e)}" for k, e in enumerate(factor_exprs)]
                + [f"    fl{i} = {pr(e)}" for i, e in zip(L, floc_exprs)])

    def row_force_lines(init):
        """Opens ``for j in range(n):`` with ``fj`` = ``init`` + row j of the linear part (every time factor)."""
        lines = [f"    for j in range({n}):", f"        fj = {init}"]
        for k, (ptr, _, _) in enumerate(group_csr):
            if not ptr[-1]:
                continue
            acc = "fj" if k == 0 else "g"
            if k:
                lines.append("        g = 0.0")
            lines += [f"        for e in range(PTR{k}[j], PTR{k}[j + 1]):",
                      f"            {acc} += p[{group_off[k]} + e] * y[COL{k}[e]]"]
            if k:
                lines.append(f"        fj += s{k - 1} * g")
        return lines

    def accelerations(target):
        """Lines computing q'' into ``target(i)`` (a string for index expression i)."""
        if band:
            return band_accelerations(target)
        init = f"p[{off_f0} + i]" if has_f0 else "0.0"
        lines = local_lines() + [f"    for i in range({n}):", f"        {target('i')} = {init}"]
        lines += [f"    g{r} = " + (f"p[{off_f0 + n + r}]" if has_f0 else "0.0") for r in range(ns)]
        lines += row_force_lines("0.0")
        lines += ["        if fj != 0.0:", f"            for i in range({n}):",
                  f"                {target('i')} += p[{off_minv} + j * {n} + i] * fj"]
        lines += [f"            g{r} -= p[{off_pm} + j * {ns} + {r}] * fj" for r in range(ns)]
        for i in L:
            if i not in S:
                lines += [f"    for i in range({n}):",
                          f"        {target('i')} += p[{off_minv} + {i} * {n} + i] * fl{i}"]
            lines += [f"    g{r} -= p[{off_pm + i * ns + r}] * fl{i}" for r in range(ns)]
        if ns:
            factor_lines, factor = schur_factor()
            lines += factor_lines + schur_solve(factor, [f"g{r}" for r in range(ns)], target, "x")
        return lines

    def band_accelerations(target):
        """As ``accelerations``, with f assembled first and ``M0[R, R] z = f[R]`` solved in place, in band order."""
        lines = local_lines() + row_force_lines(f"p[{off_f0} + j]" if has_f0 else "0.0")
        lines.append(f"        {target('j')} = fj")
        lines += [f"    {target(str(i))} += fl{i}" for i in L]
        if ns:  # g = -Pm^T f, then the Schur coordinates leave the band solve
            lines += [f"    g{r} = 0.0" for r in range(ns)]
            lines += [f"    for i in range({n}):", f"        fi = {target('i')}"]
            lines += [f"        g{r} -= p[{off_pm} + i * {ns} + {r}] * fi" for r in range(ns)]
            lines += [f"    {target(str(a))} = 0.0" for a in S]
        w = width + 1
        lines += [f"    for k in range({len(order)}):", f"        v = {target('ORDER[k]')}",
                  f"        for d in range(1, min({width}, k) + 1):",
                  f"            v -= p[{off_band} + k * {w} + d] * {target('ORDER[k - d]')}",
                  f"        {target('ORDER[k]')} = v * p[{off_band} + k * {w}]",
                  f"    for k in range({len(order) - 1}, -1, -1):", f"        v = {target('ORDER[k]')}",
                  f"        for d in range(1, min({width}, {len(order) - 1} - k) + 1):",
                  f"            v -= p[{off_band} + (k + d) * {w} + d] * {target('ORDER[k + d]')}",
                  f"        {target('ORDER[k]')} = v * p[{off_band} + k * {w}]"]
        if ns:
            factor_lines, factor = schur_factor()
            lines += factor_lines + schur_solve(factor, [f"g{r}" for r in range(ns)], target, "x")
        return lines

    extra_names = {key: f"em{key[0]}_{key[1]}" for key in extra_keys}
    extra_lines = [f"    {extra_names[key]} = {pr(e)}" for key, e in zip(extra_keys, extra_exprs)]

    body = prelude("rhs", "dydt", floc_exprs + extra_exprs + factor_exprs)
    body += [f"    for i in range({n}):", f"        dydt[i] = y[{n} + i]"]
    body += extra_lines + accelerations(lambda i: f"dydt[{n} + {i}]")

    jac = []
    if jacobian:
        # J[n:, c] = M^-1 r_c, r_c = df/dy_c - dM/dy_c q''. With state-dependent mass, J[r, c] (r < len(S))
        # accumulates g = -Pm^T r_c before the Schur solve, and J[:n, 0] holds q'' meanwhile; both are zero in
        # the result, the identity block J[i, n + i] is written last.
        jac = prelude("jac", "J", floc_exprs + extra_exprs + factor_exprs + df_exprs + dE_exprs)
        jac += extra_lines
        if ns:
            jac += accelerations(lambda i: f"J[{i}, 0]")
            jac += [f"    x{a} = J[{a}, 0]" for a in S]
            jac += [f"    for i in range({n}):", "        J[i, 0] = 0.0"]
        else:
            jac += [f"    s{k} = {pr(e)}" for k, e in enumerate(factor_exprs)]
        for k, (ptr, _, _) in enumerate(group_csr):
            if not ptr[-1]:
                continue
            scale = "" if k == 0 else f"s{k - 1} * "
            jac += [f"    for j in range({n}):", f"        for e in range(PTR{k}[j], PTR{k}[j + 1]):",
                    f"            v = {scale}p[{group_off[k]} + e]", f"            c = COL{k}[e]",
                    f"            for i in range({n}):",
                    f"                J[{n} + i, c] += p[{off_minv} + j * {n} + i] * v"]
            jac += [f"            J[{r}, c] -= p[{off_pm} + j * {ns} + {r}] * v" for r in range(ns)]
        columns = defaultdict(dict)
        for (i, k), e in zip(df, df_exprs):
            columns[k].setdefault(i, []).append(f"({pr(e)})")
        for (a, b, k), e in zip(dE, dE_exprs):
            d = pr(e)
            columns[k].setdefault(a, []).append(f"-({d})*x{b}")
            if a != b:
                columns[k].setdefault(b, []).append(f"-({d})*x{a}")
        for k in sorted(columns):
            for i, terms in sorted(columns[k].items()):
                jac.append(f"    r = {' + '.join(terms)}")
                if i not in S:
                    jac += [f"    for i in range({n}):", f"        J[{n} + i, {k}] += p[{off_minv} + {i} * {n} + i] * r"]
                jac += [f"    J[{r}, {k}] -= p[{off_pm + i * ns + r}] * r" for r in range(ns)]
        if ns:
            factor_lines, factor = schur_factor()
            jac += factor_lines + [f"    for c in range({2 * n}):"]
            for r in range(ns):
                jac += [f"        w{r} = J[{r}, c]", f"        J[{r}, c] = 0.0"]
            jac += schur_solve(factor, [f"w{r}" for r in range(ns)], lambda i: f"J[{n} + {i}, c]", "w", "    ")
        jac += [f"    for i in range({n}):", f"        J[i, {n} + i] = 1.0"]

    sw = prelude("switches", "out", switch_exprs)
    sw += [f"    out[{i}] = {pr(e)}" for i, e in enumerate(switch_exprs)]
    if not switch_exprs:
        sw.append("    pass")

    header = module_header(structure_key, "structured", eom, q=q, u=u, params=params, derived=derived,
                           n_prepared=n_prepared, jacobian=jacobian, n_switches=len(switch_exprs),
                           imports=("numpy as np",)) + [
        f"LOCAL_ROWS = {_tuple(L)}",
        f"MASS_STATE_DEPENDENT = {_tuple(S)}",
        f"MASS_SOLVE = {'band' if band else 'dense'!r}",
    ]
    if band:
        header.append(f"ORDER = np.array({_tuple(order)}, dtype=np.int64)")
    for k, (ptr, cols, _) in enumerate(group_csr):
        header.append(f"PTR{k} = np.array({_tuple(ptr)}, dtype=np.int64)")
        header.append(f"COL{k} = np.array({_tuple(cols) if cols else '()'}, dtype=np.int64)")
    header += ["", "", BLOCK_INVERSE]
    source = "\n".join(header + prep + [""] + body + [""] + jac + [""] + sw + [""])
    return GeneratedCode(source=source, n_coordinates=n, n_parameters=n_params, n_derived=len(derived),
                         blocks=())
