"""The pieces every code generator writes with: the result type, parameter hoisting, the unrolled solve of a
mass-matrix block, and the generated functions' first lines and module header.

Shared by the unrolled generator (:mod:`rotorkit.codegen.generate`), the structured one
(:mod:`rotorkit.codegen.structured`) and the reduced one (:mod:`rotorkit.reduction.codegen`); it imports none
of them, so none of them imports another for these.
"""

from dataclasses import dataclass

import sympy as sp

from .printer import MATH_FUNCTIONS

__all__ = ["GeneratedCode", "hoist", "name_power_bases", "BlockFactor", "function_prelude", "module_header"]


@dataclass(frozen=True)
class GeneratedCode:
    """Source text and layout of a generated RHS module."""

    source: str
    n_coordinates: int
    n_parameters: int
    n_derived: int
    blocks: tuple


def hoist(expr, params, table):
    """Replace parameter-only subexpressions of ``expr`` by symbols kept in ``table``.

    Every subtree's free symbols are computed once, bottom-up: sympy's
    ``free_symbols`` walks the whole subtree on each call, which made this
    quadratic in the expression's depth.
    """
    free = {}

    def symbols(e):
        found = free.get(e)
        if found is None:
            found = free[e] = e.free_symbols if e.is_Atom else frozenset().union(*map(symbols, e.args))
        return found

    def fixed(e):
        return symbols(e) <= params

    def hoist(e):
        if e.is_Atom or not symbols(e):  # a constant such as 100*pi stays as it is (hoisting it never ends)
            return e
        if fixed(e):
            if e not in table:
                table[e] = sp.Symbol(f"_k{len(table)}", real=True)
            return table[e]
        if e.is_Mul or e.is_Add:
            fixed_args = [a for a in e.args if fixed(a)]
            moving = [hoist(a) for a in e.args if not fixed(a)]
            fixed_part = e.func(*fixed_args) if fixed_args else None
            if fixed_part is not None and not fixed_part.is_Atom:
                fixed_part = hoist(fixed_part)
            args = moving + ([fixed_part] if fixed_part is not None else [])
            return e.func(*args, evaluate=False) if len(args) > 1 else args[0]
        return e.func(*map(hoist, e.args))

    return hoist(expr)


def name_power_bases(replacements, reduced):
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


class BlockFactor:
    """Unrolled LU factorisation (no pivoting: M is SPD) of one mass-matrix block.

    Divisions cost several multiplications: a pivot that is a parameter-only
    mass entry is divided by through its reciprocal from ``reciprocal`` (mass
    name -> name of ``1/m`` among the prepared values, computed once per
    parameter set); any other pivot used more than once gets its reciprocal
    computed once per evaluation.
    """

    def __init__(self, block, mass_name, reciprocal=None):
        self.block = block
        size = len(block)
        self.lines = []
        A = [[mass_name.get((min(block[r], block[c]), max(block[r], block[c]))) for c in range(size)]
             for r in range(size)]
        self.inverse = {}  # k -> name of 1/pivot, where the pivot is divided by through it
        self.lower = {}  # (r, k) -> multiplier name
        count = 0
        for k in range(size):
            below = [r for r in range(k + 1, size) if A[r][k] is not None]
            if reciprocal and A[k][k] in reciprocal:
                self.inverse[k] = reciprocal[A[k][k]]
            elif below:
                self.inverse[k] = f"_i{block[0]}_{k}"
                self.lines.append(f"    {self.inverse[k]} = 1.0 / {A[k][k]}")
            for r in below:
                count += 1
                factor = f"_l{block[0]}_{count}"
                self.lines.append(f"    {factor} = {A[r][k]}*{self.inverse[k]}")
                self.lower[(r, k)] = factor
                for c in range(k + 1, size):
                    if A[k][c] is None:
                        continue
                    count += 1
                    new = f"_l{block[0]}_{count}"
                    self.lines.append(f"    {new} = " + (f"{A[r][c]} - " if A[r][c] is not None else "-")
                                      + f"{factor}*{A[k][c]}")
                    A[r][c] = new
        self.upper = A  # upper triangle (c >= r) holds U

    def solve(self, rhs, out, tag):
        """Lines solving ``M_block x = rhs`` (names, None = 0); ``out(i, name)`` makes the store line."""
        size, block = len(self.block), self.block
        b = list(rhs)
        lines = []
        for k in range(size):
            for r in range(k + 1, size):
                factor = self.lower.get((r, k))
                if factor is None or b[k] is None:
                    continue
                new = f"_s{tag}_{block[r]}_{k}"
                lines.append(f"    {new} = " + (f"{b[r]} - " if b[r] is not None else "-") + f"{factor}*{b[k]}")
                b[r] = new
        x = [None] * size
        for k in reversed(range(size)):
            terms = [f" - {self.upper[k][c]}*{x[c]}" for c in range(k + 1, size)
                     if self.upper[k][c] is not None and x[c] is not None]
            if b[k] is None and not terms:
                continue
            x[k] = f"_x{tag}_{block[k]}"
            value = f"({b[k] if b[k] is not None else '0.0'}{''.join(terms)})"
            lines.append(f"    {x[k]} = {value}*{self.inverse[k]}" if k in self.inverse
                         else f"    {x[k]} = {value} / {self.upper[k][k]}")
            lines.append(out(block[k], x[k]))
        return lines, x


def function_prelude(name, out_arg, needed, *, doprint, replacements, q, u, params, derived, n_prepared,
                     all_speeds=False):
    """First lines of a generated ``name(t, y, p, out_arg)``: the time clamp, then the states, parameters,
    derived parameters and shared subexpressions that the ``needed`` expressions use (all speeds with
    ``all_speeds``: the right-hand side copies them into ``dydt``)."""
    n, n_params = len(q), len(params)
    used = set()
    for e in needed:
        used |= e.free_symbols
    keep = []
    for sym, e in reversed(replacements):  # keep the replacements the needed expressions use
        if sym in used:
            keep.append((sym, e))
            used |= e.free_symbols
    keep.reverse()
    lines = [f"def {name}(t, y, p, {out_arg}):", f"    t = min(max(t, p[{n_prepared}]), p[{n_prepared + 1}])"]
    for i, (qi, ui) in enumerate(zip(q, u)):
        if ui in used or all_speeds:
            lines.append(f"    u{i} = y[{n + i}]")
        if qi in used:
            lines.append(f"    q{i} = y[{i}]")
    lines += [f"    p{k} = p[{k}]" for k, p in enumerate(params) if p in used]
    lines += [f"    k{k} = p[{n_params + k}]" for k, (_, sym) in enumerate(derived) if sym in used]
    lines += [f"    {doprint(sym)} = {doprint(e)}" for sym, e in keep]
    return lines


def module_header(structure_key, codegen, eom, *, q, u, params, derived, n_prepared, jacobian, n_switches,
                  imports=()):
    """The generated module's docstring, imports and the layout constants System reads."""
    kind = "" if codegen == "unrolled" else f", {codegen}"
    return [
        f'"""Right-hand side generated by rotorkit (structure {structure_key}{kind}). Do not edit."""',
        f"from math import {', '.join(MATH_FUNCTIONS)}",
        "",
        *[line for module in imports for line in (f"import {module}", "")],
        f"CODEGEN = {codegen!r}",
        f"N_COORDINATES = {len(q)}",
        f"N_PARAMETERS = {len(params)}",
        f"N_DERIVED = {len(derived)}",
        f"N_PREPARED = {n_prepared + 2}",
        f"STATE_NAMES = {tuple([str(s) for s in q] + [str(s) for s in u])!r}",
        f"PARAMETER_NAMES = {tuple(str(p) for p in params)!r}",
        f"DERIVED_PARAMETERS = {tuple(tuple(sorted(str(s) for s in e.free_symbols)) for e, _ in derived)!r}",
        f"HAS_JACOBIAN = {bool(jacobian)}",
        f"N_SWITCHES = {n_switches}",
        f"SWITCH_OWNERS = {tuple(label for label, _ in eom.switches)!r}",
    ]
