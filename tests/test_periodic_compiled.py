"""The compiled path of small speed branches (rotorkit.periodic.fastpath) against the Python path and closed forms.

The Jeffcott rotor in a concentric rub stator (isotropic, no gravity): with
``z = x + i y`` a synchronous circle ``|Z| = r`` solves
``|k - m W^2 + i c W + k_r max(0, 1 - delta/r)| r = m e W^2`` (tests/test_periodic.py
derives it). Both paths must follow the same branch through its smooth fold
and its grazing corner, on that circle, with the same stability.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Model, Rotor, RubStator
from rotorkit.analysis.periodic import periodic_response
from rotorkit.periodic import fastpath
from rotorkit.periodic.continuation import ContinuationProblem
from rotorkit.periodic.hb import HarmonicBalance

pytest.importorskip("numba")

M, K, C, E = 2.0, 2.0e4, 4.0, 2.0e-5  # kg, N/m, N s/m, m
DELTA, KR = 1.0e-4, 2.0e4


def rub_model():
    return Model([Rotor(name="R", stations=(1,), speed=60.0),
                  Disk(station=1, mass=M, radius=0.1, eccentricity=E, torsion=False),
                  ElasticSupport(station=1, stiffness=K, damping=C),
                  RubStator(station=1, clearance=DELTA, contact_stiffness=KR, friction_coefficient=0.0)],
                 name="jeffrub")


def circle_residual(W, r):
    s = KR * max(0.0, 1.0 - DELTA / r)
    return (abs(K - M * W**2 + 1j * C * W + s) * r - M * E * W**2) / (M * E * W**2)


@pytest.fixture(scope="module", autouse=True)
def compile_on_first_use():
    """The kernels compiled on first use here (the default uses them only once compiled: compile_kernels)."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROTORKIT_PERIODIC_COMPILED", "1")
        yield


@pytest.fixture(scope="module")
def rub_system():
    return rub_model().compile(backend="c")


@pytest.fixture(scope="module")
def both(rub_system):
    """The branch by the compiled path and by the Python path (the compiled path switched off)."""
    compiled = periodic_response(rub_system, speeds=(60.0, 200.0), harmonics=3)
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
        reference = periodic_response(rub_system, speeds=(60.0, 200.0), harmonics=3)
    return compiled, reference


def test_the_compiled_path_is_chosen_where_it_applies(rub_system, monkeypatch):
    hb = HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=3)
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is not None
    # not for another parameter, a condensed or too large problem, the python back end, or when switched off
    assert fastpath.compiled_setup(ContinuationProblem(hb, "rub1_clearance")) is None
    big = HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=fastpath.MAX_UNKNOWNS)
    assert fastpath.compiled_setup(ContinuationProblem(big, "R_speed")) is None
    python = HarmonicBalance(rub_model().compile(backend="python"), speed_parameter="R_speed", harmonics=3)
    assert fastpath.compiled_setup(ContinuationProblem(python, "R_speed")) is None
    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is None
    monkeypatch.delenv("ROTORKIT_PERIODIC_COMPILED")
    monkeypatch.setattr(fastpath, "_numba_available", lambda: False)  # numba missing: the Python path
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is None


def test_compiled_branch_equals_the_python_branch(both):
    compiled, reference = both
    assert compiled.reason == reference.reason
    assert len(compiled) == len(reference) > 100
    assert np.allclose(compiled.parameter, reference.parameter, rtol=1e-8, atol=0)
    amplitude = float(np.max(np.abs(reference.coefficients)))
    assert np.max(np.abs(compiled.coefficients - reference.coefficients)) < 1e-8 * amplitude
    assert [b.kind for b in compiled.bifurcations] == [b.kind for b in reference.bifurcations] == ["fold",
                                                                                                  "grazing fold"]
    for a, b in zip(compiled.bifurcations, reference.bifurcations):
        assert a.index == b.index and abs(a.parameter - b.parameter) < 1e-8 * b.parameter
    assert np.array_equal(compiled.stable, reference.stable)
    assert (~compiled.stable).any() and compiled.stable.any()
    for mu, expected in zip(compiled.multipliers, reference.multipliers):
        assert np.max(np.min(np.abs(mu[:, None] - expected[None, :]), axis=1)) < 1e-8
    assert np.allclose(compiled.omega, reference.omega, rtol=1e-14)
    # the error estimate is a residual near rounding here: the same size, not the same digits
    assert np.max(compiled.residual_error) < 1e-8 and np.max(reference.residual_error) < 1e-8


def test_compiled_branch_lies_on_the_closed_form_circle(both):
    compiled = both[0]
    r = compiled.harmonic_amplitude("x1", 1)
    assert np.max(np.abs([circle_residual(W, ri) for W, ri in zip(compiled.parameter, r)])) < 1e-8
    assert np.any(r > 4 * DELTA) and np.any((r > DELTA) & (r < 1.2 * DELTA))  # through the contact and the corner
    # the grazing corner: where the linear circle's radius is the clearance, m e W^2 = delta |k - m W^2 + i c W|
    from scipy.optimize import brentq

    grazing = brentq(lambda W: M * E * W**2 - DELTA * abs(K - M * W**2 + 1j * C * W), 105.0, 120.0, xtol=1e-12)
    assert [b.kind for b in compiled.bifurcations][-1] == "grazing fold"
    assert abs(compiled.bifurcations[-1].parameter - grazing) < 1e-10 * grazing


def test_compiled_grazing_fold_equals_the_python_reference(rub_system, both):
    """The grazing fold located in one kernel call (fastpath.grazing_compiled) and by the Python reference
    (folds.grazing_point with compiled=False, its Newton solves and switch values one small kernel call each):
    the same steps, so the same value to the last bit; at the corner, and where the branch's ends cut the
    window (a piece of a single point)."""
    from rotorkit.periodic.folds import grazing_point

    compiled = both[0]
    problem = ContinuationProblem(HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=3), "R_speed")
    assert fastpath.compiled_setup(problem) is not None
    lam = np.asarray(compiled.parameter)
    Z = [np.ravel(z) for z in compiled.coefficients]
    i = [b.index for b in compiled.bifurcations if b.kind == "grazing fold"][0]
    for k in (i, i - 1, 0, len(lam) - 2):
        assert grazing_point(problem, lam, Z, k) == grazing_point(problem, lam, Z, k, compiled=False)
    assert grazing_point(problem, lam, Z, i) == compiled.bifurcations[-1].parameter


def test_compiled_progress_and_point_budget(rub_system):
    seen = []
    b = periodic_response(rub_system, speeds=(60.0, 200.0), harmonics=3, max_points=40,
                          progress=lambda count, value: seen.append((count, value)))
    assert len(b) == 40 and b.reason == "point budget of 40 points reached"
    assert [c for c, _ in seen] == list(range(2, 41))
    assert np.allclose([v for _, v in seen], b.parameter[1:], rtol=0, atol=0)


def test_compiled_branch_with_progress_equals_the_python_branch(rub_system, monkeypatch):
    """With a progress callback the kernel runs in calls of 16 points, each starting without the predictor's
    quadratic term; the reference does the same, point for point."""
    def run():
        seen = []
        return periodic_response(rub_system, speeds=(60.0, 200.0), harmonics=3, max_points=60, stability="none",
                                 progress=lambda count, value: seen.append(count)), seen
    compiled, seen = run()
    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
    reference, seen_reference = run()
    assert len(compiled) == len(reference) == 60 and seen == seen_reference
    assert np.allclose(compiled.parameter, reference.parameter, rtol=1e-8, atol=0)
    amplitude = float(np.max(np.abs(reference.coefficients)))
    assert np.max(np.abs(compiled.coefficients - reference.coefficients)) < 1e-8 * amplitude


def test_the_kernel_and_the_reference_share_the_predictor_settings():
    """The kernel bakes the predictor's curvature guard in as a global: it must be the reference's."""
    from rotorkit.periodic import compiled, continuation

    assert compiled.CURVATURE_SHARE == continuation.CURVATURE_SHARE


def test_small_eigensolver_against_lapack():
    import numba

    from rotorkit.periodic.eigen import eigenvalues

    @numba.njit
    def run(A):
        wr, wi = np.empty(A.shape[0]), np.empty(A.shape[0])
        ok = eigenvalues(A.copy(), wr, wi)
        return ok, wr, wi

    rng = np.random.default_rng(3)
    for m in (1, 2, 5, 28, 41):
        A = rng.standard_normal((m, m))
        A[: m // 2] *= 1e4  # badly scaled rows, as Hill's matrix has
        ok, wr, wi = run(A)
        expected = np.linalg.eigvals(A)
        got = wr + 1j * wi
        assert ok
        assert np.max([np.min(np.abs(got - e)) for e in expected]) < 1e-10 * np.max(np.abs(expected))
        assert np.max([np.min(np.abs(expected - g)) for g in got]) < 1e-10 * np.max(np.abs(expected))


def anisotropic_rub_system(eccentricity, damping, contact_stiffness):
    """Anisotropic bearing, gravity and a rub stator: orbits with many harmonics (contact over part of a period)."""
    from rotorkit import Maneuver
    from rotorkit.elements import LinearBearing

    return Model([Rotor(name="R", stations=(1,), speed=600.0),
                  Disk(station=1, mass=M, radius=0.1, eccentricity=eccentricity, torsion=False),
                  LinearBearing(station=1, kxx=1.2e6, kyy=1.0e6, cxx=damping, cyy=damping),
                  RubStator(station=1, clearance=1e-4, contact_stiffness=contact_stiffness, friction_coefficient=0.1),
                  Maneuver.steady(gravity=9.81)], name="anisorub").compile(backend="c")


def test_compiled_partial_rub_branch_and_error_estimates_equal_the_python_path(monkeypatch):
    system = anisotropic_rub_system(2e-5, 150.0, 1e6)
    compiled = periodic_response(system, speeds=(600.0, 700.0), harmonics=6)
    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
    reference = periodic_response(system, speeds=(600.0, 700.0), harmonics=6)
    assert len(compiled) == len(reference) and compiled.reason == reference.reason
    amplitude = float(np.max(np.abs(reference.coefficients)))
    assert np.max(np.abs(compiled.coefficients - reference.coefficients)) < 1e-8 * amplitude
    assert np.max(compiled.harmonic_share) > 1e-4  # many harmonics: the error estimates are not rounding
    # equal where the truncation error is real; near rounding (no contact yet) both are tiny
    assert np.allclose(compiled.residual_error, reference.residual_error, rtol=1e-6, atol=1e-9)
    assert np.max(reference.residual_error) > 1e-2
    assert np.array_equal(compiled.stable, reference.stable)
    for mu, expected in zip(compiled.multipliers, reference.multipliers):
        assert np.max(np.min(np.abs(mu[:, None] - expected[None, :]), axis=1)) < 1e-8


def test_compiled_hill_keeps_one_exponent_per_family_for_real_negative_multipliers():
    """Full annular rub offset by gravity past the critical speed: two real negative multipliers (exponents
    a +- i w/2, copies of each other); the compiled Hill selection must match the Python one."""
    from rotorkit.periodic.stability import hill_multipliers

    system = anisotropic_rub_system(3e-5, 30.0, 1e7).with_parameters(rub1_friction_coefficient=0.0)
    # steps short enough to follow this solution (longer ones may pass to another that coexists at 740 rad/s)
    rough = periodic_response(system, speeds=(600.0, 740.0), harmonics=4, stability="none", step=0.01, max_step=0.02)
    start = np.vstack([rough.coefficients[-1], np.zeros((12, 2))])
    from rotorkit.analysis.periodic import periodic_solution

    b = periodic_solution(system, harmonics=10, start=start, R_speed=740.0, stability="hill")
    hb = HarmonicBalance(system.with_parameters(R_speed=740.0), speed_parameter="R_speed", harmonics=10)
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is not None
    expected = hill_multipliers(hb, b.coefficients[0].ravel(), hb.frame())
    negative = expected[(np.abs(expected.imag) < 1e-9) & (expected.real < 0)]
    assert len(negative) == 2
    mu = b.multipliers[0]
    assert np.max(np.min(np.abs(mu[:, None] - expected[None, :]), axis=1)) < 1e-8
    assert np.max(np.min(np.abs(expected[:, None] - mu[None, :]), axis=1)) < 1e-8


def test_by_default_only_compiled_kernels_are_used(rub_system, both, monkeypatch):
    """Without $ROTORKIT_PERIODIC_COMPILED a first branch does not wait for the kernels' compilation: the compiled
    path is taken only once they are in the disk cache (compile_kernels), found there by a fresh process."""
    monkeypatch.delenv("ROTORKIT_PERIODIC_COMPILED")
    hb = HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=3)
    monkeypatch.setattr(fastpath, "kernels_compiled", lambda: False)
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is None
    monkeypatch.undo()
    monkeypatch.delenv("ROTORKIT_PERIODIC_COMPILED")
    fastpath._kernel.cache_clear()  # as a fresh process: only the disk cache (filled by the branches above)
    assert fastpath.kernels_compiled()
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is not None
    fastpath.compile_kernels(verbose=False)  # loads them from the disk cache
    assert fastpath._kernel.cache_info().currsize == len(fastpath.KINDS)


def kernel_points(hb, bounds, z_scale, max_points):
    """``(problem, points)``: the raw continuation output of the compiled kernel over ``bounds`` in the speed."""
    from rotorkit.periodic.continuation import ContinuationOptions, continue_branch

    problem = ContinuationProblem(hb, "R_speed")
    assert fastpath.compiled_setup(problem) is not None
    z0 = problem.solve(np.zeros(hb.size), bounds[0], tol=1e-10, max_iterations=50)
    return problem, continue_branch(problem, z0, bounds[0], bounds, z_scale=z_scale,
                                    options=ContinuationOptions(max_points=max_points))


def test_the_kernels_tangents_are_the_python_references_the_starts_included(rub_system):
    """Each point's tangent (scaled back to the unknowns' units) is the Python loop's, the start's too (the start
    tangent along the range, not the last point's); the parameter's component changes sign where the
    reference's does (at the first fold)."""
    from rotorkit.periodic.continuation import ContinuationOptions, continue_branch

    hb = HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=3)
    problem, points = kernel_points(hb, (60.0, 200.0), DELTA, 400)
    reference = continue_branch(ContinuationProblem(hb, "R_speed"), np.asarray(points.coefficients[0]), 60.0,
                                (60.0, 200.0), z_scale=DELTA, options=ContinuationOptions(max_points=400,
                                                                                         compiled=False))
    T, T_ref = np.asarray(points.tangents), np.asarray(reference.tangents)
    assert T.shape == T_ref.shape and len(T) > 100
    assert np.max(np.abs(T - T_ref)) < 1e-6 * np.max(np.abs(T_ref))
    assert T[0, -1] > 0 and abs(T[0, -1] - T[-1, -1]) > 1e-3 * abs(T[0, -1])  # the start's own, not the last's
    turns = np.flatnonzero(T[:-1, -1] * T[1:, -1] < 0)
    assert len(turns) >= 1 and np.array_equal(turns, np.flatnonzero(T_ref[:-1, -1] * T_ref[1:, -1] < 0))


def test_the_kernels_residual_scales_are_each_points_own_and_the_point_data_reuse_them(rub_system):
    """The continuation kernel computes each new point's residual scale (the corrector's for the next step, the
    Python reference's too); the per-point error estimates taken with them equal, to the bit, those that compute
    the scale at each point's parameter afresh."""
    problem, points = kernel_points(HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=3),
                                    (60.0, 200.0), DELTA, 80)
    lam = np.asarray(points.parameter)
    assert len(points.scales) == len(lam) == 80
    expected = [problem.frame(v).scale for v in lam]  # the Python reference's (hb.Frame), the start's too
    assert np.allclose(points.scales, expected, rtol=1e-13, atol=0)
    assert np.ptp(points.scales) > 0.5 * np.max(points.scales)  # they change along the branch (m e W^2)
    Z = np.reshape(points.coefficients, (len(lam), -1))
    reused = fastpath.point_data(problem, lam, Z, "none", 4, points.scales)
    fresh = fastpath.point_data(problem, lam, Z, "none", 4)
    assert np.array_equal(reused[1], fresh[1]) and np.all(fresh[1] > 0)
    wrong = fastpath.point_data(problem, lam, Z, "none", 4, 2.0 * np.asarray(points.scales))
    assert np.allclose(wrong[1][1:], fresh[1][1:] / 2.0, rtol=1e-12)  # the given scales are the ones used


def test_the_kernels_accelerations_are_each_points_own_and_the_error_estimates_reuse_them():
    """The continuation kernel keeps each new point's accelerations at its AFT samples (its last residual's):
    they equal the model's at the point's sampled states, and the error estimates taken with them (the
    estimate's grid holds the AFT samples) equal those that evaluate the model there afresh, to rounding; on a
    partial rub, whose estimates are truncation errors, not rounding."""
    hb = HarmonicBalance(anisotropic_rub_system(2e-5, 150.0, 1e6), speed_parameter="R_speed", harmonics=6)
    problem, points = kernel_points(hb, (600.0, 700.0), 1e-4, 40)
    lam = np.asarray(points.parameter)
    accelerations = np.asarray(points.accelerations)
    assert accelerations.shape == (len(lam), hb.samples, hb.n) and np.isnan(accelerations[0, 0, 0])
    known = ~np.isnan(accelerations[:, 0, 0])
    assert known[1:].all()  # every new point's last residual was at the point
    for i in np.flatnonzero(known)[::5]:
        frame = problem.frame(lam[i])
        expected = frame.accelerations(hb.states(points.coefficients[i], frame))[:, hb.n:]
        assert np.allclose(accelerations[i], expected, rtol=1e-12, atol=1e-12 * np.max(np.abs(expected)))
    Z = np.reshape(points.coefficients, (len(lam), -1))
    fresh = fastpath.point_data(problem, lam, Z, "none", 4, points.scales)[1]
    reused = fastpath.point_data(problem, lam, Z, "none", 4, points.scales, accelerations)[1]
    assert np.max(fresh) > 1e-2  # truncation errors
    assert np.allclose(reused, fresh, rtol=1e-9, atol=1e-12)
    moved = accelerations.copy()
    moved[:, 0, 0] += 1e3  # 1000 m/s^2 more at the first AFT sample: the estimates must see it
    assert np.all(fastpath.point_data(problem, lam, Z, "none", 4, points.scales, moved)[1][1:] > reused[1:])
