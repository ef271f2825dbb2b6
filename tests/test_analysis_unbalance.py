"""Unbalance response and FRFs against closed forms and simulated runs.

- Jeffcott rotor (m, k, c), unbalance U at angle phi, spin W:
  X = U W^2 e^{i phi} / (k - m W^2 + i c W), Y = -i X (forward circle);
  the phase lag phi - arg X is 90 degrees at W = sqrt(k/m).
- Anisotropic supports kx < ky: X and Y with their own denominators; with
  light damping the orbit whirls backward exactly between sqrt(kx/m) and
  sqrt(ky/m).
- The steady state of a long simulated run of the nonlinear (eccentric
  disk) model agrees with the frequency-domain response.
- 2-DOF receptance: the inverse of the 2 x 2 dynamic stiffness by its
  adjugate; its inverse FFT is the impulse response of an independent
  state-space simulation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Model, Rotor
from rotorkit.analysis.frf import frequency_response
from rotorkit.analysis.linear_model import LinearModel
from rotorkit.analysis.unbalance import Unbalance, unbalance_response
from rotorkit.errors import ParameterError

M_, K_, C_ = 2.0, 2.0e4, 40.0
WN = math.sqrt(K_ / M_)
U, PHI = 2e-4, 0.7


def jeffcott(kx=K_, ky=K_, c=C_):
    return LinearModel(mass=M_ * np.eye(2), damping=c * np.eye(2), stiffness=np.diag([kx, ky]),
                       coordinate_names=("x1", "y1"), rotor_speeds={"R": (0.0, 1.0)})


def test_jeffcott_amplitude_and_phase_at_every_speed():
    speeds = np.linspace(0.0, 3 * WN, 301)
    r = unbalance_response(jeffcott(), [Unbalance(station=1, magnitude=U, angle=PHI)], speeds)
    X = U * speeds**2 * np.exp(1j * PHI) / (K_ - M_ * speeds**2 + 1j * C_ * speeds)
    np.testing.assert_allclose(r.response("x1"), X, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(r.response("y1"), -1j * X, rtol=1e-12, atol=1e-18)
    o = r.orbit(1)
    np.testing.assert_allclose(o.forward, np.abs(X), rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(o.backward, 0.0, atol=1e-15)
    at = unbalance_response(jeffcott(), [(1, U, PHI)], [WN])
    lag = PHI - at.phase("x1")[0]
    assert math.degrees(lag) == pytest.approx(90.0, abs=1e-9)


def test_anisotropic_supports_whirl_backward_between_the_split_frequencies():
    kx, ky = 1.5e4, 2.5e4
    wx, wy = math.sqrt(kx / M_), math.sqrt(ky / M_)
    speeds = np.linspace(0.2 * wx, 1.5 * wy, 400)
    r = unbalance_response(jeffcott(kx, ky, c=0.5), [Unbalance(station=1, magnitude=U)], speeds)
    X = U * speeds**2 / (kx - M_ * speeds**2 + 0.5j * speeds)
    Y = -1j * U * speeds**2 / (ky - M_ * speeds**2 + 0.5j * speeds)
    np.testing.assert_allclose(r.response("x1"), X, rtol=1e-12)
    np.testing.assert_allclose(r.response("y1"), Y, rtol=1e-12)
    o = r.orbit(1)
    inside = (speeds > 1.01 * wx) & (speeds < 0.99 * wy)
    outside = (speeds < 0.99 * wx) | (speeds > 1.01 * wy)
    assert set(o.direction[inside]) == {"backward"}
    assert set(o.direction[outside]) == {"forward"}
    np.testing.assert_allclose(o.major, (np.abs(X + 1j * Y) + np.abs(X - 1j * Y)) / 2, rtol=1e-12)


def test_dual_rotor_each_spool_at_its_own_speed():
    model = LinearModel(mass=M_ * np.eye(4), damping=C_ * np.eye(4), stiffness=K_ * np.eye(4),
                        coordinate_names=("x1", "y1", "x2", "y2"), rotor_speeds={"LP": (0.0, 1.0), "HP": (0.0, 1.8)},
                        station_rotors={"1": "LP", "2": "HP"})
    speeds = np.linspace(10.0, 200.0, 20)
    r = unbalance_response(model, [Unbalance(1, U), Unbalance(2, 2 * U, 1.0)], speeds)
    assert set(r.components) == {"LP", "HP"}
    w = 1.8 * speeds
    np.testing.assert_allclose(r.frequencies["HP"], w)
    X2 = 2 * U * w**2 * np.exp(1j) / (K_ - M_ * w**2 + 1j * C_ * w)
    np.testing.assert_allclose(r.response("x2", rotor="HP"), X2, rtol=1e-12)
    np.testing.assert_allclose(r.amplitude("x1", rotor="HP"), 0.0, atol=1e-20)
    with pytest.raises(ParameterError, match="rotor=None is ambiguous"):
        r.amplitude("x1")


def chain(stations=200, k=1e6, kg=2e5, m=1.0, c=5.0):
    """Stations in a chain (x and y), grounded at both ends; gyroscopic-like coupling x <-> y."""
    n = 2 * stations
    K = np.zeros((n, n))
    for axis in range(2):
        idx = np.arange(axis, n, 2)
        for a, b in zip(idx[:-1], idx[1:]):
            K[np.ix_([a, b], [a, b])] += k * np.array([[1, -1], [-1, 1]])
        K[idx[0], idx[0]] += kg
        K[idx[-1], idx[-1]] += kg
    G = np.zeros((n, n))
    for s in range(stations):
        G[2 * s, 2 * s + 1], G[2 * s + 1, 2 * s] = 1e-3, -1e-3
    names = [f"{a}{s + 1}" for s in range(stations) for a in "xy"]
    return LinearModel(mass=m * np.eye(n), damping=c * np.eye(n), stiffness=K, gyroscopic=G, coordinate_names=names)


def test_banded_and_dense_solves_agree():
    model = chain(60)
    speeds = np.linspace(0.0, 2000.0, 25)
    items = [Unbalance(10, 1e-4), Unbalance(45, 3e-4, 2.0)]
    banded = unbalance_response(model, items, speeds, method="banded")
    dense = unbalance_response(model, items, speeds, method="dense")
    assert (banded.method, dense.method) == ("banded", "dense")
    assert unbalance_response(model, items, speeds).method == "banded"
    np.testing.assert_allclose(banded.components["rotor"], dense.components["rotor"], rtol=1e-9, atol=1e-18)


@pytest.mark.slow
def test_steady_state_of_a_long_simulation_agrees():
    from rotorkit.analysis.linear_model import linear_model
    from rotorkit.simulate import simulate

    speed, e = 80.0, 1e-5
    system = Model([Rotor(name="R", stations=(1,), speed=speed),
                    Disk(station=1, mass=M_, radius=0.1, eccentricity=e, phase=PHI, torsion=False),
                    ElasticSupport(station=1, stiffness=K_, damping=C_)]).compile(backend="python")
    run = simulate(system, (0.0, 1.5), rtol=1e-10, atol=1e-14, sample_rate=4000.0)
    t = run.t
    late = t > 1.0  # the transient decays as exp(-c t / 2m) = exp(-10 t)
    basis = np.column_stack([np.cos(speed * t[late]), -np.sin(speed * t[late])])
    lm = linear_model(system)
    r = unbalance_response(lm, [Unbalance(1, M_ * e, PHI)], [speed])
    for name in ("x1", "y1"):
        (re, im), *_ = np.linalg.lstsq(basis, run[name][late], rcond=None)  # x = Re((re + i im) e^{iWt})
        np.testing.assert_allclose(re + 1j * im, r.response(name)[0], rtol=2e-4)


# ---------------------------------------------------------------------------
# FRF
# ---------------------------------------------------------------------------

M1, M2, K1, K2, C1, C2 = 1.0, 0.5, 4e4, 2e4, 8.0, 3.0


def two_dof():
    M = np.diag([M1, M2])
    K = np.array([[K1 + K2, -K2], [-K2, K2]])
    C = np.array([[C1 + C2, -C2], [-C2, C2]])
    return LinearModel(mass=M, damping=C, stiffness=K, coordinate_names=("q1", "q2"))


def test_two_dof_receptance_closed_form():
    w = np.linspace(0.0, 600.0, 601)
    frf = frequency_response(two_dof(), w)
    d11 = K1 + K2 - M1 * w**2 + 1j * w * (C1 + C2)
    d22 = K2 - M2 * w**2 + 1j * w * C2
    d12 = -K2 - 1j * w * C2
    det = d11 * d22 - d12**2
    np.testing.assert_allclose(frf("q1", "q1"), d22 / det, rtol=1e-10)
    np.testing.assert_allclose(frf("q2", "q1"), -d12 / det, rtol=1e-10)
    np.testing.assert_allclose(frf("q2", "q2"), d11 / det, rtol=1e-10)
    acc = frf.as_kind("accelerance")
    np.testing.assert_allclose(acc("q2", "q1"), -w**2 * (-d12 / det), rtol=1e-10)
    mob = frequency_response(two_dof(), w, kind="mobility", inputs=["q1"], outputs=["q2"])
    np.testing.assert_allclose(mob.values[:, 0, 0], 1j * w * (-d12 / det), rtol=1e-10)


def test_inverse_fft_of_the_receptance_is_the_simulated_impulse_response():
    from scipy.integrate import solve_ivp

    model = two_dof()
    fs, n = 4096.0, 2**14  # 4 s record: the response decays to ~1e-4 of its peak
    w = 2 * np.pi * np.fft.rfftfreq(n, 1.0 / fs)
    H = frequency_response(model, w, inputs=["q1"], outputs=["q2"]).values[:, 0, 0]
    h = np.fft.irfft(H, n) * fs  # h(t) = (1/2pi) int H e^{iwt} dw
    t = np.arange(n) / fs
    A = model.state_matrix()
    y0 = np.zeros(4)
    y0[2:] = np.linalg.solve(model.mass, [1.0, 0.0])  # unit impulse on q1: q1' jumps by 1/m1
    sim = solve_ivp(lambda _, y: A @ y, (0.0, t[n // 4]), y0, t_eval=t[: n // 4], rtol=1e-10, atol=1e-14)
    peak = np.max(np.abs(sim.y[1]))
    np.testing.assert_allclose(h[1: n // 4], sim.y[1][1:], atol=2e-3 * peak)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: unbalance_response(jeffcott(), [], [1.0]), "unbalances is empty"),
        (lambda: unbalance_response(jeffcott(), [Unbalance(3, U)], [1.0]), "station=3"),
        (lambda: Unbalance(1, -1.0), "magnitude=-1.0"),
        (lambda: unbalance_response(jeffcott(), [Unbalance(1, U)], [np.nan]), "speeds"),
        (lambda: unbalance_response(jeffcott(), [Unbalance(1, U)], [1.0], method="modal"), "method='modal'"),
        (lambda: frequency_response(two_dof(), [1.0], kind="inertance"), "kind='inertance'"),
        (lambda: frequency_response(two_dof(), [1.0], inputs=["q9"]), "q9"),
    ],
)
def test_bad_input_raises(call, match):
    with pytest.raises(ParameterError, match=match):
        call()


def test_plots_return_axes():
    from matplotlib.axes import Axes

    r = unbalance_response(jeffcott(), [Unbalance(1, U)], np.linspace(1.0, 300.0, 50))
    top, bottom = r.plot_bode("x1")
    assert isinstance(top, Axes) and "um" in top.get_ylabel() and "deg" in bottom.get_ylabel()
    assert "rad/s" in bottom.get_xlabel()
    assert isinstance(r.plot_polar("x1"), Axes)
    frf = frequency_response(two_dof(), np.linspace(0.0, 500.0, 100))
    top, bottom = frf.plot("q1", "q2", units="Hz")
    assert "m/N" in top.get_ylabel() and "Hz" in bottom.get_xlabel()
    assert r.to_csv(1).count("\n") == 51


# ---------------------------------------------------------------------------
# Static deflection and critical speed map
# ---------------------------------------------------------------------------


def test_static_deflection_and_reactions_of_a_two_mass_chain():
    from rotorkit import LumpedMass, Maneuver, ShaftSegment
    from rotorkit.analysis.static import static_deflection

    m1, m2, k1, k2, ks, g = 3.0, 5.0, 2e5, 4e5, 1e5, 9.81
    system = Model([Rotor(name="R", stations=(1, 2), speed=0.0), LumpedMass(station=1, mass=m1),
                    LumpedMass(station=2, mass=m2), ShaftSegment(start=1, end=2, bending_stiffness=ks),
                    ElasticSupport(station=1, stiffness=k1), ElasticSupport(station=2, stiffness=k2),
                    Maneuver.steady(gravity=g)]).compile(backend="python")
    result = static_deflection(system)
    K = np.array([[k1 + ks, -ks], [-ks, k2 + ks]])
    y = np.linalg.solve(K, [-m1 * g, -m2 * g])
    np.testing.assert_allclose([result.deflection["y1"], result.deflection["y2"]], y, rtol=1e-7)
    assert result.reaction("support1", 1)[1] == pytest.approx(-k1 * y[0], rel=1e-7)
    assert result.reaction("support2", 2)[1] == pytest.approx(-k2 * y[1], rel=1e-7)
    total = result.reaction("support1", 1)[1] + result.reaction("support2", 2)[1]
    assert total == pytest.approx((m1 + m2) * g, rel=1e-7)  # the supports carry the weight
    assert set(result.reactions) == {"support1", "support2"}
    assert result.plot().get_ylabel() == "static deflection (um)"
    with pytest.raises(ParameterError, match="label='shaft1_2'"):
        result.reaction("shaft1_2", 1)


def test_critical_speed_map_of_a_disk_on_a_flexible_shaft():
    from rotorkit.analysis.critical_map import critical_speed_map

    m1, m2, ks = 10.0, 1.0, 1e6  # disk, bearing station, shaft stiffness
    K = np.zeros((4, 4))
    for a, b in ((0, 2), (1, 3)):
        K[np.ix_([a, b], [a, b])] = ks * np.array([[1, -1], [-1, 1]])
    rotor = LinearModel(mass=np.diag([m1, m1, m2, m2]), damping=np.zeros((4, 4)), stiffness=K,
                        coordinate_names=("x1", "y1", "x2", "y2"))
    ks_values = np.logspace(4, 8, 5)
    cmap = critical_speed_map(rotor, supports=[2], stiffnesses=ks_values, speed_range=(1.0, 20000.0), n_critical=2)
    for i, k in enumerate(ks_values):
        b = m1 * (ks + k) + m2 * ks  # m1 m2 w^4 - (m1 (ks + k) + m2 ks) w^2 + ks k = 0
        roots = np.sqrt((b + np.array([-1, 1]) * np.sqrt(b * b - 4 * m1 * m2 * ks * k)) / (2 * m1 * m2))
        roots = roots[roots < 20000.0]
        np.testing.assert_allclose(cmap.speeds[i, : roots.size], roots, rtol=1e-7)
    ax = cmap.plot()
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert "N/m" in ax.get_xlabel()
