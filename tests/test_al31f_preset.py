"""The AL-31F preset against the paper's printed matrices and an independent
hand-written evaluation of the equations in MODEL_NOTES."""

import math

import numpy as np
import pytest
import sympy as sp

import rotorkit as rk

BACKENDS = rk.available_backends()


@pytest.fixture(scope="module")
def model():
    return rk.preset("al31f")


@pytest.fixture(scope="module")
def numeric_matrices(model):
    eom = model.equations()
    values = {sp.Symbol(k, real=True): v for k, v in model.parameters.items()}
    M0 = np.array(eom.linear_mass_matrix().subs(values), dtype=float)
    C = np.array(eom.damping.subs(values), dtype=float)
    K = np.array(eom.stiffness.subs(values), dtype=float)
    return M0, C, K


def paper_chain(a1, a2, a3, a5, a6, a7, a8, a9, a10):
    """The 7x7 pattern printed in eqs. 8 and 11."""
    return np.array([
        [a1 + a6, -a6, 0, 0, 0, 0, 0],
        [-a6, a6 + a7, -a7, 0, 0, 0, 0],
        [0, -a7, a2 + a7 + a8, -a8, 0, 0, 0],
        [0, 0, -a8, a8 + a9, -a9, 0, 0],
        [0, 0, 0, -a9, a9 + a10, -a10, 0],
        [0, 0, 0, 0, -a10, a5 + a10, 0],
        [0, 0, 0, 0, 0, 0, a3],
    ], dtype=float)


def test_coordinates_named_as_the_paper(model):
    assert model.coordinate_names == tuple(
        [f"x{i}" for i in range(1, 8)] + [f"y{i}" for i in range(1, 8)] + ["alpha2", "alpha5"])


def test_stiffness_matrix_equals_eq_8(numeric_matrices):
    E, I, G, Ip = 2e11, 1.178e-7, 7.7e10, 2.356e-7
    l1, l2, l3, l4, l5 = 0.33, 0.33, 0.6, 0.23, 0.23
    k = 1e6
    Kx = paper_chain(k, k, k, k, 3 * E * I / l1**3, 12 * E * I / l2**3, 12 * E * I / l3**3,
                     12 * E * I / l4**3, 3 * E * I / l5**3)
    kt1, kt2 = G * Ip / l1, G * Ip / (l2 + l3 + l4)
    Kt = np.array([[kt1 + kt2, -kt2], [-kt2, kt2]])
    expected = np.zeros((16, 16))
    expected[:7, :7] = Kx
    expected[7:14, 7:14] = Kx
    expected[14:, 14:] = Kt
    np.testing.assert_allclose(numeric_matrices[2], expected, rtol=1e-12, atol=1e-6)


def test_damping_matrix_equals_eq_11(numeric_matrices):
    Cx = paper_chain(300, 300, 300, 300, 150, 150, 150, 150, 150)
    expected = np.zeros((16, 16))
    expected[:7, :7] = Cx
    expected[7:14, 7:14] = Cx
    expected[14:, 14:] = [[2.0, -1.0], [-1.0, 1.0]]
    np.testing.assert_allclose(numeric_matrices[1], expected, rtol=1e-12, atol=1e-12)


def test_mass_matrix_equals_eq_20(numeric_matrices):
    masses = [2, 10, 2, 2, 6, 2, 8]
    e = 46.35e-6
    J2, J5 = 10 * 0.075**2 / 2 + 10 * e**2, 6 * 0.03**2 / 2 + 6 * e**2
    expected = np.diag(masses + masses + [J2, J5])
    np.testing.assert_allclose(numeric_matrices[0], expected, rtol=1e-14)


def _states(handwritten):
    """States that exercise every branch: rest, r2 = 0, just inside/past the
    clearance, bearing engaged, inside and after the roll window."""
    P = handwritten.params()
    rng = np.random.default_rng(7)
    cases = []
    for t in (0.0, 1.3, 2.0, 2.7, 3.999, 4.0, 5.2):
        y = np.zeros(32)
        cases.append((t, y))  # at rest, r2 = 0 exactly
        y = rng.normal(size=32) * np.r_[np.full(16, 5e-5), np.full(16, 5e-3)]
        y[1] = y[8] = 0.0  # r2 = 0 with other motion
        cases.append((t, y))
        for factor in (0.999, 1.001, 1.5):  # r2 just inside, just past and well past the clearance
            y = rng.normal(size=32) * np.r_[np.full(16, 5e-5), np.full(16, 5e-3)]
            angle = rng.uniform(0, 2 * math.pi)
            r = factor * P["delta"]
            y[1], y[8] = r * math.cos(angle), r * math.sin(angle)
            y[6] += 3 * P["delta0"]  # bearing balls engaged
            cases.append((t, y))
    return cases


@pytest.mark.parametrize("backend", BACKENDS)
def test_rhs_agrees_with_independent_evaluation(handwritten, backend):
    system = rk.preset("al31f").compile(backend=backend)
    P = handwritten.params()
    for t, y in _states(handwritten):
        ours = system.rhs(t, y)
        ref = handwritten.rhs_numpy(t, y, P)
        assert np.all(np.isfinite(ours))
        # accelerations at stations 4 and 7 are small differences of large
        # bearing forces: compare relative to the block's largest entry
        for block in (slice(0, 16), slice(16, 30), slice(30, 32)):
            scale = max(np.abs(ref[block]).max(), 1e-300)
            assert np.abs(ours[block] - ref[block]).max() <= 1e-9 * scale, (t, backend)


def test_rub_force_and_torque_pieces(handwritten):
    """The rub element's force and friction torque (with the minus sign) at chosen states."""
    model = rk.preset("al31f", maneuver=False, gravity=0.0)
    eom = model.equations()
    P = handwritten.params()
    values = {sp.Symbol(k, real=True): v for k, v in model.parameters.items()}
    rub = eom.forces["rub2"]
    x2, y2, a2 = eom.coordinates[1], eom.coordinates[8], 14
    fn = sp.lambdify((x2, y2), [rub[1].subs(values), rub[8].subs(values), rub[a2].subs(values)],
                     modules=[{"ramp": lambda v: max(v, 0.0),
                               "safe_div": lambda a, b: a / b if b != 0 else 0.0,
                               "hypot": math.hypot,
                               "contact_ratio": lambda r, d: (r - d) / r if r > d else (1.0 if r == 0 and d == 0 else 0.0)}, "math"])
    for r in (0.0, 0.5 * P["delta"], P["delta"] * (1 + 1e-9), 1.2 * P["delta"], 3 * P["delta"]):
        for angle in (0.0, 1.0, 2.5):
            q = np.zeros(16)
            q[1], q[8] = r * math.cos(angle), r * math.sin(angle)
            fx, fy, torque = fn(q[1], q[8])
            ex, ey, et = handwritten.rub_force(q, P)
            np.testing.assert_allclose([fx, fy, torque], [ex, ey, et], rtol=1e-12, atol=1e-12)
            if r > P["delta"]:
                assert torque < 0  # friction opposes the spin


def test_zero_clearance_is_finite_at_the_origin():
    system = rk.preset("al31f", rub_clearance=0.0).compile()
    assert np.all(np.isfinite(system.rhs(0.5, np.zeros(32))))


def test_time_events_are_the_roll_window():
    assert rk.preset("al31f").compile().time_events == (2.0, 4.0)
    system = rk.preset("al31f", roll_start=1.0, roll_end=1.5).compile()
    assert system.time_events == (1.0, 1.5)
