"""Virtual sensors against closed forms: free vibration of an undamped Jeffcott rotor
(x = x0 cos(wn t)), free torsional vibration of a disk on a spring to the drive
(alpha = a0 cos(wt t)), the analog Butterworth magnitude, and the noise statistics."""

import math

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, LumpedMass, Model, ParameterError, Rotor, ShaftSegment, TopologyError
from rotorkit.sensors import Difference, DisplacementProbe, RotaryEncoder, measure, read_sensors
from rotorkit.simulate import simulate

SPIN = 100.0  # rad/s
M, K = 2.0, 2e5  # kg, N/m: wn = 316.2 rad/s
J, KT = 0.01, 400.0  # kg m^2, N m/rad: wt = 200 rad/s


def jeffcott(stiffness=K):
    return Model([Rotor(name="R", stations=(1,), speed=SPIN), Disk(station=1, mass=M, radius=0.1),
                  ElasticSupport(station=1, stiffness=stiffness)], name="jeffcott")


def torsion_rig():
    """Drive station 0, a torsional disk at 1 on a spring k_t (no damping, no unbalance, no gravity)."""
    return Model([Rotor(name="R", stations=(0, 1), speed=SPIN), LumpedMass(station=0, mass=1.0),
                  Disk(station=1, mass=1.0, polar_inertia=J, torsion=True),
                  ElasticSupport(station=0, stiffness=1e5), ElasticSupport(station=1, stiffness=1e5),
                  ShaftSegment(start=0, end=1, torsional_stiffness=KT)], name="torsion")


@pytest.fixture(scope="module")
def jeffcott_system():
    return jeffcott().compile(backend="python")


@pytest.fixture(scope="module")
def torsion_system():
    return torsion_rig().compile(backend="python")


TIGHT = dict(rtol=1e-10, atol=1e-14)


def test_probe_samples_analytic_motion_at_its_own_rate(jeffcott_system):
    x0, y0 = 1e-4, -5e-5
    wn = math.sqrt(K / M)
    state = jeffcott_system.initial_state(x1=x0, y1=y0)
    angle = math.radians(30)
    probes = [DisplacementProbe(name="p", station=1, angle=angle, sample_rate=3000.0),
              DisplacementProbe(name="v", station=1, direction="vertical", sample_rate=1300.0)]
    m = measure(jeffcott_system, (0.0, 0.5), probes, y0=state, **TIGHT)
    p, v = m["p"], m["v"]
    assert p.unit == "m" and p.sample_rate == 3000.0
    np.testing.assert_allclose(p.t, np.arange(1501) / 3000.0, rtol=0, atol=1e-15)  # exactly its own instants
    np.testing.assert_allclose(v.t, np.arange(651) / 1300.0, rtol=0, atol=1e-15)
    exact = (x0 * math.cos(angle) + y0 * math.sin(angle)) * np.cos(wn * p.t)
    np.testing.assert_allclose(p.values, exact, rtol=0, atol=1e-8 * x0)
    np.testing.assert_allclose(v.values, y0 * np.cos(wn * v.t), rtol=0, atol=1e-8 * x0)


@pytest.mark.parametrize("order, cutoff", [(4, 200.0), (2, 150.0)])
def test_anti_aliasing_attenuates_a_component_above_nyquist_as_specified(order, cutoff):
    f_tone = 700.0  # Hz, above the 500 Hz Nyquist rate of a 1000 Hz probe
    system = jeffcott(stiffness=M * (2 * math.pi * f_tone) ** 2).compile(backend="python")
    x0 = 1e-4
    y0 = system.initial_state(x1=x0)
    plain = DisplacementProbe(name="plain", station=1, direction="x", sample_rate=1000.0)
    aa = DisplacementProbe(name="aa", station=1, direction="x", sample_rate=1000.0, anti_aliasing=cutoff,
                           filter_order=order, oversampling=16)
    m = measure(system, (0.0, 0.6), [plain, aa], y0=y0, **TIGHT)

    def amplitude(s):  # least-squares amplitude of the alias at 300 Hz, after the filter's start transient
        keep = s.t >= 0.2
        t, x = s.t[keep], s.values[keep]
        basis = np.column_stack([np.cos(2 * np.pi * 300.0 * t), np.sin(2 * np.pi * 300.0 * t)])
        coef = np.linalg.lstsq(basis, x, rcond=None)[0]
        return float(np.hypot(*coef))

    expected = 1 / math.sqrt(1 + (f_tone / cutoff) ** (2 * order))  # analog Butterworth magnitude
    assert amplitude(m["plain"]) == pytest.approx(x0, rel=1e-6)  # unfiltered: the alias keeps its full amplitude
    assert amplitude(m["aa"]) == pytest.approx(expected * x0, rel=0.03)


def test_noise_has_the_stated_standard_deviation_and_repeats_with_its_seed(jeffcott_system):
    sigma = 2e-6
    probes = [DisplacementProbe(name=f"n{k}", station=1, direction="x", sample_rate=20000.0, noise=sigma, seed=s)
              for k, s in enumerate((1, 1, 2))]
    m = measure(jeffcott_system, (0.0, 1.0), probes)  # the rotor stays at rest: the record is pure noise
    n = m["n0"].values
    assert n.size == 20001
    assert np.std(n) == pytest.approx(sigma, rel=0.03)  # sampling error of a std: 1/sqrt(2 n) = 0.5 %
    assert abs(np.mean(n)) < 4 * sigma / math.sqrt(n.size)
    np.testing.assert_array_equal(n, m["n1"].values)
    assert not np.array_equal(n, m["n2"].values)


def test_resolution_quantises_the_record(jeffcott_system):
    res = 1e-6
    probe = DisplacementProbe(name="q", station=1, direction="x", sample_rate=2000.0, resolution=res)
    m = measure(jeffcott_system, (0.0, 0.1), [probe], y0=jeffcott_system.initial_state(x1=1e-5))
    q = m["q"].values / res
    np.testing.assert_allclose(q, np.round(q), atol=1e-9)
    exact = 1e-5 * np.cos(math.sqrt(K / M) * m["q"].t)
    assert np.max(np.abs(m["q"].values - exact)) <= res / 2 + 1e-12


def test_encoder_on_rigid_rotor_at_constant_speed_reads_that_speed(torsion_system):
    encoders = [RotaryEncoder(name="ideal", station=1, sample_rate=12800.0),
                RotaryEncoder(name="counted", station=1, sample_rate=1000.0, pulses_per_revolution=2048)]
    m = measure(torsion_system, (0.0, 1.0), encoders)
    assert m["ideal"].unit == "rad/s"
    np.testing.assert_allclose(m["ideal"].values, SPIN, rtol=1e-12)
    counted = m["counted"].values
    step = 2 * math.pi / (2048 * 1e-3)  # speed resolution of a counting encoder
    assert np.all(np.abs(counted - SPIN) <= step * (1 + 1e-9))
    assert np.mean(counted) == pytest.approx(SPIN, abs=step / counted.size * 2)  # counts add up to the turned angle


def test_encoder_reads_spin_plus_torsional_rate(torsion_system):
    a0 = 1e-3
    wt = math.sqrt(KT / J)
    y0 = torsion_system.initial_state(alpha1=a0)
    enc = RotaryEncoder(name="omega", station=1, sample_rate=12800.0)
    m = measure(torsion_system, (0.0, 1.0), [enc, Difference(name="d", minuend="omega", subtrahend="omega")],
                y0=y0, **TIGHT)
    t = m["omega"].t
    np.testing.assert_allclose(m["omega"].values, SPIN - a0 * wt * np.sin(wt * t), rtol=0, atol=1e-8)
    np.testing.assert_array_equal(m["d"].values, 0.0)
    hp = m["omega"].highpass(2.0).window(0.3, 0.7)  # the paper's 2 Hz high-pass removes the constant spin
    assert np.max(np.abs(hp.values)) < 1.2 * a0 * wt  # the 100 rad/s spin is gone, the 0.2 rad/s oscillation stays
    assert np.std(hp.values) == pytest.approx(a0 * wt / math.sqrt(2), rel=0.1)


def test_read_sensors_from_a_result_on_the_grid_and_refuses_more(jeffcott_system):
    y0 = jeffcott_system.initial_state(x1=1e-4)
    result = simulate(jeffcott_system, (0.0, 0.2), y0=y0, sample_rate=4000.0, **TIGHT)
    probe = DisplacementProbe(name="p", station=1, direction="x", sample_rate=2000.0)
    got = read_sensors(result, [probe], jeffcott_system.model)["p"]
    np.testing.assert_allclose(got.values, result["x1"][::2], rtol=0, atol=0)
    fast = DisplacementProbe(name="fast", station=1, direction="x", sample_rate=12800.0)
    with pytest.raises(ParameterError, match=r"'fast' reads at 12800 Hz.*no dense output.*measure"):
        read_sensors(result, [fast], jeffcott_system.model)
    off_grid = DisplacementProbe(name="odd", station=1, direction="x", sample_rate=3000.0)
    with pytest.raises(ParameterError, match="not on that sensor's instants"):
        read_sensors(result, [off_grid], jeffcott_system.model)


@pytest.mark.parametrize("sensor, error, match", [
    (DisplacementProbe(name="p", station=9, direction="x", sample_rate=1e3), TopologyError,
     r"DisplacementProbe 'p': station 9 is not a station of the model \(stations: 0, 1\)"),
    (RotaryEncoder(name="e", station=0, sample_rate=1e3), TopologyError,
     r"RotaryEncoder 'e': station 0 has no torsional coordinate alpha0 \(stations with one: 1\)"),
    (RotaryEncoder(name="e", station=7, sample_rate=1e3), TopologyError, "station 7 is not a station"),
])
def test_sensor_on_a_bad_station_is_a_named_error(torsion_system, sensor, error, match):
    with pytest.raises(error, match=match):
        measure(torsion_system, (0.0, 0.01), [sensor])


@pytest.mark.parametrize("make, match", [
    (lambda: DisplacementProbe(name="p", station=1, direction="x", sample_rate=0.0), "sample_rate = 0.0"),
    (lambda: DisplacementProbe(name="p", station=1, direction="x", sample_rate=float("inf")), "sample_rate = inf"),
    (lambda: DisplacementProbe(name="p", station=1, sample_rate=1e3), "exactly one of direction"),
    (lambda: DisplacementProbe(name="p", station=1, direction="z", sample_rate=1e3), "direction = 'z'"),
    (lambda: DisplacementProbe(name="p", station=1, direction="x", sample_rate=1e3, noise=-1.0), "noise = -1.0"),
    (lambda: DisplacementProbe(name="p", station=1, direction="x", sample_rate=1e3, anti_aliasing=600.0),
     "below the Nyquist rate 500 Hz"),
    (lambda: DisplacementProbe(name="p", station=1, direction="x", sample_rate=1e3, resolution=0.0),
     "resolution = 0"),
    (lambda: DisplacementProbe(name="2p", station=1, direction="x", sample_rate=1e3), "name = '2p'"),
    (lambda: RotaryEncoder(name="e", station=1, sample_rate=1e3, pulses_per_revolution=0),
     "pulses_per_revolution = 0"),
    (lambda: RotaryEncoder(name="e", station=1, sample_rate="fast"), "sample_rate = 'fast'"),
])
def test_bad_sensor_settings_are_named_errors(make, match):
    with pytest.raises(ParameterError, match=match):
        make()


def test_sensor_sets_are_checked(torsion_system):
    enc = RotaryEncoder(name="e", station=1, sample_rate=1e3)
    with pytest.raises(ParameterError, match="two sensors are named 'e'"):
        measure(torsion_system, (0.0, 0.01), [enc, enc])
    with pytest.raises(ParameterError, match="no sensor named 'f'"):
        measure(torsion_system, (0.0, 0.01), [enc, Difference(name="d", minuend="e", subtrahend="f")])
    probe = DisplacementProbe(name="p", station=1, direction="x", sample_rate=2e3)
    with pytest.raises(ParameterError, match="must share rate and unit"):
        measure(torsion_system, (0.0, 0.01), [enc, probe, Difference(name="d", minuend="e", subtrahend="p")])


def test_sensors_accept_pint_quantities():
    import pint

    u = pint.UnitRegistry()
    p = DisplacementProbe(name="p", station=1, angle=90 * u.degree, sample_rate=2 * u.kHz, noise=1 * u.um)
    assert p.angle == pytest.approx(math.pi / 2) and p.sample_rate == pytest.approx(2000.0)
    assert p.noise == pytest.approx(1e-6)


@pytest.mark.parametrize("times", [[0.2, 0.1], [0.0, 2.0], [float("nan")], []])
def test_simulate_sample_times_are_checked(jeffcott_system, times):
    with pytest.raises(ParameterError, match="sample_times"):
        simulate(jeffcott_system, (0.0, 1.0), sample_times=times)
