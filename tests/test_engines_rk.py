"""Tests of the compiled adaptive Runge-Kutta engine (rotorkit.engines.rk_numba)."""

import numpy as np
import pytest

numba = pytest.importorskip("numba")

from scipy.integrate import solve_ivp  # noqa: E402

from rotorkit.engines import rk_common  # noqa: E402
from rotorkit.engines import rk_numba as rk  # noqa: E402
from rotorkit.errors import ParameterError  # noqa: E402

METHODS = ["RK45", "DOP853"]


# ---------------------------------------------------------------------------
# Right-hand sides
# ---------------------------------------------------------------------------


@numba.njit
def oscillator(t, y, p, dydt):
    """y'' = -w^2 y with w = p[0]."""
    dydt[0] = y[1]
    dydt[1] = -p[0] * p[0] * y[0]


@numba.njit
def decay(t, y, p, dydt):
    """y_i' = -p_i y_i."""
    for i in range(y.size):
        dydt[i] = -p[i] * y[i]


@numba.njit
def duffing(t, y, p, dydt):
    """x'' + c x' + k x + k3 x^3 = f cos(w t), p = (c, k, k3, f, w)."""
    x = y[0]
    v = y[1]
    dydt[0] = v
    dydt[1] = -p[0] * v - p[1] * x - p[2] * x ** 3 + p[3] * np.cos(p[4] * t)


@numba.njit
def nan_after_half(t, y, p, dydt):
    """Exponential decay that returns NaN for t > 0.5."""
    if t > 0.5:
        dydt[0] = np.nan
    else:
        dydt[0] = -y[0]


@numba.njit
def blow_up(t, y, p, dydt):
    """y' = y^2: y = 1 / (1 - t) blows up at t = 1."""
    dydt[0] = y[0] * y[0]


@numba.njit
def raises_late(t, y, p, dydt):
    """A core that raises its own exception."""
    if t > 0.5:
        raise ValueError("core failure on purpose")
    dydt[0] = -y[0]


def duffing_py(t, y, p):
    """The Duffing right-hand side for scipy."""
    x, v = y
    return [v, -p[0] * v - p[1] * x - p[2] * x ** 3 + p[3] * np.cos(p[4] * t)]


DUFFING_P = np.array([0.3, 1.0, 0.5, 0.4, 1.1])  # hardening, periodic regime


# ---------------------------------------------------------------------------
# Accuracy against exact solutions
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_harmonic_oscillator_error_shrinks_with_rtol(method):
    w, t1 = 3.0, 10.0
    t_eval = np.linspace(0.0, t1, 201)
    exact = np.vstack([np.cos(w * t_eval), -w * np.sin(w * t_eval)])
    errors = []
    for rtol in (1e-4, 1e-7, 1e-10):
        sol = rk.integrate(oscillator, 0.0, t1, [1.0, 0.0], [w], t_eval,
                           method=method, rtol=rtol, atol=rtol * 1e-3)
        assert sol.status == 0, sol.message
        # error relative to the amplitude of each state (1 and w)
        err = np.max(np.abs(sol.y - exact) / np.array([[1.0], [w]]))
        assert err < 10 * rtol, (rtol, err)
        errors.append(err)
    assert errors[0] > errors[1] > errors[2]


@pytest.mark.parametrize("method", METHODS)
def test_exponential_decay_exact(method):
    rates = np.array([0.5, 2.0, 7.0])
    t_eval = np.linspace(0.0, 1.0, 51)
    exact = np.exp(-np.outer(rates, t_eval))
    for rtol in (1e-5, 1e-9):
        atol = 1e-14
        sol = rk.integrate(decay, 0.0, 1.0, np.ones(3), rates, t_eval,
                           method=method, rtol=rtol, atol=atol)
        assert sol.status == 0
        assert np.max(np.abs(sol.y - exact) / (rtol * exact + atol)) < 10
        assert sol.n_samples_done == t_eval.size


# ---------------------------------------------------------------------------
# Same error control as scipy
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("rtol", [1e-6, 1e-9])
def test_duffing_matches_scipy(method, rtol):
    t1 = 40.0
    atol = rtol * 1e-3
    y0 = [1.0, 0.0]
    t_eval = np.linspace(0.0, t1, 401)[1:]  # scipy adds dense stages for t0
    sol = rk.integrate(duffing, 0.0, t1, y0, DUFFING_P, t_eval, method=method,
                       rtol=rtol, atol=atol)
    ref = solve_ivp(duffing_py, (0.0, t1), y0, method=method, t_eval=t_eval,
                    rtol=rtol, atol=atol, args=(DUFFING_P,))
    steps = solve_ivp(duffing_py, (0.0, t1), y0, method=method, rtol=rtol,
                      atol=atol, args=(DUFFING_P,))
    assert sol.status == 0 and ref.status == 0
    # Identical controller: identical counts on this machine; allow a
    # rounding-induced difference of a couple of steps elsewhere.
    n_steps_scipy = steps.t.size - 1
    assert abs(sol.n_accepted - n_steps_scipy) <= max(2, 0.01 * n_steps_scipy)
    assert abs(sol.nfev - ref.nfev) <= 0.01 * ref.nfev
    amplitude = np.max(np.abs(ref.y), axis=1, keepdims=True)
    assert np.max(np.abs(sol.y - ref.y) / amplitude) < 5 * rtol
    assert sol.t_reached == t1
    np.testing.assert_allclose(sol.y_reached, ref.y[:, -1], rtol=0,
                               atol=5 * rtol * amplitude.max())


def test_coefficients_equal_scipy():
    rk_mod = pytest.importorskip("scipy.integrate._ivp.rk")
    coeffs = pytest.importorskip("scipy.integrate._ivp.dop853_coefficients")
    np.testing.assert_array_equal(rk_common.RK45_A, rk_mod.RK45.A)
    np.testing.assert_array_equal(rk_common.RK45_B, rk_mod.RK45.B)
    np.testing.assert_array_equal(rk_common.RK45_C, rk_mod.RK45.C)
    np.testing.assert_array_equal(rk_common.RK45_E, rk_mod.RK45.E)
    np.testing.assert_array_equal(rk_common.RK45_P, rk_mod.RK45.P)
    np.testing.assert_array_equal(rk_common.DOP853_A, coeffs.A)
    np.testing.assert_array_equal(rk_common.DOP853_B, coeffs.B)
    np.testing.assert_array_equal(rk_common.DOP853_C, coeffs.C)
    np.testing.assert_array_equal(rk_common.DOP853_E3, coeffs.E3)
    np.testing.assert_array_equal(rk_common.DOP853_E5, coeffs.E5)
    np.testing.assert_array_equal(rk_common.DOP853_D, coeffs.D)


# ---------------------------------------------------------------------------
# Output times, tolerances, edge cases
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_t_eval_endpoints(method):
    y0 = np.array([1.0, 0.0])
    t_eval = np.linspace(0.0, 2.0, 9)
    sol = rk.integrate(oscillator, 0.0, 2.0, y0, [2.0], t_eval, method=method)
    assert sol.status == 0
    assert sol.t is not None and np.array_equal(sol.t, t_eval)
    assert sol.y.shape == (2, 9)
    assert sol.n_samples_done == 9
    np.testing.assert_array_equal(sol.y[:, 0], y0)  # t0 sample is y0 itself
    np.testing.assert_array_equal(sol.y[:, -1], sol.y_reached)  # t1 sample
    assert sol.t_reached == 2.0
    np.testing.assert_allclose(sol.y[0], np.cos(2.0 * t_eval), atol=1e-5)


@pytest.mark.parametrize("method", METHODS)
def test_single_and_empty_t_eval(method):
    sol = rk.integrate(decay, 0.0, 1.0, [1.0], [1.0], [0.3], method=method,
                       rtol=1e-9, atol=1e-12)
    assert sol.y.shape == (1, 1) and sol.n_samples_done == 1
    assert abs(sol.y[0, 0] - np.exp(-0.3)) < 1e-8
    empty = rk.integrate(decay, 0.0, 1.0, [1.0], [1.0], [], method=method,
                         rtol=1e-9, atol=1e-12)
    assert empty.status == 0 and empty.y.shape == (1, 0)
    assert abs(empty.y_reached[0] - np.exp(-1.0)) < 1e-8


def test_zero_length_interval():
    sol = rk.integrate(decay, 1.0, 1.0, [2.0], [1.0], [1.0])
    assert sol.status == 0 and sol.n_accepted == 0
    assert sol.y[0, 0] == 2.0 and sol.y_reached[0] == 2.0


@pytest.mark.parametrize("method", METHODS)
def test_atol_array_matches_scipy(method):
    w = 3.0
    y0 = np.array([1e-3, 0.0])  # small amplitude: atol dominates the scale
    atol = np.array([1e-12, 1e-4])
    t_eval = np.linspace(0.1, 10.0, 100)
    sol = rk.integrate(oscillator, 0.0, 10.0, y0, [w], t_eval, method=method,
                       rtol=1e-6, atol=atol)
    ref = solve_ivp(lambda t, y: [y[1], -w * w * y[0]], (0.0, 10.0), y0,
                    method=method, t_eval=t_eval, rtol=1e-6, atol=atol)
    assert sol.status == 0
    assert abs(sol.nfev - ref.nfev) <= 0.01 * ref.nfev
    np.testing.assert_allclose(sol.y, ref.y, rtol=0, atol=1e-8)
    tight = rk.integrate(oscillator, 0.0, 10.0, y0, [w], t_eval,
                         method=method, rtol=1e-6, atol=1e-12)
    loose = rk.integrate(oscillator, 0.0, 10.0, y0, [w], t_eval,
                         method=method, rtol=1e-6, atol=1e-4)
    assert loose.n_accepted < sol.n_accepted < tight.n_accepted  # per component


# ---------------------------------------------------------------------------
# Failures are reported, never hang
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_nan_core_stops_with_status_minus_2(method):
    t_eval = np.linspace(0.0, 1.0, 11)
    sol = rk.integrate(nan_after_half, 0.0, 1.0, [1.0], None, t_eval,
                       method=method)
    assert sol.status == rk.STATUS_NON_FINITE
    assert "Non-finite" in sol.message
    assert 0.5 - 1e-6 < sol.t_reached <= 0.5
    assert np.all(np.isfinite(sol.y_reached))
    assert abs(sol.y_reached[0] - np.exp(-sol.t_reached)) < 1e-6
    done = sol.n_samples_done
    assert done == np.count_nonzero(t_eval <= sol.t_reached)
    assert done in (5, 6)  # t = 0.5 itself is reached only up to rounding
    assert np.all(np.isfinite(sol.y[:, :done]))
    assert np.all(np.isnan(sol.y[:, done:]))


@pytest.mark.parametrize("method", METHODS)
def test_finite_time_blow_up_reports_failure(method):
    sol = rk.integrate(blow_up, 0.0, 2.0, [1.0], None, [0.5, 1.5],
                       method=method)
    assert sol.status in (rk.STATUS_STEP_TOO_SMALL, rk.STATUS_NON_FINITE)
    assert 0.99 < sol.t_reached < 1.01  # the numerical solution may pass t=1
    assert sol.n_samples_done == 1
    assert abs(sol.y[0, 0] - 2.0) < 1e-5
    assert sol.message


def test_max_steps_exceeded():
    sol = rk.integrate(oscillator, 0.0, 100.0, [1.0, 0.0], [5.0], [50.0],
                       max_steps=20)
    assert sol.status == rk.STATUS_MAX_STEPS
    assert sol.n_accepted + sol.n_rejected == 20
    assert "max_steps=20" in sol.message
    assert sol.n_samples_done == 0 and np.isnan(sol.y[0, 0])


def test_core_exception_propagates():
    with pytest.raises(ValueError, match="on purpose"):
        rk.integrate(raises_late, 0.0, 1.0, [1.0], None, [1.0])


# ---------------------------------------------------------------------------
# Argument checking and compilation
# ---------------------------------------------------------------------------


def test_bad_arguments_raise_clear_errors():
    args = (decay, 0.0, 1.0, [1.0], [1.0], [0.5])
    with pytest.raises(ParameterError, match="method='RK23'"):
        rk.integrate(*args, method="RK23")
    with pytest.raises(ValueError, match="t1=-1.0"):
        rk.integrate(decay, 0.0, -1.0, [1.0], [1.0], [])
    with pytest.raises(ParameterError, match="t_eval"):
        rk.integrate(decay, 0.0, 1.0, [1.0], [1.0], [0.5, 1.5])
    with pytest.raises(ParameterError, match="sorted"):
        rk.integrate(decay, 0.0, 1.0, [1.0], [1.0], [0.5, 0.2])
    with pytest.raises(ParameterError, match="atol"):
        rk.integrate(*args, atol=[1e-6, 1e-6])
    with pytest.raises(ParameterError, match="atol"):
        rk.integrate(*args, atol=-1.0)
    with pytest.raises(ParameterError, match="first_step"):
        rk.integrate(*args, first_step=2.0)
    with pytest.raises(ParameterError, match="max_step"):
        rk.integrate(*args, max_step=0.0)
    with pytest.raises(ParameterError, match="y0"):
        rk.integrate(decay, 0.0, 1.0, [np.nan], [1.0], [])
    with pytest.raises(rk.CoreSignatureError, match="numba"):
        rk.integrate(lambda t, y, p, d: None, 0.0, 1.0, [1.0], [1.0], [])


def test_core_with_wrong_signature():
    @numba.njit
    def two_args(t, y):
        pass

    with pytest.raises(rk.CoreSignatureError, match="core"):
        rk.integrate(two_args, 0.0, 1.0, [1.0], [1.0], [])


def test_first_step_and_max_step_are_honoured():
    sol = rk.integrate(decay, 0.0, 1.0, [1.0], [1.0], [1.0], method="RK45",
                       first_step=1e-3, max_step=0.01)
    assert sol.status == 0
    assert sol.n_accepted >= 100


def test_loop_compiled_once_for_all_cores_and_methods():
    for method in METHODS:
        for core in (decay, oscillator):
            rk.integrate(core, 0.0, 0.1, [1.0, 0.0], [1.0, 1.0], [0.1],
                         method=method)
    assert len(rk._compiled_loop().signatures) == 1


# ---------------------------------------------------------------------------
# Pieces: pausing between steps changes nothing
# ---------------------------------------------------------------------------


def _in_pieces(method, t1, t_eval, steps, capacity):
    """The Duffing run as a caller of pause_after/sample_capacity would continue it."""
    y, start, first, ts, ys, pieces = np.array([1.0, 0.0]), 0.0, None, [], [], 0
    while True:
        rest = t_eval[np.searchsorted(t_eval, start, side="right" if ts else "left"):]
        sol = rk.integrate(duffing, start, t1, y, DUFFING_P, rest, method=method, rtol=1e-8, atol=1e-10,
                           first_step=first, pause_after=steps, sample_capacity=capacity)
        pieces += 1
        ts.append(sol.t[:sol.n_samples_done])
        ys.append(sol.y[:, :sol.n_samples_done])
        if sol.status != rk.STATUS_PAUSED:
            return sol, np.concatenate(ts), np.concatenate(ys, axis=1), pieces
        y, start, first = sol.y_reached, sol.t_reached, min(sol.h_next, t1 - sol.t_reached)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("steps, capacity", [(7, 10_000), (1000, 13), (3, 5)])
def test_a_run_paused_between_steps_and_continued_equals_one_run(method, steps, capacity):
    t1 = 30.0
    t_eval = np.linspace(0.0, t1, 3001)
    whole = rk.integrate(duffing, 0.0, t1, [1.0, 0.0], DUFFING_P, t_eval, method=method, rtol=1e-8, atol=1e-10)
    last, t, y, pieces = _in_pieces(method, t1, t_eval, steps, capacity)
    assert pieces > 10  # it really ran in pieces (by steps, by sample buffer, or both)
    assert last.status == rk.STATUS_SUCCESS
    np.testing.assert_array_equal(t, t_eval)  # every sample once
    # the same steps: equal to rounding (a step redone after a full buffer sees its time as t + h)
    np.testing.assert_allclose(y, whole.y, rtol=0, atol=1e-12 * np.abs(whole.y).max())
