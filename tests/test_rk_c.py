"""Tests of the C integration loop (rotorkit.engines.rk_c): the numba loop's steps and results, without numba."""

import ctypes
import json
import os
import re
import subprocess
import sys
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorkit.codegen import cbuild
from rotorkit.engines import rk_c, rk_common
from rotorkit.errors import ParameterError

pytestmark = pytest.mark.skipif(cbuild.compiler() is None,
                                reason="no C compiler found (rk_c builds its loop with one: install gcc or set $CC)")

METHODS = ["RK45", "DOP853"]
DUFFING_P = np.array([0.3, 1.0, 0.5, 0.4, 1.1])  # hardening, periodic regime
STIFF_P = np.array([1e4, 0.05])  # coupling spring (1e4 against 1: modes at 1 and ~141 rad/s), damping

# Right-hand sides in C, and the same arithmetic (same order) for numba below.
CORES = r"""
#include <math.h>
void duffing(double t, const double *y, const double *p, double *d)
{
    const double x = y[0], v = y[1];
    d[0] = v;
    d[1] = -p[0] * v - p[1] * x - p[2] * (x * x * x) + p[3] * cos(p[4] * t);
}
void decay1(double t, const double *y, const double *p, double *d) { d[0] = -p[0] * y[0]; }
void decay3(double t, const double *y, const double *p, double *d)
{
    for (int i = 0; i < 3; i++)
        d[i] = -p[i] * y[i];
}
void stiff2(double t, const double *y, const double *p, double *d)
{
    const double stretch = y[0] - y[1];
    d[0] = y[2];
    d[1] = y[3];
    d[2] = -y[0] - p[0] * stretch - p[1] * y[2];
    d[3] = p[0] * stretch - p[1] * y[3];
}
void nan_after_half(double t, const double *y, const double *p, double *d) { d[0] = t > 0.5 ? NAN : -y[0]; }
void blow_up(double t, const double *y, const double *p, double *d) { d[0] = y[0] * y[0]; }
"""
NAMES = ("duffing", "decay1", "decay3", "stiff2", "nan_after_half", "blow_up")


@pytest.fixture(scope="module")
def c(tmp_path_factory):
    """The C cores' addresses by name (the library stays loaded for the module)."""
    lib = cbuild.library(tmp_path_factory.mktemp("cores"), "cores", CORES)
    cores = {name: ctypes.cast(getattr(lib, name), ctypes.c_void_p).value for name in NAMES}
    cores["_library"] = lib
    return cores


@pytest.fixture(scope="module")
def nb():
    """The same cores for numba's loop (the comparisons skip without numba)."""
    numba = pytest.importorskip("numba")
    from rotorkit.engines import rk_numba

    @numba.njit
    def duffing(t, y, p, d):
        x = y[0]
        v = y[1]
        d[0] = v
        d[1] = -p[0] * v - p[1] * x - p[2] * (x * x * x) + p[3] * np.cos(p[4] * t)

    @numba.njit
    def decay1(t, y, p, d):
        d[0] = -p[0] * y[0]

    @numba.njit
    def decay3(t, y, p, d):
        for i in range(3):
            d[i] = -p[i] * y[i]

    @numba.njit
    def stiff2(t, y, p, d):
        stretch = y[0] - y[1]
        d[0] = y[2]
        d[1] = y[3]
        d[2] = -y[0] - p[0] * stretch - p[1] * y[2]
        d[3] = p[0] * stretch - p[1] * y[3]

    @numba.njit
    def nan_after_half(t, y, p, d):
        d[0] = np.nan if t > 0.5 else -y[0]

    @numba.njit
    def blow_up(t, y, p, d):
        d[0] = y[0] * y[0]

    cores = {name: value for name, value in locals().items() if name in NAMES}
    cores["integrate"] = rk_numba.integrate
    return cores


def assert_same_run(a, b):
    """Two solutions took the same steps and agree to 1e-12 relative (NaN columns alike)."""
    assert (a.status, a.nfev, a.n_accepted, a.n_rejected, a.n_samples_done) == \
           (b.status, b.nfev, b.n_accepted, b.n_rejected, b.n_samples_done)
    assert a.message == b.message
    assert a.y.shape == b.y.shape
    np.testing.assert_array_equal(a.t, b.t)
    scale = max(np.abs(b.y[np.isfinite(b.y)]).max(initial=0.0), np.abs(b.y_reached).max())
    np.testing.assert_allclose(a.y, b.y, rtol=1e-12, atol=1e-12 * scale)
    np.testing.assert_allclose(a.y_reached, b.y_reached, rtol=1e-12, atol=1e-12 * scale)
    assert a.t_reached == pytest.approx(b.t_reached, rel=1e-12, abs=0)
    assert a.h_next == pytest.approx(b.h_next, rel=1e-12, abs=0, nan_ok=True)


# (core, t1, y0, p, t_eval, options)
PROBLEMS = {
    "duffing": ("duffing", 40.0, [1.0, 0.0], DUFFING_P, np.linspace(0.0, 40.0, 401), {}),
    "duffing-tight": ("duffing", 40.0, [1.0, 0.0], DUFFING_P, np.linspace(0.0, 40.0, 4001),
                      dict(rtol=1e-10, atol=1e-13)),
    "decay": ("decay3", 1.0, [1.0, 1.0, 1.0], [0.5, 2.0, 7.0], np.linspace(0.0, 1.0, 51),
              dict(rtol=1e-9, atol=1e-14)),
    "stiff": ("stiff2", 5.0, [1.0, 0.0, 0.0, 0.0], STIFF_P, np.linspace(0.0, 5.0, 101),
              dict(rtol=1e-7, atol=[1e-10, 1e-10, 1e-8, 1e-8])),
    "max-step": ("decay1", 1.0, [1.0], [1.0], [0.25, 1.0], dict(first_step=1e-3, max_step=0.01)),
    "non-finite": ("nan_after_half", 1.0, [1.0], None, np.linspace(0.0, 1.0, 11), {}),
    "blow-up": ("blow_up", 2.0, [1.0], None, [0.5, 1.5], {}),
    "step-too-small": ("decay1", 1.0, [0.0], [1.0], [0.5], dict(atol=0.0)),
    "max-steps": ("duffing", 100.0, [1.0, 0.0], DUFFING_P, [50.0], dict(max_steps=20)),
    "paused": ("duffing", 10.0, [1.0, 0.0], DUFFING_P, np.linspace(0.0, 10.0, 101), dict(pause_after=5)),
}


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("problem", sorted(PROBLEMS))
def test_same_steps_and_samples_as_the_numba_loop(c, nb, method, problem):
    core, t1, y0, p, t_eval, options = PROBLEMS[problem]
    a = rk_c.integrate(c[core], 0.0, t1, y0, p, t_eval, method=method, **options)
    b = nb["integrate"](nb[core], 0.0, t1, y0, p, t_eval, method=method, **options)
    assert_same_run(a, b)


@pytest.mark.parametrize("method", METHODS)
def test_exponential_decay_closed_form(c, method):
    rates = np.array([0.5, 2.0, 7.0])
    t_eval = np.linspace(0.0, 1.0, 51)
    exact = np.exp(-np.outer(rates, t_eval))
    for rtol in (1e-5, 1e-9):
        atol = 1e-14
        sol = rk_c.integrate(c["decay3"], 0.0, 1.0, np.ones(3), rates, t_eval, method=method, rtol=rtol, atol=atol)
        assert sol.status == 0 and sol.success and sol.n_samples_done == t_eval.size
        assert np.max(np.abs(sol.y - exact) / (rtol * exact + atol)) < 10
        np.testing.assert_array_equal(sol.y[:, 0], np.ones(3))  # the t0 sample is y0 itself
        np.testing.assert_array_equal(sol.y[:, -1], sol.y_reached)  # a sample at a step end is its state
        assert sol.t_reached == 1.0


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("rtol", [1e-6, 1e-9])
def test_duffing_and_stiff_chain_match_scipy(c, method, rtol):
    def duffing(t, y, p):
        x, v = y
        return [v, -p[0] * v - p[1] * x - p[2] * (x * x * x) + p[3] * np.cos(p[4] * t)]

    def stiff(t, y, p):
        stretch = y[0] - y[1]
        return [y[2], y[3], -y[0] - p[0] * stretch - p[1] * y[2], p[0] * stretch - p[1] * y[3]]

    for name, rhs, p, y0, t1 in (("duffing", duffing, DUFFING_P, [1.0, 0.0], 40.0),
                                 ("stiff2", stiff, STIFF_P, [1.0, 0.0, 0.0, 0.0], 5.0)):
        atol = rtol * 1e-3
        t_eval = np.linspace(0.0, t1, 401)[1:]  # scipy adds dense stages for t0
        sol = rk_c.integrate(c[name], 0.0, t1, y0, p, t_eval, method=method, rtol=rtol, atol=atol)
        ref = solve_ivp(rhs, (0.0, t1), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol, args=(p,))
        steps = solve_ivp(rhs, (0.0, t1), y0, method=method, rtol=rtol, atol=atol, args=(p,))
        assert sol.status == 0 and ref.status == 0
        n_steps = steps.t.size - 1  # the same controller: the same steps up to summation-order rounding
        assert abs(sol.n_accepted - n_steps) <= max(2, 0.01 * n_steps), name
        assert abs(sol.nfev - ref.nfev) <= 0.01 * ref.nfev, name
        amplitude = np.max(np.abs(ref.y), axis=1, keepdims=True)
        assert np.max(np.abs(sol.y - ref.y) / amplitude.max()) < 5 * rtol, name


# ---------------------------------------------------------------------------
# Statuses
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_non_finite_core_stops_with_status_minus_2_just_before_it(c, method):
    t_eval = np.linspace(0.0, 1.0, 11)
    sol = rk_c.integrate(c["nan_after_half"], 0.0, 1.0, [1.0], None, t_eval, method=method)
    assert sol.status == rk_c.STATUS_NON_FINITE == -2 and "Non-finite" in sol.message
    assert 0.5 - 1e-6 < sol.t_reached <= 0.5
    assert abs(sol.y_reached[0] - np.exp(-sol.t_reached)) < 1e-6
    done = sol.n_samples_done
    assert done == np.count_nonzero(t_eval <= sol.t_reached) and done in (5, 6)
    assert np.all(np.isfinite(sol.y[:, :done])) and np.all(np.isnan(sol.y[:, done:]))
    assert sol.n_rejected > 10  # the step shrank by 5 at a time onto t = 0.5


def test_a_non_finite_initial_derivative_stops_at_once(c):
    sol = rk_c.integrate(c["nan_after_half"], 0.75, 1.0, [1.0], None, [0.75, 1.0])
    assert sol.status == -2 and sol.nfev == 1 and sol.n_accepted == 0 and sol.t_reached == 0.75
    assert sol.n_samples_done == 1 and sol.y[0, 0] == 1.0 and np.isnan(sol.y[0, 1])


@pytest.mark.parametrize("method", METHODS)
def test_step_too_small_is_status_minus_1(c, method):
    """atol = 0 and a zero state: the error norm is 0/0, the step shrinks below 10 eps |t|."""
    sol = rk_c.integrate(c["decay1"], 0.0, 1.0, [0.0], [1.0], [0.5], method=method, atol=0.0)
    assert sol.status == rk_c.STATUS_STEP_TOO_SMALL == -1 and "step size" in sol.message
    assert sol.n_accepted == 0 and sol.n_samples_done == 0 and sol.t_reached == 0.0
    blow = rk_c.integrate(c["blow_up"], 0.0, 2.0, [1.0], None, [0.5, 1.5], method=method)
    assert blow.status in (-1, -2) and 0.99 < blow.t_reached < 1.01 and blow.n_samples_done == 1
    assert abs(blow.y[0, 0] - 2.0) < 1e-5


def test_max_steps_is_status_minus_3(c):
    sol = rk_c.integrate(c["duffing"], 0.0, 100.0, [1.0, 0.0], DUFFING_P, [50.0], max_steps=20)
    assert sol.status == rk_c.STATUS_MAX_STEPS == -3
    assert sol.n_accepted + sol.n_rejected == 20 and "max_steps=20" in sol.message
    assert sol.n_samples_done == 0 and np.isnan(sol.y[0, 0])


@pytest.mark.parametrize("method", METHODS)
def test_pause_after_is_status_minus_4(c, method):
    sol = rk_c.integrate(c["duffing"], 0.0, 10.0, [1.0, 0.0], DUFFING_P, [10.0], method=method, pause_after=5)
    assert sol.status == rk_c.STATUS_PAUSED == -4 and "Paused" in sol.message and not sol.success
    assert sol.n_accepted == 5 and 0.0 < sol.t_reached < 10.0 and sol.h_next > 0


def test_out_of_memory_is_status_minus_5(c, monkeypatch):
    """The loop's size check refuses a state too large to allocate; the front end reports it."""
    loop = rk_c._loop().rk_integrate
    one = np.ones(1)
    counters, reals = np.zeros(4, dtype=np.int64), np.zeros(2)
    status = loop(c["decay1"], 1, 0.0, 1.0, one.ctypes.data, 2 ** 62, one.ctypes.data, one.ctypes.data, 0, 1e-6,
                  one.ctypes.data, 0.0, np.inf, 100, 0, one.ctypes.data, 0, one.ctypes.data, counters.ctypes.data,
                  reals.ctypes.data)
    assert status == rk_c.STATUS_NO_MEMORY == -5
    assert counters.tolist() == [0, 0, 0, 0] and reals[0] == 0.0

    class NoMemory:
        @staticmethod
        def rk_integrate(*args):
            return rk_c.STATUS_NO_MEMORY

    monkeypatch.setattr(rk_c, "_loop", lambda: NoMemory)
    sol = rk_c.integrate(c["decay1"], 0.5, 1.0, [3.0], [1.0], [1.0])
    assert sol.status == -5 and "out of memory" in sol.message and not sol.success
    assert sol.y_reached.tolist() == [3.0]


# ---------------------------------------------------------------------------
# Output times, tolerances, edge cases
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("method", METHODS)
def test_empty_and_single_t_eval(c, method):
    empty = rk_c.integrate(c["decay1"], 0.0, 1.0, [1.0], [1.0], [], method=method, rtol=1e-9, atol=1e-12)
    assert empty.status == 0 and empty.y.shape == (1, 0) and empty.n_samples_done == 0
    assert abs(empty.y_reached[0] - np.exp(-1.0)) < 1e-8
    one = rk_c.integrate(c["decay1"], 0.0, 1.0, [1.0], [1.0], [0.3], method=method, rtol=1e-9, atol=1e-12)
    assert one.y.shape == (1, 1) and one.n_samples_done == 1 and abs(one.y[0, 0] - np.exp(-0.3)) < 1e-8
    assert empty.n_accepted == one.n_accepted  # samples never shorten steps
    assert one.nfev == empty.nfev + (3 if method == "DOP853" else 0)  # DOP853's dense stages for the sample


def test_zero_length_interval(c):
    sol = rk_c.integrate(c["decay1"], 1.0, 1.0, [2.0], [1.0], [1.0])
    assert sol.status == 0 and sol.n_accepted == 0 and sol.y[0, 0] == 2.0 and sol.y_reached[0] == 2.0


@pytest.mark.parametrize("method", METHODS)
def test_atol_vector_is_per_component(c, method):
    y0 = np.array([1e-3, 0.0])  # small amplitude: atol dominates the scale
    atol = np.array([1e-12, 1e-4])
    t_eval = np.linspace(0.1, 10.0, 100)
    p = [0.0, 9.0, 0.0, 0.0, 0.0]  # the Duffing core as x'' = -9 x
    sol = rk_c.integrate(c["duffing"], 0.0, 10.0, y0, p, t_eval, method=method, rtol=1e-6, atol=atol)
    ref = solve_ivp(lambda t, y: [y[1], -9.0 * y[0]], (0.0, 10.0), y0, method=method, t_eval=t_eval, rtol=1e-6,
                    atol=atol)
    assert sol.status == 0 and abs(sol.nfev - ref.nfev) <= 0.01 * ref.nfev
    np.testing.assert_allclose(sol.y, ref.y, rtol=0, atol=1e-8)
    tight = rk_c.integrate(c["duffing"], 0.0, 10.0, y0, p, t_eval, method=method, rtol=1e-6, atol=1e-12)
    loose = rk_c.integrate(c["duffing"], 0.0, 10.0, y0, p, t_eval, method=method, rtol=1e-6, atol=1e-4)
    assert loose.n_accepted < sol.n_accepted < tight.n_accepted


# ---------------------------------------------------------------------------
# Pieces and sample buffers
# ---------------------------------------------------------------------------


def _in_pieces(integrate, core, method, t1, t_eval, steps, capacity):
    """The Duffing run continued as simulate continues a paused one."""
    y, start, first, ts, ys, pieces = np.array([1.0, 0.0]), 0.0, None, [], [], 0
    while True:
        rest = t_eval[np.searchsorted(t_eval, start, side="right" if ts else "left"):]
        sol = integrate(core, start, t1, y, DUFFING_P, rest, method=method, rtol=1e-8, atol=1e-10,
                        first_step=first, pause_after=steps, sample_capacity=capacity)
        pieces += 1
        ts.append(sol.t[:sol.n_samples_done])
        ys.append(sol.y[:, :sol.n_samples_done])
        if sol.status != rk_c.STATUS_PAUSED:
            return sol, np.concatenate(ts), np.concatenate(ys, axis=1), pieces
        y, start, first = sol.y_reached, sol.t_reached, min(sol.h_next, t1 - sol.t_reached)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("steps, capacity", [(7, 10_000), (1000, 13), (3, 5)])
def test_pieces_continued_with_h_next_equal_one_run(c, method, steps, capacity):
    t1 = 30.0
    t_eval = np.linspace(0.0, t1, 3001)
    whole = rk_c.integrate(c["duffing"], 0.0, t1, [1.0, 0.0], DUFFING_P, t_eval, method=method, rtol=1e-8,
                           atol=1e-10)
    last, t, y, pieces = _in_pieces(rk_c.integrate, c["duffing"], method, t1, t_eval, steps, capacity)
    assert pieces > 10 and last.status == 0
    np.testing.assert_array_equal(t, t_eval)  # every sample once
    np.testing.assert_allclose(y, whole.y, rtol=0, atol=1e-12 * np.abs(whole.y).max())


@pytest.mark.parametrize("method", METHODS)
def test_pieces_equal_the_numba_loops_pieces(c, nb, method):
    t_eval = np.linspace(0.0, 30.0, 3001)
    a = _in_pieces(rk_c.integrate, c["duffing"], method, 30.0, t_eval, 3, 5)
    b = _in_pieces(nb["integrate"], nb["duffing"], method, 30.0, t_eval, 3, 5)
    assert a[3] == b[3]
    assert_same_run(a[0], b[0])
    np.testing.assert_allclose(a[2], b[2], rtol=1e-12, atol=1e-12 * np.abs(b[2]).max())


@pytest.mark.parametrize("method", METHODS)
def test_a_first_step_overflowing_the_buffer_enlarges_it(c, method):
    t_eval = np.linspace(0.0, 1.0, 10_001)  # hundreds of samples in the first step
    args = (c["decay1"], 0.0, 1.0, [1.0], [1.0], t_eval)
    plain = rk_c.integrate(*args, method=method, pause_after=1)
    sol = rk_c.integrate(*args, method=method, pause_after=1, sample_capacity=1)
    assert sol.status == plain.status == rk_c.STATUS_PAUSED and sol.n_accepted == 1
    columns = sol.y.shape[1]
    assert 1 < columns < t_eval.size and columns & (columns - 1) == 0  # doubled from 1 until the first step fits
    assert sol.t.size == columns and sol.n_samples_done == plain.n_samples_done <= columns
    assert t_eval[sol.n_samples_done - 1] <= sol.t_reached == plain.t_reached < t_eval[sol.n_samples_done]
    np.testing.assert_array_equal(sol.y[:, :sol.n_samples_done], plain.y[:, :sol.n_samples_done])
    # each start that paused at once cost one evaluation (the first two: it chose the step, which the others reuse)
    assert sol.nfev == plain.nfev + int(np.log2(columns)) and sol.n_rejected == plain.n_rejected


@pytest.mark.parametrize("method", METHODS)
def test_buffer_enlargement_counts_like_the_numba_loop(c, nb, method):
    t_eval = np.linspace(0.0, 1.0, 10_001)
    args = (0.0, 1.0, [1.0], [1.0], t_eval)
    a = rk_c.integrate(c["decay1"], *args, method=method, pause_after=2, sample_capacity=3)
    b = nb["integrate"](nb["decay1"], *args, method=method, pause_after=2, sample_capacity=3)
    assert_same_run(a, b)


# ---------------------------------------------------------------------------
# Arguments
# ---------------------------------------------------------------------------

BAD = [
    (dict(method="RK23"), "method='RK23'"),
    (dict(t1=-1.0, t_eval=[]), "t1=-1.0"),
    (dict(t0=float("nan")), "t0=nan"),
    (dict(t_eval=[0.5, 1.5]), "t_eval"),
    (dict(t_eval=[0.5, 0.2]), "sorted"),
    (dict(t_eval=[[0.5]]), "1-D"),
    (dict(atol=[1e-6, 1e-6]), "atol"),
    (dict(atol=-1.0), "atol"),
    (dict(rtol=-1.0), "rtol"),
    (dict(first_step=2.0), "first_step"),
    (dict(first_step=0.0), "first_step"),
    (dict(max_step=0.0), "max_step"),
    (dict(max_steps=0), "max_steps"),
    (dict(max_steps=1.5), "max_steps"),
    (dict(pause_after=-1), "pause_after=-1"),
    (dict(pause_after=3, sample_capacity="x"), "sample_capacity='x'"),
    (dict(pause_after=3, sample_capacity=0), "sample_capacity=0"),
    (dict(y0=[np.nan]), "y0"),
    (dict(y0=[]), "y0"),
]


def _call(integrate, core, changes):
    kwargs = dict(t0=0.0, t1=1.0, y0=[1.0], p=[1.0], t_eval=[0.5])
    kwargs.update(changes)
    return integrate(core, **kwargs)


@pytest.mark.parametrize("changes, match", BAD, ids=[str(i) for i in range(len(BAD))])
def test_bad_arguments_raise_the_numba_loops_errors(c, changes, match):
    with pytest.raises(ParameterError, match=re.escape(match)) as caught:
        _call(rk_c.integrate, c["decay1"], changes)
    try:
        import numba
    except ImportError:
        return
    from rotorkit.engines import rk_numba

    with pytest.raises(ParameterError) as expected:
        _call(rk_numba.integrate, numba.njit(lambda t, y, p, d: None), changes)
    assert str(caught.value) == str(expected.value)


@pytest.mark.parametrize("core", [None, 0, -4, True, 1.5, "rhs", lambda t, y, p, d: None])
def test_a_core_that_is_not_an_address_is_refused(core):
    with pytest.raises(rk_c.CoreSignatureError, match="address"):
        rk_c.integrate(core, 0.0, 1.0, [1.0], [1.0], [])


def test_a_ctypes_function_pointer_is_taken_as_its_address(c):
    by_pointer = rk_c.integrate(c["_library"].decay1, 0.0, 1.0, [1.0], [2.0], [1.0])
    by_address = rk_c.integrate(c["decay1"], 0.0, 1.0, [1.0], [2.0], [1.0])
    assert_same_run(by_pointer, by_address)


def test_a_tiny_rtol_is_raised_with_a_warning_pointing_at_the_caller(c):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        sol = rk_c.integrate(c["decay1"], 0.0, 1.0, [1.0], [1.0], [1.0], rtol=1e-20)
    assert sol.status == 0
    assert [w.filename for w in caught if "too small" in str(w.message)] == [__file__]


# ---------------------------------------------------------------------------
# The loop: tables, build, threads, no numba
# ---------------------------------------------------------------------------


def test_the_c_tables_are_rk_commons_to_the_last_bit():
    text = rk_c.source()
    assert "@GENERATED@" not in text
    for name, table in {"RK45_A": rk_common.RK45_A_SQ, "RK45_B": rk_common.RK45_B, "RK45_C": rk_common.RK45_C_EXT,
                        "RK45_E": rk_common.RK45_E, "RK45_PT": rk_common.RK45_PT, "DOP853_A": rk_common.DOP853_A,
                        "DOP853_B": rk_common.DOP853_B, "DOP853_C": rk_common.DOP853_C,
                        "DOP853_E3": rk_common.DOP853_E3, "DOP853_E5": rk_common.DOP853_E5,
                        "DOP853_D": rk_common.DOP853_D}.items():
        found = re.search(rf"static const double {name}((?:\[\d+\])+) = (\{{.*?\}});", text, re.S)
        assert found, name
        assert [int(d) for d in re.findall(r"\d+", found.group(1))] == list(table.shape), name
        values = [float(v) for v in re.findall(r"[-+0-9.eE]+", found.group(2))]
        np.testing.assert_array_equal(values, table.ravel(), err_msg=name)
    assert f"#define DIVERGED ({rk_common.DIVERGED!r})" in text
    assert f"#define STATUS_PAUSED ({rk_common.STATUS_PAUSED})" in text


def test_the_loop_is_built_once_into_the_private_cache():
    from rotorkit.codegen import cache

    assert rk_c._loop() is rk_c._loop()
    folder = cache.cache_dir() / "shared" / "rk_c_loop"
    assert (folder / "rk_loop.c").read_text() == rk_c.source()
    assert (folder / "rk_loop.so").is_file() and json.loads((folder / "rk_loop.sig.json").read_text())
    assert (folder.stat().st_mode & 0o077) == 0


def test_the_baseline_build_equals_the_one_this_processor_runs(c, tmp_path):
    """gcc builds the loop for any x86-64 and for AVX2 and the loader picks one: the other must agree bit for bit."""
    baseline = rk_c._Loop(cbuild.library(tmp_path, "rk_loop_baseline", "#define RK_ONE_VERSION 1\n" + rk_c.source()))
    for method in METHODS:
        for name, (core, t1, y0, p, t_eval, options) in PROBLEMS.items():
            picked = rk_c.integrate(c[core], 0.0, t1, y0, p, t_eval, method=method, **options)
            with pytest.MonkeyPatch.context() as patch:
                patch.setattr(rk_c, "_loop", lambda: baseline)
                other = rk_c.integrate(c[core], 0.0, t1, y0, p, t_eval, method=method, **options)
            assert (picked.nfev, picked.n_accepted, picked.n_rejected) == (other.nfev, other.n_accepted,
                                                                          other.n_rejected), name
            np.testing.assert_array_equal(picked.y, other.y, err_msg=name)
            np.testing.assert_array_equal(picked.y_reached, other.y_reached, err_msg=name)


def test_runs_in_threads_equal_runs_in_turn(c):
    amplitudes = [0.5, 1.0, 1.5, 2.0]

    def run(x0):
        return rk_c.integrate(c["duffing"], 0.0, 20.0, [x0, 0.0], DUFFING_P, np.linspace(0.0, 20.0, 201),
                              rtol=1e-9, atol=1e-12)

    in_turn = [run(x0) for x0 in amplitudes]
    with ThreadPoolExecutor(max_workers=2) as pool:
        threaded = list(pool.map(run, amplitudes))
    for a, b in zip(threaded, in_turn):
        assert (a.nfev, a.n_accepted) == (b.nfev, b.n_accepted)
        np.testing.assert_array_equal(a.y, b.y)


def test_integrating_in_c_does_not_import_numba(tmp_path):
    package_root = Path(rk_c.__file__).resolve().parents[2]  # the rotorkit this test imports
    code = f"""
import ctypes, json, sys
from rotorkit.codegen import cbuild
from rotorkit.engines import rk_c
lib = cbuild.library({str(tmp_path)!r}, "decay", "void rhs(double t, const double *y, const double *p, double *d)"
                     "{{ d[0] = -p[0] * y[0]; }}")
sol = rk_c.integrate(ctypes.cast(lib.rhs, ctypes.c_void_p).value, 0.0, 1.0, [1.0], [2.0], [0.5, 1.0])
assert sol.status == 0 and abs(sol.y[0, 1] - 0.1353352832366127) < 1e-7, sol
print(json.dumps([m for m in ("numba", "llvmlite", "sympy") if m in sys.modules]))
"""
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=package_root,
                         timeout=300, env=dict(os.environ, PYTHONPATH=str(package_root),
                                                     ROTORKIT_CACHE_DIR=str(tmp_path / "cache")))
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout.strip().splitlines()[-1]) == []
