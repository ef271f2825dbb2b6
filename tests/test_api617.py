"""API 617 formulas on hand-worked examples, Level I Q_0 on a Jeffcott rotor, shear and moment closed forms."""

import math

import numpy as np
import pytest

from rotorkit.analysis.api617 import (
    ANALYSIS_UNBALANCE_MULTIPLE,
    amplification_factor,
    amplitude_check,
    analysis_unbalance,
    api617_audit,
    clearance_scale_factor,
    level1_stability,
    outboard_masses,
    placements,
    required_separation_margin,
    separation_margin,
    shear_moment,
    unbalance_magnitude,
    vibration_limit,
    wachel_cross_coupling,
)
from rotorkit.audit.clearance import close_clearances_si, probe_stations
from rotorkit.linear.linear_model import LinearModel
from rotorkit.errors import ParameterError

RPM = math.pi / 30.0


def test_unbalance_magnitude_is_6350_w_over_n_g_mm():
    # W = 200 kg, N = 10000 rpm: U = 6350 x 200 / 10000 = 127 g mm = 1.27e-4 kg m
    assert unbalance_magnitude(200.0, 10000 * RPM) == pytest.approx(127e-6, rel=1e-12)
    assert unbalance_magnitude("200 kg", "10000 rpm") == pytest.approx(127e-6, rel=1e-12)
    # 4 W / N oz in with W in lb: the same rule in US units (1 oz in = 720.078 g mm, 1 lb = 0.453592 kg)
    assert unbalance_magnitude("441 lb", "10000 rpm") * 1e6 / 720.078 == pytest.approx(4 * 441 / 10000, rel=2e-3)
    # above 25000 rpm N is held at 25000: W = 200 kg, N = 30000 rpm -> 6350 x 200 / 25000 = 50.8 g mm
    assert unbalance_magnitude(200.0, 30000 * RPM) == pytest.approx(50.8e-6, rel=1e-12)


def test_the_analysis_applies_twice_the_residual_unbalance():
    # API 617 (7th ed. 2.6.2.7, 8th 4.8.2.7, 9th 6.8.2.7): 2 x U_r; W = 200 kg, N = 10000 rpm: 2 x 127 = 254 g mm
    assert ANALYSIS_UNBALANCE_MULTIPLE == 2.0
    assert analysis_unbalance(200.0, 10000 * RPM) == pytest.approx(254e-6, rel=1e-12)
    assert analysis_unbalance(200.0, 10000 * RPM, multiple=4) == pytest.approx(508e-6, rel=1e-12)


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
    # AF = 30: 17 (1 - 1 / 28.5) = 16.40 -> the ceiling 16 below, 26.40 -> 26 above; AF = 18.5 meets both exactly
    (30.0, False, 16.0), (30.0, True, 26.0), (18.5, False, 16.0), (18.5, True, 26.0),
])
def test_required_separation_margin(af, above, expected):
    assert required_separation_margin(af, above) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("n_rpm, expected_um", [
    (20000, 25.4 * math.sqrt(12000 / 20000)),   # 25.4 x 0.774597 = 19.6748 um
    (48000, 12.7),                              # 25.4 x sqrt(1/4)
    (12000, 25.4),                              # the formula meets the cap
    (6000, 25.4),                               # 25.4 x sqrt(2) = 35.9, capped at 25.4
])
def test_vibration_limit_a_vl(n_rpm, expected_um):
    assert vibration_limit(n_rpm * RPM) == pytest.approx(expected_um * 1e-6, rel=1e-12)
    assert vibration_limit(f"{n_rpm} rpm") == pytest.approx(expected_um * 1e-6, rel=1e-12)


def test_clearance_scale_factor_is_clipped():
    assert clearance_scale_factor(25.4e-6, 12.7e-6) == pytest.approx(2.0)          # 25.4 / 12.7
    assert clearance_scale_factor(25.4e-6, 2e-6) == 6.0                            # 12.7 -> 6
    assert clearance_scale_factor(25.4e-6, 100e-6) == 0.5                          # 0.254 -> 0.5
    assert clearance_scale_factor(25.4e-6, 100e-6, limits=None) == pytest.approx(0.254)


def _triangle(w, centre, height, width=50.0):
    return height * np.clip(1 - np.abs(w - centre) / width, 0, None)


def test_amplitude_check_hand_worked():
    """Probes against A_vl in the operating range; close clearances scaled by S_cc up to the trip speed."""
    w = np.linspace(0.0, 1200.0, 1201)        # rad/s, 1 rad/s steps
    amplitudes = {
        "2": np.full_like(w, 10e-6),                                       # 10 um everywhere
        "8": _triangle(w, 900.0, 20e-6) + _triangle(w, 500.0, 40e-6),      # 20 um at 900; 40 um at 500 (outside)
        "5": _triangle(w, 1040.0, 100e-6) + _triangle(w, 1150.0, 500e-6, 20.0),   # 500 um beyond the trip speed
        "6": _triangle(w, 1040.0, 150e-6),
    }
    # operating 800..1000 rad/s; N_mc = 1000 rad/s = 9549 rpm < 12000: A_vl = 25.4 um
    # A_max = 20 um (probe 8 at 900 rad/s; its 40 um at 500 is below the operating range) < 25.4: pass
    # S_cc = 25.4 / 20 = 1.27; trip 1050 rad/s
    # st. 5: 1.27 x 100 = 127 um (its 500 um peak at 1150 > trip is not counted) < 0.75 x 200 = 150 um: pass
    # st. 6: 1.27 x 150 = 190.5 um > 0.75 x 250 = 187.5 um: fail
    check = amplitude_check(w, amplitudes, ("2", "8"), (800.0, 1000.0), 1050.0, 1000.0, {"5": 200e-6, "6": 250e-6})
    assert check.vibration_limit == pytest.approx(25.4e-6)
    assert check.max_amplitude == pytest.approx(20e-6) and check.probe == "8" and check.speed == 900.0
    assert check.probes_passed
    assert check.scale_factor == pytest.approx(1.27)
    five, six = check.clearances
    assert five.amplitude == pytest.approx(127e-6) and five.limit == pytest.approx(150e-6) and five.passed
    assert five.speed == 1040.0
    assert six.amplitude == pytest.approx(190.5e-6) and six.limit == pytest.approx(187.5e-6) and not six.passed
    assert not check.passed
    # N_mc = 20000 rpm: A_vl = 19.67 um < A_max = 20 um: the probes fail
    fast = amplitude_check(w, amplitudes, ("2", "8"), (800.0, 1000.0), 1050.0, 20000 * RPM)
    assert fast.vibration_limit == pytest.approx(19.6748e-6, rel=1e-5) and not fast.probes_passed
    assert fast.clearances == ()


# stations 1..9 at z = 0, 0.1, ..., 0.8 m; bearings at 2 (z = 0.1) and 8 (z = 0.7); stations 1 and 9 outboard
_STATIONS = [str(i) for i in range(1, 10)]
_POSITIONS = {s: 0.1 * i for i, s in enumerate(_STATIONS)}
_BEARINGS = {"b2": 0.1, "b8": 0.7}
_LOADS = {"b2": 100.0, "b8": 150.0}
_NAMES = [f"{c}{s}" for s in _STATIONS for c in "xy"]


def _shape(v):
    """A forward circular mode shape whose x-plane deflection is ``v``: y = -i x."""
    out = np.zeros(len(_NAMES), dtype=complex)
    for s, value in zip(_STATIONS, v):
        out[_NAMES.index(f"x{s}")] = value
        out[_NAMES.index(f"y{s}")] = -1j * value
    return out * np.exp(0.7j)   # an arbitrary phase of the eigenvector


def _place(v, outboard=(0.0, 0.0)):
    return placements(_shape(v), _NAMES, _STATIONS, _POSITIONS, _LOADS, _BEARINGS, 10000 * RPM, outboard=outboard)


def test_placement_of_a_first_mode_is_mid_span_with_all_the_journal_load():
    # half sine between the bearings; the bare stubs (st. 1, 9) bend the other way and get nothing
    v = [-0.4, 0.0, 0.5, 0.87, 1.0, 0.87, 0.5, 0.0, -0.4]
    p = _place(v)
    # one unbalance at the largest displacement, W = 100 + 150 kg: 2 x 6350 x 250 / 10000 = 317.5 g mm
    assert [u.station for u in p.unbalances] == ["5"] and p.kinds == ("mid-span",)
    assert p.unbalances[0].magnitude == pytest.approx(317.5e-6, rel=1e-12)
    assert p.unbalances[0].angle == 0.0 and p.loads == (250.0,)


def test_placement_of_a_conical_mode_is_out_of_phase_with_the_nearest_journal_loads():
    v = [-0.2, 0.0, 0.7, 1.0, 0.5, -0.5, -0.95, 0.0, 0.2]
    p = _place(v)
    # st. 4 (z = 0.3, nearest b2: 100 kg): 2 x 6350 x 100 / 10000 = 127 g mm at 0 deg;
    # st. 7 (z = 0.6, nearest b8: 150 kg): 190.5 g mm at 180 deg
    assert [u.station for u in p.unbalances] == ["4", "7"]
    assert [u.magnitude for u in p.unbalances] == pytest.approx([127e-6, 190.5e-6], rel=1e-12)
    assert [u.angle for u in p.unbalances] == [0.0, math.pi]
    assert p.loads == (100.0, 150.0) and "out of phase" in p.rule
    # the sign of the eigenvector does not matter: the largest lobe (st. 4) is put at 0 degrees
    q = _place([-x for x in v])
    assert [(u.station, u.angle) for u in q.unbalances] == [("4", 0.0), ("7", math.pi)]


def test_placement_on_an_unloaded_journal_takes_the_whole_rotor_weight():
    v = [-0.2, 0.0, 0.7, 1.0, 0.5, -0.5, -0.95, 0.0, 0.2]
    p = placements(_shape(v), _NAMES, _STATIONS, _POSITIONS, {"b2": 0.0, "b8": 150.0}, _BEARINGS, 10000 * RPM)
    # st. 4's nearest journal (b2) carries nothing: W = 0 + 150 kg; st. 7's is b8: 150 kg
    assert p.loads == (150.0, 150.0) and "b2 carries none" in p.rule


def test_placement_on_overhung_ends_uses_the_overhung_mass():
    # a disk outboard of the right bearing (40 kg outboard): the mode peaks at the shaft end
    p = _place([0.0, 0.0, 0.05, 0.1, 0.1, 0.05, 0.0, 0.3, 1.0], outboard=(0.0, 40.0))
    assert [u.station for u in p.unbalances] == ["9"] and p.kinds == ("overhung",)
    assert p.unbalances[0].magnitude == pytest.approx(2 * 6350 * 40 / 10000 * 1e-6, rel=1e-12)   # 50.8 g mm
    # both ends overhung and moving together: in phase at the two ends (the small inner lobe < 30 % dropped)
    p = _place([1.0, 0.4, -0.1, -0.2, -0.2, -0.1, 0.3, 0.5, 0.9], outboard=(30.0, 40.0))
    assert [(u.station, u.angle) for u in p.unbalances] == [("1", 0.0), ("9", 0.0)]
    assert p.loads == (30.0, 40.0) and "in phase" in p.rule
    # ... and against each other: out of phase
    p = _place([1.0, 0.4, 0.1, 0.05, 0.0, -0.05, -0.3, -0.5, -0.9], outboard=(30.0, 40.0))
    assert [(u.station, u.angle) for u in p.unbalances] == [("1", 0.0), ("9", math.pi)]


def test_outboard_masses_count_an_end_only_when_a_disk_hangs_on_it():
    from rotorkit.linear.linear_matrices import station_positions

    d, rho = 0.05, 7800.0
    model = _overhung_model()
    positions = station_positions(model)
    left, right = outboard_masses(model, positions, {"b2": positions["2"], "b3": positions["3"]})
    # left: a bare 0.1 m stub, not overhung -> 0; right: 0.2 m of shaft (rho pi d^2 / 4 x 0.2 = 3.063 kg) + 10 kg
    assert left == 0.0
    assert right == pytest.approx(rho * math.pi * d**2 / 4 * 0.2 + 10.0, rel=1e-12)


def _overhung_model():
    from rotorkit import BeamSegment, Disk, LinearBearing, Maneuver, Model, Rotor

    beam = dict(outer_diameter=0.05, density=7800.0, youngs_modulus=2.1e11, shear_modulus=8e10)
    return Model([Rotor(name="R", stations=(1, 2, 3, 4), speed=0.0),
                  BeamSegment(start=1, end=2, length=0.1, **beam), BeamSegment(start=2, end=3, length=0.5, **beam),
                  BeamSegment(start=3, end=4, length=0.2, **beam), LinearBearing(station=2, kxx=1e8, kyy=1e8),
                  LinearBearing(station=3, kxx=1e8, kyy=1e8), Disk(station=4, mass=10.0, radius=0.1),
                  Maneuver.steady(gravity=9.81)])


@pytest.mark.parametrize("keywords, match", [
    (dict(probes=["2", "99"]), r"probes=.*\['99'\] unknown"),
    (dict(close_clearances={"3": "-0.2 mm"}), r"close_clearances\['3'\]"),
    (dict(close_clearances={"7": "0.2 mm"}), "station '7' unknown"),
])
def test_audit_names_bad_probes_and_clearances_before_any_analysis(keywords, match):
    with pytest.raises(ParameterError, match=match):
        api617_audit(_overhung_model(), ("8000 rpm", "10000 rpm"), q_a=1e6, **keywords)


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
    (lambda: api617_audit(None, ("8000 rpm", "10000 rpm"), q_a=1e6, unbalance_multiple=0.0), "unbalance_multiple"),
    (lambda: api617_audit(None, ("10000 rpm", "8000 rpm"), q_a=1e6), "operating_range"),   # speeds out of order
    (lambda: api617_audit(None, ("8000 rpm", "10000 rpm"), q_a=1e6, scale_factor_limits=(6, 0.5)),
     "scale_factor_limits"),
    (lambda: analysis_unbalance(100.0, 1000.0, multiple=-2), "multiple"),
    (lambda: vibration_limit("0 rpm"), "max_continuous_speed"),
    (lambda: clearance_scale_factor(25.4e-6, 0.0), "max_amplitude"),
    (lambda: close_clearances_si({"5": "-0.1 mm"}, ["4", "5"]), r"close_clearances\['5'\]"),   # negative
    (lambda: close_clearances_si({"5": 0.0}, ["4", "5"]), "positive diametral"),
    (lambda: close_clearances_si({"9": "0.3 mm"}, ["4", "5"]), "station '9' unknown"),
    (lambda: close_clearances_si({"5": "3 kg"}, ["4", "5"]), "close_clearances"),              # not a length
    (lambda: probe_stations(["4", "99"], ["4", "5"]), r"probes=.*\['99'\] unknown"),
    (lambda: placements(_shape([1.0] * 9), _NAMES, _STATIONS, _POSITIONS, {}, {}, 1000.0), "journal_loads"),
    (lambda: _place([0.0] * 9), "no place for an unbalance"),
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


@pytest.mark.slow  # derives a small beam model (~15-50 s on a loaded machine)
def test_audit_of_an_overhung_rotor_puts_the_unbalance_on_the_overhung_disk():
    """A 30 kg disk 0.3 m outboard of the second bearing: its mode peaks at the disk."""
    from rotorkit import BeamSegment, Disk, LinearBearing, Maneuver, Model, Rotor

    d, rho = 0.06, 7800.0
    beam = dict(outer_diameter=d, density=rho, youngs_modulus=2.1e11, shear_modulus=8e10)
    bearing = dict(kxx=5e7, kyy=5e7, cxx=2e3, cyy=2e3)
    model = Model([Rotor(name="R", stations=(1, 2, 3, 4, 5), speed=0.0),
                   BeamSegment(start=1, end=2, length=0.25, **beam), BeamSegment(start=2, end=3, length=0.25, **beam),
                   BeamSegment(start=3, end=4, length=0.15, **beam), BeamSegment(start=4, end=5, length=0.15, **beam),
                   LinearBearing(station=1, **bearing), LinearBearing(station=3, **bearing),
                   Disk(station=5, mass=30.0, polar_inertia=0.3, diametral_inertia=0.15),
                   Maneuver.steady(gravity=9.81)], name="overhung_test")
    audit = api617_audit(model, ("2000 rpm", "3000 rpm"), q_a=1e4, close_clearances={"4": "0.5 mm"})
    first = audit.modes[0]
    # W = the mass outboard of bearing 3: the disk and 0.3 m of shaft, 30 + 7800 pi 0.06^2 / 4 x 0.3 = 36.62 kg
    w = 30.0 + rho * math.pi * d**2 / 4 * 0.3
    assert first.placement.kinds == ("overhung",) and first.placement.loads == (pytest.approx(w, rel=1e-9),)
    # at the disk: 2 x 6350 x 36.62 / 3000 = 155.0 g mm
    (u,) = first.unbalances
    assert u.station == "5" and u.magnitude == pytest.approx(2 * 6350 * w / 3000 * 1e-6, rel=1e-9)
    # probes at the bearings by default; the seal at station 4 checked with S_cc
    amp = first.amplitude
    assert amp.probes == ("1", "3") and [c.station for c in amp.clearances] == ["4"]
    assert amp.clearances[0].limit == pytest.approx(0.375e-3)
