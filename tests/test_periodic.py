"""Harmonic balance, continuation and Floquet stability against closed forms and independent computations.

- A linear rotor (anisotropic, cross-coupled, speed-dependent bearing): the
  harmonic balance equals :func:`rotorkit.analysis.unbalance.unbalance_response`
  and its Floquet multipliers are ``exp(lambda T)`` of the modal eigenvalues.
- The Jeffcott rotor in a concentric rub stator (isotropic, no gravity):
  with ``z = x + i y`` the RubStator force is ``-k_r (1 - delta/r)(1 + i mu) z``
  for ``r > delta``, so a synchronous circle ``z = Z e^{i W t}``, ``|Z| = r``, solves
  ``[k - m W^2 + i c W + k_r (1 - delta/r)(1 + i mu)] Z = m e W^2 e^{i phi}``;
  its modulus gives, for ``r > delta``, the quadratic
  ``[(k - m W^2 + k_r) r - k_r delta]^2 + [(c W + mu k_r) r - mu k_r delta]^2 = (m e W^2)^2``
  and for ``r <= delta`` the linear circle ``r = m e W^2 / |k - m W^2 + i c W|``.
  In the frame rotating at ``W`` the circle is an equilibrium, whose Jacobian
  eigenvalues ``s`` give the Floquet multipliers ``exp(s 2 pi / W)``.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Model, Rotor, RubStator
from rotorkit.elements import LinearBearing
from rotorkit.analysis.periodic import continuation, periodic_response, periodic_solution
from rotorkit.periodic import ConvergenceError, NoOscillatingInput
from rotorkit.periodic.hb import HarmonicBalance, newton
from rotorkit.periodic.stability import hill_multipliers, is_stable, monodromy_multipliers

M, K, C, E = 2.0, 2.0e4, 4.0, 2.0e-5  # kg, N/m, N s/m, m
DELTA, KR, MU = 1.0e-4, 2.0e4, 0.0
SPEEDS = (60.0, 200.0)


def rub_model(mu=MU, eccentricity=E):
    return Model([Rotor(name="R", stations=(1,), speed=60.0),
                  Disk(station=1, mass=M, radius=0.1, eccentricity=eccentricity, torsion=False),
                  ElasticSupport(station=1, stiffness=K, damping=C),
                  RubStator(station=1, clearance=DELTA, contact_stiffness=KR, friction_coefficient=mu)], name="jeffrub")


@pytest.fixture(scope="module")
def rub_system():
    return rub_model().compile(backend="c")


@pytest.fixture(scope="module")
def rub_branch(rub_system):
    return periodic_response(rub_system, speeds=SPEEDS, harmonics=3)


def circle_roots(W, mu=MU):
    """Radii (m) of all synchronous circles at speed W (closed form above)."""
    roots = []
    linear = M * E * W**2 / abs(K - M * W**2 + 1j * C * W)
    if linear <= DELTA:
        roots.append(linear)
    a1, b1 = K - M * W**2 + KR, -KR * DELTA
    a2, b2 = C * W + mu * KR, -mu * KR * DELTA
    A, B, Cq = a1 * a1 + a2 * a2, 2 * (a1 * b1 + a2 * b2), b1 * b1 + b2 * b2 - (M * E * W**2) ** 2
    disc = B * B - 4 * A * Cq
    if disc >= 0:
        roots += [r for r in ((-B - np.sqrt(disc)) / (2 * A), (-B + np.sqrt(disc)) / (2 * A)) if r > DELTA]
    return sorted(roots)


def circle_residual(W, r, mu=MU):
    """The circle equation's modulus residual relative to the unbalance force."""
    s = KR * max(0.0, 1.0 - DELTA / r)
    return (abs(K - M * W**2 + 1j * C * W + s * (1 + 1j * mu)) * r - M * E * W**2) / (M * E * W**2)


def rotating_multipliers(W, Z, mu=MU):
    """Floquet multipliers of the circle with complex amplitude Z (of x) from the rotating-frame Jacobian."""
    u, v = Z.real, Z.imag
    r = abs(Z)
    if r > DELTA:
        s, ds = KR * (1 - DELTA / r), KR * DELTA / r**2
        dFu = ds * (u / r) * (1 + 1j * mu) * Z + s * (1 + 1j * mu)
        dFv = ds * (v / r) * (1 + 1j * mu) * Z + s * (1 + 1j * mu) * 1j
    else:
        dFu = dFv = 0.0
    a_w, a_wd = (M * W**2 - 1j * C * W - K) / M, (-2j * M * W - C) / M
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1.0
    for col, d in ((0, a_w - dFu / M), (1, a_w * 1j - dFv / M), (2, a_wd), (3, a_wd * 1j)):
        A[2, col], A[3, col] = d.real, d.imag
    return np.exp(np.linalg.eigvals(A) * 2 * np.pi / W)


def nearest_distance(a, b):
    return float(np.max(np.min(np.abs(np.asarray(a)[:, None] - np.asarray(b)[None, :]), axis=1)))


# --- linear rotor -------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def linear_system():
    bearing = LinearBearing.tabulated(station=1, speeds=[0.0, 400.0], kxx=[2.0e4, 3.0e4], kyy=[1.5e4, 2.5e4],
                                      kxy=[1.0e3, 2.0e3], kyx=[-1.0e3, -3.0e3], cxx=[4.0, 6.0], cyy=[3.0, 5.0])
    return Model([Rotor(name="R", stations=(1,), speed=100.0),
                  Disk(station=1, mass=M, radius=0.1, eccentricity=E, phase=0.3, torsion=False), bearing],
                 name="linrotor").compile(backend="c")


def test_linear_rotor_equals_unbalance_response(linear_system):
    from rotorkit.analysis.unbalance import Unbalance, unbalance_response

    speeds = np.linspace(50.0, 250.0, 9)
    expected = unbalance_response(linear_system, [Unbalance(1, M * E, 0.3)], speeds, speed_parameter="R_speed")
    branch = continuation(linear_system, "R_speed", (50.0, 250.0), harmonics=2, stability="none")
    hb = HarmonicBalance(linear_system, speed_parameter="R_speed", harmonics=2)
    for i, W in enumerate(speeds):
        frame = hb.frame({"R_speed": W})
        z = newton(lambda z, j: hb.residual(z, frame, j), np.zeros(hb.size), tol=1e-12, scale=frame.scale)[0]
        Z = z.reshape(5, 2)
        for c, name in enumerate(("x1", "y1")):
            Q = expected.response(name)[i]
            scale = np.max(np.abs(expected.response(name)))
            assert abs(Z[1, c] - 1j * Z[2, c] - Q) <= 1e-10 * scale
            assert np.max(np.abs(Z[[0, 3, 4], c])) <= 1e-12 * scale
    # along the continued branch too (points where they fall)
    response = unbalance_response(linear_system, [Unbalance(1, M * E, 0.3)], branch.parameter,
                                  speed_parameter="R_speed").response("x1")
    assert np.max(np.abs(branch.complex_amplitude("x1", 1) - response)) <= 1e-9 * np.max(np.abs(response))
    assert branch.reason.startswith("parameter bound")
    assert branch.parameter[-1] == 250.0


def test_linear_multipliers_are_exponentials_of_modal_eigenvalues(linear_system):
    from rotorkit.analysis.linear_model import linear_model

    W = 140.0
    hb = HarmonicBalance(linear_system, speed_parameter="R_speed", harmonics=3)
    frame = hb.frame({"R_speed": W})
    z = newton(lambda z, j: hb.residual(z, frame, j), np.zeros(hb.size), tol=1e-12, scale=frame.scale)[0]
    eig = np.linalg.eigvals(linear_model(linear_system, speed_parameter="R_speed", speed=W).state_matrix(W))
    expected = np.exp(eig * 2 * np.pi / W)
    assert nearest_distance(monodromy_multipliers(hb, z, frame)[0], expected) < 1e-8
    assert nearest_distance(hill_multipliers(hb, z, frame), expected) < 1e-8


# --- Jeffcott rotor with a concentric rub stator -------------------------------------------------------------

def test_rub_branch_lies_on_the_closed_form_circles(rub_branch):
    b = rub_branch
    assert b.reason.startswith("parameter bound")
    r = b.harmonic_amplitude("x1", 1)
    errors = [circle_residual(W, ri) for W, ri in zip(b.parameter, r)]
    assert np.max(np.abs(errors)) < 1e-8
    # circles: y lags x by a quarter period, nothing but harmonic 1
    assert np.allclose(b.complex_amplitude("y1", 1), -1j * b.complex_amplitude("x1", 1), rtol=0, atol=1e-12)
    assert np.max(b.max_radius(1) - r) < 1e-12
    for k in (0, 2, 3):
        assert np.max(b.harmonic_amplitude("x1", k)) < 1e-14
    # the branch passes its smooth fold and its grazing corner: two turning points
    assert [f.kind for f in b.bifurcations] == ["fold", "grazing fold"]
    smooth, corner = b.bifurcations
    W = np.linspace(130.0, 145.0, 150001)  # the smooth fold: where the quadratic's discriminant vanishes
    a1, a2 = K - M * W**2 + KR, C * W + MU * KR
    disc = (a1 * KR * DELTA + a2 * MU * KR * DELTA) ** 2 - (a1**2 + a2**2) * (
        (KR * DELTA) ** 2 + (MU * KR * DELTA) ** 2 - (M * E * W**2) ** 2)
    upper = (-(a1 * -KR * DELTA + a2 * -MU * KR * DELTA) + np.sqrt(np.maximum(disc, 0))) / (a1**2 + a2**2)
    fold = W[np.flatnonzero((disc >= 0) & (upper > DELTA))[-1]]
    assert abs(smooth.parameter - fold) < 2e-3 * fold
    # the corner: the linear circle of radius delta, m e W^2 = delta |k - m W^2 + i c W| above the resonance
    from scipy.optimize import brentq

    grazing = brentq(lambda W: M * E * W**2 - DELTA * abs(K - M * W**2 + 1j * C * W), 105.0, 120.0, xtol=1e-12)
    assert abs(corner.parameter - grazing) < 1e-10 * grazing  # both pieces followed to the corner
    assert np.any(r > 4 * DELTA) and np.any((r > DELTA) & (r < 1.2 * DELTA))


def test_three_coexisting_circles_found(rub_system, rub_branch):
    W = 125.0
    expected = circle_roots(W)
    assert len(expected) == 3
    b = rub_branch
    hb = HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=3)
    frame = hb.frame({"R_speed": W})
    found = []
    for i in np.flatnonzero((b.parameter[:-1] - W) * (b.parameter[1:] - W) <= 0):
        w = (W - b.parameter[i]) / (b.parameter[i + 1] - b.parameter[i])
        guess = ((1 - w) * b.coefficients[i] + w * b.coefficients[i + 1]).ravel()
        z = newton(lambda z, j: hb.residual(z, frame, j), guess, tol=1e-12, scale=frame.scale)[0]
        found.append(np.hypot(z[2], z[4]))
    assert len(found) == 3
    assert np.allclose(sorted(found), expected, rtol=1e-8, atol=0)


def test_rub_stability_agrees_with_rotating_frame_and_methods(rub_system, rub_branch):
    b = rub_branch
    hb = HarmonicBalance(rub_system, speed_parameter="R_speed", harmonics=3)
    assert b.stable is not None and (~b.stable).any() and b.stable.any()
    for i in range(0, len(b), max(1, len(b) // 12)):
        W = b.parameter[i]
        frame = hb.frame({"R_speed": W})
        z = b.coefficients[i].ravel()
        expected = rotating_multipliers(W, b.complex_amplitude("x1", 1)[i])
        mono = monodromy_multipliers(hb, z, frame)[0]
        assert nearest_distance(b.multipliers[i], expected) < 1e-7
        assert nearest_distance(mono, expected) < 1e-7
        assert b.stable[i] == is_stable(expected)


def test_friction_rub_stability_from_the_rotating_frame():
    """With friction the contact circles destabilise: Hill still matches the rotating-frame eigenvalues."""
    b = periodic_response(rub_model(mu=0.05).compile(backend="c"), speeds=(80.0, 140.0), harmonics=2,
                          max_points=60)
    for i in range(0, len(b), 5):
        expected = rotating_multipliers(b.parameter[i], b.complex_amplitude("x1", 1)[i], mu=0.05)
        assert nearest_distance(b.multipliers[i], expected) < 1e-7
        assert abs(circle_residual(b.parameter[i], b.harmonic_amplitude("x1", 1)[i], mu=0.05)) < 1e-8


def contact_circle(W, mu):
    """The complex amplitude of x on the smaller contact circle (closed form above) at speed W."""
    r = [q for q in circle_roots(W, mu) if q > DELTA][0]
    return M * E * W**2 / (K - M * W**2 + 1j * C * W + KR * (1 - DELTA / r) * (1 + 1j * mu))


@pytest.mark.parametrize("mu", [0.05, 0.3])
def test_neimark_sacker_points_located_where_the_rotating_frame_says(mu, monkeypatch):
    """With friction the synchronous rub circle loses stability through a complex pair of multipliers: at a
    Hopf point of the contact circle just past the grazing speed (light friction), or at the grazing itself
    (the contact circle unstable from its first contact), and the unstable contact circle meets the stable
    linear one at the grazing corner. Both Neimark-Sacker points are located on the branch (root finding
    between its points, not an interpolation between points some rad/s apart). On the Python path, whose
    corrector a trial step at a negative speed used to stop with a ParameterError (now a failed trial)."""
    from scipy.optimize import brentq

    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
    b = periodic_response(rub_model(mu=mu).compile(backend="c"), speeds=SPEEDS, harmonics=3)
    found = sorted(x.parameter for x in b.bifurcations if x.kind == "Neimark-Sacker")
    assert len(found) == 2

    def linear_radius_past_clearance(W):
        return M * E * W**2 / abs(K - M * W**2 + 1j * C * W) - DELTA

    wn = np.sqrt(K / M)
    grazing_up, grazing_down = (brentq(linear_radius_past_clearance, lo, hi, xtol=1e-13)
                                for lo, hi in ((SPEEDS[0], wn), (wn, SPEEDS[1])))

    def growth(W):  # the largest rotating-frame multiplier's modulus less 1 on the contact circle
        return np.max(np.abs(rotating_multipliers(W, contact_circle(W, mu), mu))) - 1.0

    start = grazing_up * (1 + 1e-9)
    hopf = grazing_up if growth(start) > 0 else brentq(growth, start, 100.0, xtol=1e-12)
    assert found[0] == pytest.approx(hopf, rel=1e-7)
    assert (hopf > grazing_up) == (mu == 0.05)  # one case of each kind
    fold = next(x.parameter for x in b.bifurcations if x.kind == "fold")
    assert growth(0.5 * (grazing_down + fold)) > 0  # the smaller contact circle is unstable up to the corner
    assert found[1] == pytest.approx(grazing_down, rel=1e-9)


def test_continuation_in_the_clearance_and_the_point_budget(rub_system):
    """At 125 rad/s, clearance from 0.2 mm down: every point lies on the circle of its own clearance; where
    the clearance reaches the linear circle's radius the branch turns back at a grazing corner onto a
    contact circle (three coexist at 0.1 mm, see test_three_coexisting_circles_found) and leaves the range
    at 0.2 mm again."""
    W = 125.0
    system = rub_system.with_parameters(R_speed=W)
    b = continuation(system, "rub1_clearance", (2e-4, 2e-5), harmonics=2, stability="none")
    assert b.reason.startswith("parameter bound") and b.parameter[-1] in (2e-4, 2e-5)
    assert [f.kind for f in b.bifurcations] == ["grazing fold"]
    linear = M * E * W**2 / abs(K - M * W**2 + 1j * C * W)
    assert abs(b.bifurcations[0].parameter - linear) < 1e-8 * linear
    r = b.harmonic_amplitude("x1", 1)
    s = KR * np.maximum(0.0, 1.0 - b.parameter / r)
    residual = (np.abs(K - M * W**2 + 1j * C * W + s * (1 + 1j * MU)) * r - M * E * W**2) / (M * E * W**2)
    assert np.max(np.abs(residual)) < 1e-8
    assert np.any(r > b.parameter) and np.any(r < b.parameter)  # clear of the stator, then rubbing
    short = continuation(system, "rub1_clearance", (2e-4, 2e-5), harmonics=2, stability="none", max_points=5)
    assert len(short) == 5 and short.reason.startswith("point budget")


# --- partial rub: anisotropic bearing, gravity, contact over part of the period ------------------------------

def partial_rub_system():
    from rotorkit import Maneuver

    return Model([Rotor(name="R", stations=(1,), speed=650.0),
                  Disk(station=1, mass=M, radius=0.1, eccentricity=2e-5, torsion=False),
                  LinearBearing(station=1, kxx=1.2e6, kyy=1.0e6, cxx=150.0, cyy=150.0),
                  RubStator(station=1, clearance=1e-4, contact_stiffness=1e6, friction_coefficient=0.1),
                  Maneuver.steady(gravity=9.81)], name="partialrub").compile(backend="c")


def test_partial_rub_equals_settled_time_integration():
    from rotorkit import simulate

    system = partial_rub_system()
    W = 650.0
    T = 2 * np.pi / W
    t = np.linspace(396 * T, 400 * T, 2049)[:-1]
    run = simulate(system, (0.0, 400 * T), rtol=1e-11, atol=1e-14, sample_times=np.linspace(396 * T, 400 * T, 2049))
    x, y = run.y[0][:-1], run.y[1][:-1]
    r_time = np.max(np.hypot(x, y))

    def harmonic(signal, k):
        return 2 * np.mean(signal * np.exp(-1j * k * W * t))  # a_k - i b_k

    errors = []
    for H in (3, 6, 10):
        b = periodic_solution(system, harmonics=H, stability="none")
        errors.append(b.residual_error[0])
        if H == 10:
            assert abs(b.max_radius(1)[0] - r_time) <= 1e-4 * r_time
            for k in (1, 2, 3):
                for name, signal in (("x1", x), ("y1", y)):
                    assert abs(b.complex_amplitude(name, k)[0] - harmonic(signal, k)) <= 1e-4 * r_time
            assert abs(b.coefficients[0, 0, 1] - np.mean(y)) <= 1e-4 * r_time
            contact = np.hypot(*b.orbit(0, 1)) > 1e-4
            assert contact.any() and not contact.all()  # partial rub indeed
    assert errors[0] > errors[1] > errors[2]


def test_hill_keeps_one_exponent_per_family_for_real_negative_multipliers():
    """Full annular rub offset by gravity on an anisotropic bearing, past the critical speed: two real negative
    multipliers, whose Hill exponents a +- i w/2 are copies of each other; Hill must match the monodromy matrix."""
    from rotorkit import Maneuver
    from rotorkit.periodic.hb import HarmonicBalance

    system = Model([Rotor(name="R", stations=(1,), speed=600.0),
                    Disk(station=1, mass=M, radius=0.1, eccentricity=3e-5, torsion=False),
                    LinearBearing(station=1, kxx=1.2e6, kyy=1.0e6, cxx=30.0, cyy=30.0),
                    RubStator(station=1, clearance=1e-4, contact_stiffness=1e7, friction_coefficient=0.0),
                    Maneuver.steady(gravity=9.81)], name="annularrub").compile(backend="c")
    # steps short enough to follow this solution (longer ones may pass to another that coexists at 740 rad/s)
    rough = periodic_response(system, speeds=(600.0, 740.0), harmonics=4, stability="none", step=0.01, max_step=0.02)
    start = np.vstack([rough.coefficients[-1], np.zeros((16, 2))])
    b = periodic_solution(system, harmonics=12, start=start, R_speed=740.0, stability="hill")
    hb = HarmonicBalance(system.with_parameters(R_speed=740.0), speed_parameter="R_speed", harmonics=12)
    mono = monodromy_multipliers(hb, b.coefficients[0].ravel(), hb.frame())[0]
    negative = mono[(np.abs(mono.imag) < 1e-9) & (mono.real < 0)]
    assert len(negative) == 2 and abs(negative[0] - negative[1]) > 0.1
    assert nearest_distance(b.multipliers[0], mono) < 1e-6 and nearest_distance(mono, b.multipliers[0]) < 1e-6


def test_harmonics_raised_until_the_share_is_small():
    b = periodic_solution(partial_rub_system(), harmonics=2, error_tol=1e-4, stability="none")
    assert b.harmonic_share[0] <= 1e-4 and b.harmonics > 2


# --- condensation onto the contact coordinates --------------------------------------------------------------

def test_condensed_equals_full_harmonic_balance():
    """A chain of 4 disks (8 coordinates) with a rub at disk 3: condensed onto (x3, y3), expanded, the same."""
    stations = (1, 2, 3, 4)
    elements = [Rotor(name="R", stations=stations, speed=300.0)]
    for s in stations:
        elements += [Disk(station=s, mass=1.0, radius=0.05, eccentricity=1e-5 if s in (1, 4) else 0.0,
                          torsion=False), ElasticSupport(station=s, stiffness=1e6, damping=50.0)]
    elements += [LinearBearing(station=a, other_station=b, kxx=2e6, kyy=2e6, cxx=10.0, cyy=10.0)
                 for a, b in zip(stations, stations[1:])]
    elements.append(RubStator(station=3, clearance=3e-7, contact_stiffness=1e6, friction_coefficient=0.1))
    system = Model(elements, name="chain4").compile(backend="c")
    from rotorkit.periodic.condensed import nonlinear_coordinates

    assert nonlinear_coordinates(system.model) == ("x3", "y3")
    for W in (300.0, 350.0):
        condensed = periodic_solution(system, harmonics=3, condense=True, R_speed=W)
        full = periodic_solution(system, harmonics=3, condense=False, R_speed=W)
        assert condensed.max_radius(3)[0] > 3e-7  # in contact
        scale = np.max(np.abs(full.coefficients))
        assert np.max(np.abs(condensed.coefficients - full.coefficients)) < 1e-12 * scale
        assert nearest_distance(condensed.multipliers[0], full.multipliers[0]) < 1e-10
        assert condensed.residual_error[0] < 1e-8


# --- results ---------------------------------------------------------------------------------------------

def test_branch_results_roundtrip_and_plots(rub_branch, tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotorkit.periodic.branch import load_branch

    b = rub_branch
    x, y = b.orbit(5, 1)
    assert np.allclose(np.hypot(x, y), b.max_radius(1)[5], rtol=1e-9)
    ds = b.to_xarray()
    assert ds["coefficients"].shape == (len(b), 7, 2)
    b.save(tmp_path / "branch.nc")
    back = load_branch(tmp_path / "branch.nc")
    assert np.array_equal(back.coefficients, b.coefficients)
    assert np.array_equal(back.stable, b.stable)
    assert back.bifurcations == b.bifurcations
    fig, ax = plt.subplots()
    assert b.plot_response(1, ax=ax) is ax
    assert b.plot_orbit(3, 1) is plt.gca()
    assert b.plot_harmonics("x1", ax=ax) is ax
    plt.close("all")
    assert np.all(b.residual_error < 1e-8)


# --- bad input ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("call, error, match", [
    (lambda s: continuation(s, "rub1_clearence", (1e-4, 2e-4)), "ParameterError", "rub1_clearance"),
    (lambda s: periodic_response(s, speeds=(100.0, 100.0)), "ParameterError", "zero width"),
    (lambda s: periodic_response(s, speeds=(50.0, 100.0), harmonics=0), "ParameterError", "harmonics=0"),
    (lambda s: periodic_response(s, speeds=(50.0, 100.0), stability="floquet"), "ParameterError", "stability"),
    (lambda s: periodic_response(s, speeds=(50.0, 100.0), tol=1e-40), "ConvergenceError", "Newton"),
    (lambda s: periodic_response(s, speeds=("1 m", 100.0)), "UnitError", "rad/s"),
])
def test_bad_input(rub_system, call, error, match):
    import rotorkit.errors as errors_module
    import rotorkit.periodic.errors as periodic_errors

    cls = getattr(errors_module, error, None) or getattr(periodic_errors, error)
    with pytest.raises(cls, match=match):
        call(rub_system)


def test_no_oscillating_input():
    with pytest.raises(NoOscillatingInput, match="eccentricity"):
        periodic_solution(rub_model(eccentricity=0.0).compile(backend="c"), harmonics=2)


def test_convergence_error_is_named():
    with pytest.raises(ConvergenceError, match="start="):
        periodic_response(rub_model().compile(backend="c"), speeds=(60.0, 80.0), tol=1e-40)


def test_docstring_example_runs():
    import doctest

    import rotorkit.analysis.periodic as periodic

    failures, tried = doctest.testmod(periodic, verbose=False)
    assert tried > 0 and failures == 0


def test_a_systems_harmonic_balance_is_kept_per_settings_and_the_compiled_path_still_asked(rub_system, monkeypatch):
    """The harmonic balance of a system is kept for the next branch with the same settings (a system never
    changes), not across systems or settings; its kept compiled set-up never overrides the per-call choice of
    the Python path (ROTORKIT_PERIODIC_COMPILED=0)."""
    from rotorkit.analysis import periodic as analysis
    from rotorkit.periodic import fastpath
    from rotorkit.periodic.continuation import ContinuationProblem

    options = dict(speed_parameter="R_speed", harmonics=3, subharmonic=1, samples=None)
    hb = analysis._harmonic_balance(rub_system, "auto", **options)
    assert analysis._harmonic_balance(rub_system, "auto", **options) is hb
    assert analysis._harmonic_balance(rub_system, "auto", **dict(options, harmonics=4)) is not hb
    other = rub_system.with_parameters(R_speed=70.0)
    assert analysis._harmonic_balance(other, "auto", **options) is not hb
    kept = object()
    monkeypatch.setattr(hb, "_compiled_setup", kept, raising=False)
    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "0")
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is None
    monkeypatch.setenv("ROTORKIT_PERIODIC_COMPILED", "1")
    assert fastpath.compiled_setup(ContinuationProblem(hb, "R_speed")) is kept
