"""Generated code: same numbers as the symbolic equations, guards, block solve."""

import math

import numpy as np
import pytest
import sympy as sp

import rotorkit as rk
from rotorkit.codegen.generate import double_angles, generate, mass_blocks
from rotorkit.codegen.printer import RhsPrinter
from rotorkit.symbolic.functions import ramp, safe_div, step, window


@pytest.mark.parametrize("backend", rk.available_backends())
def test_cse_and_block_solve_do_not_change_the_numbers(backend):
    """Compare with M, f evaluated straight from sympy and a dense numpy solve."""
    model = rk.preset("al31f")
    eom = model.equations()
    system = model.compile(backend=backend)
    values = {sp.Symbol(k, real=True): v for k, v in model.parameters.items()}
    args = (eom.t, *eom.coordinates, *eom.speeds)
    mods = [{"ramp": lambda v: max(v, 0.0), "safe_div": lambda a, b: a / b if b != 0 else 0.0,
                               "hypot": math.hypot,
                               "contact_ratio": lambda r, d: (r - d) / r if r > d else (1.0 if r == 0 and d == 0 else 0.0),
             "window": lambda t, a, b: 1.0 if a <= t < b else 0.0, "Min": min, "Max": max}, "math"]
    M = sp.lambdify(args, sp.Matrix(eom.mass_matrix.subs(values)).tolist(), modules=mods)
    f = sp.lambdify(args, sp.Matrix(eom.forcing.subs(values)).T.tolist()[0], modules=mods)
    rng = np.random.default_rng(11)
    for t in (0.1, 2.5, 4.7):
        y = rng.normal(size=32) * np.r_[np.full(16, 2e-4), np.full(16, 1e-2)]
        ref = np.linalg.solve(np.array(M(t, *y), dtype=float), np.array(f(t, *y), dtype=float).ravel())
        got = system.rhs(t, y)
        np.testing.assert_array_equal(got[:16], y[16:])
        np.testing.assert_allclose(got[16:], ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())


def test_double_angles_save_calls_and_keep_the_numbers():
    a, b, c = sp.symbols("a b c", real=True)
    exprs = [3 * sp.sin(2 * a * b) + sp.cos(a * b), sp.cos(2 * a * b) * sp.sin(a * b) + sp.sin(c)]
    out = double_angles(exprs)
    calls = set().union(*(e.atoms(sp.sin, sp.cos) for e in out))
    assert calls == {sp.sin(a * b), sp.cos(a * b), sp.sin(c)}  # four calls of a, b became two
    point = {a: 0.7, b: 1.3, c: -0.4}
    for e, new in zip(exprs, out):
        assert float(new.subs(point)) == pytest.approx(float(e.subs(point)), rel=1e-14)
    # only two of the four present: rewriting would not save a call, so nothing changes
    assert double_angles([sp.sin(2 * a) + sp.sin(a)]) == [sp.sin(2 * a) + sp.sin(a)]


def test_constant_masses_are_multiplied_by_their_prepared_reciprocals():
    """The preset's rhs divides by no parameter-only mass entry (a division costs several multiplications)."""
    eom = rk.preset("al31f").equations()
    source = generate(eom, "k").source
    rhs = source[source.index("def rhs("):source.index("def jac(")]
    divisions = [line for line in rhs.splitlines() if " / " in line]
    # what is left: each eccentric disk's Schur complement, which depends on the state
    assert len(divisions) == 2 and all(line.split(" / ")[1].startswith("_l") for line in divisions), divisions
    names = [str(p) for p in eom.parameters]
    for name in ("disk2_mass", "mass1_mass", "disk7_mass"):
        assert f"(1.0/(p{names.index(name)}))" in source


def test_mass_blocks_of_the_preset():
    blocks = mass_blocks(rk.preset("al31f").equations().mass_matrix)
    assert (1, 8, 14) in blocks and (4, 11, 15) in blocks
    assert sum(len(b) for b in blocks) == 16 and all(len(b) in (1, 3) for b in blocks)


@pytest.mark.parametrize("expr, point, expected", [
    (ramp(sp.Symbol("a")) ** sp.Rational(3, 2), {"a": -2.0}, 0.0),  # never complex
    (ramp(sp.Symbol("a")) ** sp.Rational(3, 2), {"a": 4.0}, 8.0),
    (safe_div(sp.Symbol("a"), sp.Symbol("b")), {"a": 0.0, "b": 0.0}, 0.0),  # finite at 0/0
    (safe_div(sp.Symbol("a"), sp.Symbol("b")), {"a": 3.0, "b": 2.0}, 1.5),
    (step(sp.Symbol("a")), {"a": 0.0}, 0.0),
    (window(sp.Symbol("a"), 2, 4), {"a": 4.0}, 0.0),
    (window(sp.Symbol("a"), 2, 4), {"a": 2.0}, 1.0),
    (sp.Symbol("a") / sp.Symbol("b") ** 3, {"a": 8.0, "b": 2.0}, 1.0),  # precedence of printed powers
    (1 / (sp.Symbol("a") + sp.Symbol("b")) ** 2, {"a": 1.0, "b": 1.0}, 0.25),
])
def test_printer_guards_and_precedence(expr, point, expected):
    code = RhsPrinter().doprint(expr)
    from math import sqrt  # noqa: F401  (used by the printed code)

    assert eval(code, {"sqrt": sqrt}, dict(point)) == pytest.approx(expected)  # noqa: S307 (our own printer)


def test_generated_module_documents_its_layout():
    model = rk.preset("al31f")
    code = generate(model.equations(), model.structure_key)
    assert "STATE_NAMES = ('x1'" in code.source and "PARAMETER_NAMES = (" in code.source
    assert "Heaviside" not in code.source and "Piecewise" not in code.source
    assert code.n_derived > 0  # parameter-only subexpressions are hoisted out of rhs()


def test_with_parameters_changes_numbers_without_rederiving():
    system = rk.preset("al31f").compile()
    y = np.zeros(32)
    y[1] = 2e-4  # x2 past the clearance
    soft, stiff = system.with_parameters(rub2_contact_stiffness=1e6), system.with_parameters(rub2_contact_stiffness=2e6)
    assert soft.core is system.core  # same compiled code
    f_soft = soft.rhs(0.0, y)[17] - system.with_parameters(rub2_contact_stiffness=0.0).rhs(0.0, y)[17]
    f_stiff = stiff.rhs(0.0, y)[17] - system.with_parameters(rub2_contact_stiffness=0.0).rhs(0.0, y)[17]
    assert f_stiff == pytest.approx(2 * f_soft, rel=1e-9)
    assert system.parameters["rub2_contact_stiffness"] == 8e6
