"""API 617 formulas on hand-worked examples, Level I Q_0 on a Jeffcott rotor, shear and moment closed forms."""

import math

import numpy as np
import pytest

from rotorkit.analysis.api617 import (
    amplification_factor,
    api617_audit,
    level1_stability,
    required_separation_margin,
    separation_margin,
    shear_moment,
    unbalance_magnitude,
    wachel_cross_coupling,
)
from rotorkit.linear.linear_model import LinearModel
from rotorkit.errors import ParameterError

RPM = math.pi / 30.0


def test_unbalance_magnitude_is_6350_w_over_n_g_mm():
    # W = 200 kg, N = 10000 rpm: U = 6350 x 200 / 10000 = 127 g mm = 1.27e-4 kg m
    assert unbalance_magnitude(200.0, 10000 * RPM) == pytest.approx(127e-6, rel=1e-12)
    assert unbalance_magnitude("200 kg", "10000 rpm") == pytest.approx(127e-6, rel=1e-12)
    # 4 W / N oz in with W in lb: the same rule in US units (1 oz in = 720.078 g mm, 1 lb = 0.453592 kg)
    assert unbalance_magnitude("441 lb", "10000 rpm") * 1e6 / 720.078 == pytest.approx(4 * 441 / 10000, rel=2e-3)


def test_docstring_examples_run():
    import doctest

    from rotorkit.audit import formulas

    failures, tried = doctest.testmod(formulas, verbose=False)
    assert tried >= 2 and failures == 0


def _sdof(zeta, r):
    return 1.0 / np.sqrt((1 - r**2) ** 2 + (2 * zeta * r) ** 2)


@pytest.mark.parametrize("zeta", [0.01, 0.03, 0.08])
def test_amplification_factor_of_a_single_degree_of_freedom(zeta):
    wn = 500.0
    r = np.linspace(0.5, 1.5, 20001)
    af = amplification_factor(wn * r, _sdof(zeta, r))
    # exact half-power points of the force-excited oscillator (|X|^2 = peak^2 / 2, peak = 1 / (2 zeta
    # sqrt(1 - zeta^2)) at r^2 = 1 - 2 zeta^2): r^2 = 1 - 2 zeta^2 -/+ 2 zeta sqrt(1 - zeta^2)
    lo2 = 1 - 2 * zeta**2 - 2 * zeta * math.sqrt(1 - zeta**2)
    hi2 = 1 - 2 * zeta**2 + 2 * zeta * math.sqrt(1 - zeta**2)
    peak = wn * math.sqrt(1 - 2 * zeta**2)
    assert af.critical_speed == pytest.approx(peak, rel=1e-6)
    assert af.lower == pytest.approx(wn * math.sqrt(lo2), rel=1e-6)
    assert af.upper == pytest.approx(wn * math.sqrt(hi2), rel=1e-6)
    assert af.factor == pytest.approx(peak / (wn * (math.sqrt(hi2) - math.sqrt(lo2))), rel=1e-5)
    assert af.factor == pytest.approx(1 / (2 * zeta), rel=2 * zeta)   # the API 684 approximation


def test_amplification_factor_without_a_peak_is_critically_damped():
    r = np.linspace(0.1, 2.0, 200)
    af = amplification_factor(r, 1.0 / (1 + r))
    assert af.factor == 0.0 and af.critically_damped


@pytest.mark.parametrize("af, above, expected", [
    (2.0, False, 0.0), (2.0, True, 0.0),                 # critically damped: no margin required
    (3.5, False, 17 * (1 - 1 / 2.0)), (3.5, True, 10 + 17 * (1 - 1 / 2.0)),
    (11.5, False, 17 * 0.9), (11.5, True, 10 + 17 * 0.9),
])
def test_required_separation_margin(af, above, expected):
    assert required_separation_margin(af, above) == pytest.approx(expected, rel=1e-12)


def test_separation_margin_from_the_operating_range():
    band = ("8000 rpm", "10500 rpm")
    assert separation_margin("6000 rpm", band) == (pytest.approx(25.0), False)
    assert separation_margin("12000 rpm", band) == (pytest.approx(100 * 1500 / 10500), True)
    margin, _ = separation_margin("9000 rpm", band)
    assert margin < 0   # inside the range


def test_wachel_cross_coupling_hand_worked_and_in_us_units():
    q, total = wachel_cross_coupling(["1.5 MW", "1.2 MW"], ["480 mm", "440 mm"], ["25 mm", "22 mm"], "10500 rpm",
                                     [1.2, 1.1])
    # q = B_c C P / (D H N) rho_d/rho_s, C = 60 / (2 pi) with N in rpm and SI base units
    C = 60 / (2 * math.pi)
    hand = [3 * C * 1.5e6 / (0.48 * 0.025 * 10500) * 1.2, 3 * C * 1.2e6 / (0.44 * 0.022 * 10500) * 1.1]
    assert q == pytest.approx(hand, rel=1e-12)
    assert total == pytest.approx(sum(hand), rel=1e-12)
    # the US form, C = 63 with hp, in, rpm -> klbf/in (1 klbf/in = 175126.8 N/m, 1 hp = 745.7 W)
    us = 3 * 63 * (1.5e6 / 745.7) / ((480 / 25.4) * (25 / 25.4) * 10500) * 1.2 * 175126.8
    assert q[0] == pytest.approx(us, rel=2e-3)


def _jeffcott(m=10.0, k=1e6, c=200.0):
    return LinearModel(mass=np.eye(2) * m, damping=np.eye(2) * c, stiffness=np.eye(2) * k,
                       coordinate_names=("x1", "y1"))


def test_level1_q0_of_a_cross_coupled_jeffcott_rotor():
    m, k, c = 10.0, 1e6, 200.0
    result = level1_stability(_jeffcott(m, k, c), "1000 rpm", "10 kN/m", [1])
    # m z'' + c z' + k z = i Q z (z = x + i y): the forward root reaches s = i sqrt(k/m) when Q = c sqrt(k/m)
    assert result.q_0 == pytest.approx(c * math.sqrt(k / m), rel=1e-6)
    zeta = c / (2 * math.sqrt(k * m))
    assert result.log_decrements[0] == pytest.approx(2 * math.pi * zeta / math.sqrt(1 - zeta**2), rel=1e-6)
    assert np.all(np.diff(result.log_decrements) < 0)     # more cross-coupling, less damping
    assert result.q_ratio == pytest.approx(result.q_0 / 1e4)
    assert result.passed == (result.q_ratio >= 2 and result.log_decrement_a >= 0.1)


def test_level1_q0_beyond_ten_q_a_is_found_by_extension():
    result = level1_stability(_jeffcott(), 100.0, 100.0, ["1"])   # 10 Q_A = 1 kN/m << Q_0 = 63 kN/m
    assert result.q_0 == pytest.approx(200.0 * math.sqrt(1e5), rel=1e-6)


@pytest.fixture(scope="module")
def simply_supported():
    """A pinned-pinned Euler-Bernoulli shaft of span L under its own weight and a central disk's."""
    from rotorkit import BeamSegment, Disk, ElasticSupport, Maneuver, Model, Rotor

    L, d, rho = 1.0, 0.05, 7800.0
    beam = dict(length=L / 2, outer_diameter=d, density=rho, youngs_modulus=2.1e11, shear_modulus=8e10,
                theory="euler-bernoulli")
    model = Model([Rotor(name="R", stations=(1, 2, 3), speed=0.0), BeamSegment(start=1, end=2, **beam),
                   BeamSegment(start=2, end=3, **beam), ElasticSupport(station=1, stiffness=1e12),
                   ElasticSupport(station=3, stiffness=1e12), Disk(station=2, mass=20.0, radius=0.1),
                   Maneuver.steady(gravity=9.81)])
    return model, L, rho * math.pi * d**2 / 4 * 9.81, 20.0 * 9.81


@pytest.mark.slow  # derives a small beam model (~10-30 s on a loaded machine)
def test_shear_and_moment_of_a_simply_supported_shaft(simply_supported):
    model, L, w, P = simply_supported
    s = shear_moment(model)
    z, V, M = s.positions, s.shear[:, 1], s.moment[:, 1]   # the y-z plane: gravity along -y
    assert np.allclose(s.shear[:, 0], 0, atol=1e-9) and np.allclose(s.moment[:, 0], 0, atol=1e-9)
    # reactions (w L + P) / 2; M = w z (L - z) / 2 + P z / 2 left of the disk: P L / 4 + w L^2 / 8 at mid-span
    assert V[0] == pytest.approx((w * L + P) / 2, rel=1e-6)
    middle = np.isclose(z, L / 2)
    assert M[middle] == pytest.approx(P * L / 4 + w * L**2 / 8, rel=1e-6)
    quarter = np.isclose(z, L / 4)
    assert M[quarter] == pytest.approx(w * (L / 4) * (3 * L / 4) / 2 + P * L / 8, rel=1e-6)
    # the disk's weight is a jump of -P in the shear at mid-span
    assert np.ptp(V[middle]) == pytest.approx(P, rel=1e-6)
    assert s.closure[0] < 1e-6 * P and s.closure[1] < 1e-6 * P * L
    assert s.max_moment() == (pytest.approx(L / 2), pytest.approx(P * L / 4 + w * L**2 / 8, rel=1e-6))


@pytest.mark.parametrize("call, match", [
    (lambda: unbalance_magnitude(-1.0, 1000.0), "journal_load"),
    (lambda: unbalance_magnitude(100.0, "0 rpm"), "max_continuous_speed"),
    (lambda: amplification_factor([3.0, 2.0, 1.0], [1.0, 2.0, 1.0]), "increasing"),
    (lambda: required_separation_margin(-1.0, True), "factor"),
    (lambda: separation_margin(100.0, (200.0, 100.0)), "operating_range"),
    (lambda: wachel_cross_coupling(["1 MW", "1 MW"], ["0.4 m"] * 3, "20 mm", "1000 rpm"), "impellers"),
    (lambda: wachel_cross_coupling("1 MW", "0 m", "20 mm", "1000 rpm"), "impeller_diameter"),
    (lambda: level1_stability(_jeffcott(), 100.0, -5.0, [1]), "q_a"),
    (lambda: level1_stability(_jeffcott(), 100.0, 5.0, ["7"]), "station"),
    (lambda: api617_audit(None, ("8000 rpm", "10000 rpm")), "q_a"),
    (lambda: api617_audit(None, ("8000 rpm", "10000 rpm"), q_a=1e6, trip_speed="9000 rpm"), "trip_speed"),
    (lambda: api617_audit(None, ("8000 rpm", "10000 rpm"), q_a=1e6, unbalance_factor=0.0), "unbalance_factor"),
])
def test_bad_input_is_a_named_error(call, match):
    with pytest.raises(ParameterError, match=match):
        call()


@pytest.mark.slow  # derives a small beam model
def test_critical_map_of_a_shaft_without_its_bearings():
    """Rigid-body modes on soft supports, the pinned-pinned beam on stiff ones (forward synchronous whirl).

    The beam has no rotary inertia of its sections but keeps their gyroscopic coupling (polar inertia
    rho I_p per length, I_p = 2 I): a forward synchronous whirl is stiffened by it. Bounce:
    sqrt(2 k / m); conical: sqrt((k L^2 / 2) / (m L^2 / 12 - m d^2 / 8)); pinned-pinned:
    (pi / L)^2 sqrt(E I / (rho A - rho I_p (pi / L)^2)).
    """
    from rotorkit import BeamSegment, LinearBearing, Model, Rotor
    from rotorkit.analysis.api617 import undamped_critical_map
    from rotorkit.linear.linear_model import linear_model

    L, d, rho, E = 1.0, 0.04, 7800.0, 2.1e11
    beam = dict(length=L / 2, outer_diameter=d, density=rho, youngs_modulus=E, shear_modulus=8e10,
                theory="euler-bernoulli", rotary_inertia=False, elements=4)
    model = Model([Rotor(name="R", stations=(1, 2, 3), speed=100.0), BeamSegment(start=1, end=2, **beam),
                   BeamSegment(start=2, end=3, **beam), LinearBearing(station=1, kxx=3e6, kyy=2e6),
                   LinearBearing(station=3, kxx=3e6, kyy=2e6)])
    linear = linear_model(model)
    area, inertia = math.pi * d**2 / 4, math.pi * d**4 / 64
    pinned = (math.pi / L) ** 2 * math.sqrt(E * inertia / (rho * area - rho * 2 * inertia * (math.pi / L) ** 2))
    cmap = undamped_critical_map(model, linear, {"linearbearing1": "1", "linearbearing3": "3"}, 1.5 * pinned,
                                 decades=(4, 3))
    mass = rho * area * L
    k = cmap.stiffnesses
    soft = int(np.argmin(k))
    # 200 N/m against a shaft of 48 EI / L^3 = 1.3 MN/m: rigid to ~1e-4
    assert cmap.speeds[soft, 0] == pytest.approx(math.sqrt(2 * k[soft] / mass), rel=1e-4)
    conical = math.sqrt(k[soft] * L**2 / 2 / (mass * L**2 / 12 - mass * d**2 / 8))
    assert cmap.speeds[soft, 1] == pytest.approx(conical, rel=1e-4)
    stiff = int(np.argmax(k))   # 3 GN/m: pinned ends to ~1e-3
    assert cmap.speeds[stiff, 0] == pytest.approx(pinned, rel=3e-3)
    assert cmap.speeds[stiff, 0] < pinned
    speeds, kxx = cmap.bearing_curves["linearbearing1 kxx"]
    assert np.allclose(kxx, 3e6) and np.allclose(cmap.bearing_curves["linearbearing3 kyy"][1], 2e6)
