"""Closed-form rotordynamics checks of models built from rotorkit's public objects.

A Jeffcott rotor (one disk of mass m on an isotropic support of stiffness k
and damping c) has textbook answers for everything it does:

- free vibration at ``wn = sqrt(k / m)``, damped at ``wn sqrt(1 - zeta^2)``,
  with ``zeta = c / (2 sqrt(k m))``;
- a free-decay envelope ``exp(-zeta wn t)`` (log decrement
  ``2 pi zeta / sqrt(1 - zeta^2)``);
- a static sag ``-m g / k`` under gravity;
- a circular, synchronous, forward unbalance whirl of radius
  ``e r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2)``, ``r = Omega / wn``, lagging
  the unbalance by ``atan2(2 zeta r, 1 - r^2)``.

Multi-station models check what has no one-line formula but follows from
Lagrangian mechanics: conservation of ``1/2 q'^T M q' + 1/2 q^T K q`` when
nothing dissipates or drives, and the eccentric torsional disk's mass matrix
and equations written out by hand. Nothing here compares the library with a
stored snapshot of its own output.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

import rotorkit
from rotorkit import (
    Disk,
    ElasticSupport,
    LumpedMass,
    Maneuver,
    Model,
    Rotor,
    ShaftSegment,
    simulate,
)

MASS = 2.0  # kg
STIFFNESS = 2.0e4  # N/m
WN = math.sqrt(STIFFNESS / MASS)  # 100 rad/s
G = 9.81  # m/s^2


def damping_for(zeta):
    """Support damping (N s/m) giving damping ratio ``zeta`` on the Jeffcott rotor."""
    return 2.0 * zeta * math.sqrt(STIFFNESS * MASS)


def jeffcott(*, speed=0.0, eccentricity=0.0, damping=0.0, gravity=None, phase=0.0):
    """A Jeffcott rotor: rotor R, disk at station 1 (no torsion), support at station 1."""
    elements = [
        Rotor(name="R", stations=(1,), speed=speed),
        Disk(station=1, mass=MASS, radius=0.1, eccentricity=eccentricity, phase=phase, torsion=False),
        ElasticSupport(station=1, stiffness=STIFFNESS, damping=damping),
    ]
    if gravity is not None:
        elements.append(Maneuver.steady(gravity=gravity))
    return Model(elements, name="jeffcott")


def upward_zero_crossings(t, x):
    """Times at which ``x`` crosses zero upwards (linear interpolation between samples)."""
    i = np.flatnonzero((x[:-1] < 0.0) & (x[1:] >= 0.0))
    return t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])


def refined_peaks(t, x):
    """(times, values) of the local maxima of ``x``, refined by a parabola through 3 samples."""
    i = np.flatnonzero((x[1:-1] > x[:-2]) & (x[1:-1] >= x[2:])) + 1
    a, b, c = x[i - 1], x[i], x[i + 1]
    d = 0.5 * (a - c) / (a - 2.0 * b + c)
    return t[i] + d * (t[1] - t[0]), b - 0.25 * (a - c) * d


def measured_frequency(result, name):
    """Angular frequency (rad/s) from the mean spacing of upward zero crossings."""
    tc = upward_zero_crossings(result.t, result[name])
    assert len(tc) >= 10, f"too few oscillations of {name} to measure a frequency ({len(tc)} crossings)"
    return 2.0 * math.pi * (len(tc) - 1) / (tc[-1] - tc[0])


# ---------------------------------------------------------------------------
# the model itself
# ---------------------------------------------------------------------------


def test_jeffcott_has_two_bending_coordinates_and_named_parameters():
    model = jeffcott(speed=50.0, eccentricity=1e-4, damping=10.0)
    assert model.coordinate_names == ("x1", "y1")
    system = model.compile(backend="python")
    assert system.state_names == ("x1", "y1", "x1_dot", "y1_dot")
    p = system.parameters
    assert p["support1_stiffness"] == STIFFNESS
    assert p["support1_damping"] == 10.0
    assert p["disk1_mass"] == MASS
    assert p["disk1_eccentricity"] == 1e-4
    assert p["R_speed"] == 50.0


def test_jeffcott_linear_matrices_are_m_c_k():
    eq = jeffcott(speed=50.0, eccentricity=1e-4, damping=10.0).equations()
    m, k, c = (sp.Symbol(n, real=True) for n in ("disk1_mass", "support1_stiffness", "support1_damping"))
    assert sp.simplify(eq.mass_matrix - sp.diag(m, m)) == sp.zeros(2, 2)
    assert sp.simplify(eq.stiffness - sp.diag(k, k)) == sp.zeros(2, 2)
    assert sp.simplify(eq.damping - sp.diag(c, c)) == sp.zeros(2, 2)


# ---------------------------------------------------------------------------
# free vibration
# ---------------------------------------------------------------------------


def test_undamped_free_vibration_at_sqrt_k_over_m():
    system = jeffcott().compile(backend="python")
    result = simulate(system, (0.0, 2.0), y0=system.initial_state(x1=1e-3), rtol=1e-10, atol=1e-15,
                      sample_rate=20_000.0)
    w = measured_frequency(result, "x1")
    assert w == pytest.approx(WN, rel=1e-6)  # about 30 cycles; achieved ~1e-11
    # undamped: the amplitude sqrt(x^2 + (x'/wn)^2) neither grows nor decays
    amplitude = np.hypot(result["x1"], result["x1_dot"] / WN)
    np.testing.assert_allclose(amplitude, 1e-3, rtol=1e-7)
    # and y, never excited, stays at rest
    assert np.max(np.abs(result["y1"])) < 1e-15


@pytest.mark.parametrize("zeta", [0.05, 0.1])
def test_damped_free_vibration_at_wn_sqrt_1_minus_zeta2(zeta):
    system = jeffcott(damping=damping_for(zeta)).compile(backend="python")
    result = simulate(system, (0.0, 1.0), y0=system.initial_state(x1=1e-3), rtol=1e-11, atol=1e-17,
                      sample_rate=20_000.0)
    w = measured_frequency(result, "x1")
    wd = WN * math.sqrt(1.0 - zeta**2)
    assert w == pytest.approx(wd, rel=1e-6)
    # the measurement resolves the damped shift (1.25e-3 at zeta = 0.05)
    assert abs(w / WN - 1.0) > 0.5 * zeta**2


@pytest.mark.parametrize("zeta", [0.02, 0.05])
def test_free_decay_log_decrement(zeta):
    c = damping_for(zeta)
    assert c / (2.0 * math.sqrt(STIFFNESS * MASS)) == pytest.approx(zeta)
    system = jeffcott(damping=c).compile(backend="python")
    result = simulate(system, (0.0, 1.0), y0=system.initial_state(x1=1e-3), rtol=1e-11, atol=1e-17,
                      sample_rate=20_000.0)
    tp, peaks = refined_peaks(result.t, result["x1"])
    assert len(peaks) >= 10
    # envelope exp(-zeta wn t): slope of log(peak) against time
    sigma = -np.polyfit(tp, np.log(peaks), 1)[0]
    assert sigma == pytest.approx(zeta * WN, rel=1e-5)
    # log decrement between successive peaks
    decrement = np.log(peaks[:-1] / peaks[1:])
    expected = 2.0 * math.pi * zeta / math.sqrt(1.0 - zeta**2)
    np.testing.assert_allclose(decrement, expected, rtol=1e-5)


def test_circular_free_decay_radius_is_the_exponential_envelope():
    """Started on a decaying circle, r(t) = r0 exp(-zeta wn t) at every sample."""
    zeta = 0.05
    sigma, wd, r0 = zeta * WN, WN * math.sqrt(1.0 - zeta**2), 1e-3
    system = jeffcott(damping=damping_for(zeta)).compile(backend="python")
    y0 = system.initial_state(x1=r0, x1_dot=-sigma * r0, y1_dot=wd * r0)
    result = simulate(system, (0.0, 0.5), y0=y0, rtol=1e-11, atol=1e-17, sample_rate=5_000.0)
    r = np.hypot(result["x1"], result["y1"])
    np.testing.assert_allclose(r, r0 * np.exp(-sigma * result.t), rtol=1e-7)
    # and it turns at the damped frequency: angle = wd t
    angle = np.unwrap(np.arctan2(result["y1"], result["x1"]))
    np.testing.assert_allclose(angle, wd * result.t, atol=1e-7)


# ---------------------------------------------------------------------------
# static sag under gravity
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("g", [9.81, 1.62])
def test_static_sag_is_an_equilibrium(g):
    system = jeffcott(gravity=g, damping=damping_for(0.1)).compile(backend="python")
    sag = -MASS * g / STIFFNESS
    dydt = system.rhs(0.37, system.initial_state(y1=sag))
    np.testing.assert_allclose(dydt, 0.0, atol=1e-12 * g)
    # off the equilibrium, gravity alone acts: -g at the undeflected axis
    np.testing.assert_allclose(system.rhs(0.0, system.initial_state()), [0.0, 0.0, 0.0, -g], atol=1e-12 * g)


def test_static_sag_reached_from_rest_with_damping():
    system = jeffcott(gravity=G, damping=damping_for(0.2)).compile(backend="python")
    result = simulate(system, (0.0, 1.5), rtol=1e-10, atol=1e-15, sample_rate=20_000.0)
    sag = -MASS * G / STIFFNESS  # -0.981 mm
    assert result["y1"][-1] == pytest.approx(sag, rel=1e-6)
    assert abs(result["y1_dot"][-1]) < 1e-9
    assert np.max(np.abs(result["x1"])) < 1e-15
    # on the way, a step response of a damped oscillator overshoots to (1 + exp(-zeta pi / sqrt(1-zeta^2)))
    overshoot = 1.0 + math.exp(-0.2 * math.pi / math.sqrt(1.0 - 0.2**2))
    assert np.min(result["y1"]) == pytest.approx(overshoot * sag, rel=1e-4)


# ---------------------------------------------------------------------------
# unbalance response
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("ratio", [0.5, 0.9, 1.0, 1.5, 3.0])
def test_steady_unbalance_whirl(ratio):
    zeta, e = 0.05, 1e-4
    speed = ratio * WN
    system = jeffcott(speed=speed, eccentricity=e, damping=damping_for(zeta)).compile(backend="python")
    # transients decay as exp(-zeta wn t) = exp(-5 t): 3 s leaves ~3e-7 of them
    t_end = 3.0
    result = simulate(system, (0.0, t_end), rtol=1e-9, atol=1e-14, sample_rate=20_000.0)
    amplitude = e * ratio**2 / math.sqrt((1.0 - ratio**2) ** 2 + (2.0 * zeta * ratio) ** 2)
    lag = math.atan2(2.0 * zeta * ratio, 1.0 - ratio**2)

    last = result.t > t_end - 4.0 * math.pi / speed  # the last two revolutions
    t, x, y = result.t[last], result["x1"][last], result["y1"][last]
    radius = np.hypot(x, y)
    # circular orbit of the closed-form radius
    np.testing.assert_allclose(radius, amplitude, rtol=1e-4)  # achieved ~1e-6
    assert np.max(np.abs(x)) == pytest.approx(amplitude, rel=1e-4)
    assert np.max(np.abs(y)) == pytest.approx(amplitude, rel=1e-4)
    # synchronous: a fit of cos/sin at the spin speed leaves (almost) nothing
    basis = np.column_stack([np.cos(speed * t), np.sin(speed * t)])
    (ax, bx), res_x, *_ = np.linalg.lstsq(basis, x, rcond=None)
    (ay, by), res_y, *_ = np.linalg.lstsq(basis, y, rcond=None)
    assert math.sqrt(res_x[0] / len(t)) < 1e-4 * amplitude
    assert math.sqrt(res_y[0] / len(t)) < 1e-4 * amplitude
    # x = A cos(W t - lag), y = A sin(W t - lag): forward whirl lagging the unbalance
    assert math.atan2(bx, ax) == pytest.approx(lag, abs=1e-4)
    assert math.atan2(-ay, by) == pytest.approx(lag, abs=1e-4)
    assert np.all(x * result["y1_dot"][last] - y * result["x1_dot"][last] > 0.0)


# ---------------------------------------------------------------------------
# energy conservation of a conservative multi-station model
# ---------------------------------------------------------------------------


def three_station_rotor(*, speed, e2=0.0, e3=0.0):
    """Stations 1-2-3, disks with torsion at 2 and 3, supports at 1 and 3, no damping, no load field."""
    return Model([
        Rotor(name="R", stations=(1, 2, 3), speed=speed),
        LumpedMass(station=1, mass=2.0),
        Disk(station=2, mass=10.0, radius=0.075, eccentricity=e2, phase=0.3, torsion=True),
        Disk(station=3, mass=6.0, radius=0.03, eccentricity=e3, phase=-1.1, torsion=True),
        ShaftSegment(start=1, end=2, bending_stiffness=5e5, torsional_stiffness=5e3),
        ShaftSegment(start=2, end=3, bending_stiffness=3e5, torsional_stiffness=2e3),
        ElasticSupport(station=1, stiffness=1e6),
        ElasticSupport(station=3, stiffness=8e5),
    ], name="three_station")


def energy_function(model, mass_matrix=None):
    """(T, V)(t, y): 1/2 q'^T M(q, t) q' and 1/2 q^T K q from the model's symbolic M and K."""
    eq = model.equations()
    values = {p: model.parameters[p.name] for p in eq.parameters}
    M = (eq.mass_matrix if mass_matrix is None else mass_matrix).subs(values)
    K = np.array(eq.stiffness.subs(values), dtype=float)
    M_of = sp.lambdify((eq.t,) + tuple(eq.coordinates), M, "numpy")
    n = eq.n

    def energy(t, y):
        kinetic, potential = np.empty(len(t)), np.empty(len(t))
        for i in range(len(t)):
            q, qd = y[:n, i], y[n:, i]
            kinetic[i] = 0.5 * qd @ np.array(M_of(t[i], *q), dtype=float) @ qd
            potential[i] = 0.5 * q @ K @ q
        return kinetic, potential

    return energy


def random_initial_state(system, rng):
    n = len(system.coordinate_names)
    torsion = np.array([name.startswith("alpha") for name in system.coordinate_names])
    q = np.where(torsion, rng.normal(0.0, 1e-2, n), rng.normal(0.0, 1e-4, n))
    qd = np.where(torsion, rng.normal(0.0, 1.0, n), rng.normal(0.0, 1e-2, n))
    return np.concatenate([q, qd])


CONSERVATIVE_CASES = {
    # constant mass matrix; the spin only adds J Omega alpha', which does no work
    "spinning_centred": dict(speed=200.0),
    # state-dependent mass matrix M(alpha): -m e sin(alpha + phase), ... (scleronomic at zero speed)
    "eccentric_at_rest": dict(speed=0.0, e2=5e-3, e3=3e-3),
}


@pytest.mark.parametrize("case", list(CONSERVATIVE_CASES))
def test_energy_conserved_and_drift_shrinks_with_rtol(case):
    model = three_station_rotor(**CONSERVATIVE_CASES[case])
    assert model.coordinate_names == ("x1", "x2", "x3", "y1", "y2", "y3", "alpha2", "alpha3")
    energy = energy_function(model)
    system = model.compile(backend="numba" if "numba" in rotorkit.available_backends() else "python")
    y0 = random_initial_state(system, np.random.default_rng(7))
    drift = {}
    for rtol in (1e-6, 1e-10):
        result = simulate(system, (0.0, 0.5), y0=y0, method="DOP853", rtol=rtol, atol=rtol * 1e-6,
                          sample_rate=2_000.0)
        T, V = energy(result.t, result.y)
        E = T + V
        drift[rtol] = np.max(np.abs(E / E[0] - 1.0))
        # not a trivial run: energy flows between kinetic and potential forms
        assert np.ptp(T / E) > 0.2
    assert drift[1e-10] < 1e-8  # achieved ~3e-10
    assert drift[1e-6] < 1e-3  # achieved ~7e-6
    assert drift[1e-10] < drift[1e-6] / 100.0  # achieved a factor ~3e4


def test_energy_check_detects_a_wrong_mass_matrix():
    """Control: with the eccentric coupling dropped from M, the 'energy' is not conserved."""
    model = three_station_rotor(speed=0.0, e2=5e-3, e3=3e-3)
    wrong = energy_function(model, mass_matrix=model.equations().linear_mass_matrix())
    right = energy_function(model)
    system = model.compile(backend="numba" if "numba" in rotorkit.available_backends() else "python")
    y0 = random_initial_state(system, np.random.default_rng(7))
    result = simulate(system, (0.0, 0.5), y0=y0, rtol=1e-10, atol=1e-16, sample_rate=2_000.0)
    E_right, E_wrong = sum(right(result.t, result.y)), sum(wrong(result.t, result.y))
    assert np.max(np.abs(E_right / E_right[0] - 1.0)) < 1e-8
    assert np.max(np.abs(E_wrong / E_wrong[0] - 1.0)) > 1e-6


# ---------------------------------------------------------------------------
# eccentric disk with torsion: the coupled mass matrix and equations
# ---------------------------------------------------------------------------

TORSION = dict(speed=150.0, m1=3.0, m=10.0, radius=0.075, e=2e-3, phase=0.4, k1=1e6, c1=200.0,
               kb=4e5, cb=50.0, kt=3e3, ct=0.7, g=9.81)


def torsional_disk_model(v=TORSION):
    """Lumped mass at station 1 (supported, no torsion) and an eccentric torsional disk at station 2."""
    return Model([
        Rotor(name="R", stations=(1, 2), speed=v["speed"]),
        LumpedMass(station=1, mass=v["m1"]),
        Disk(station=2, mass=v["m"], radius=v["radius"], eccentricity=v["e"], phase=v["phase"], torsion=True),
        ShaftSegment(start=1, end=2, bending_stiffness=v["kb"], bending_damping=v["cb"],
                     torsional_stiffness=v["kt"], torsional_damping=v["ct"]),
        ElasticSupport(station=1, stiffness=v["k1"], damping=v["c1"]),
        Maneuver.steady(gravity=v["g"]),
    ], name="torsional_disk")


def hand_derived_accelerations(t, y, v=TORSION):
    """q'' of the torsional disk model from Lagrange's equations written out by hand.

    T = 1/2 m1 (x1'^2 + y1'^2) + 1/2 m |v_G|^2 + 1/2 J phi'^2, centroid at
    (x2 + e cos phi, y2 + e sin phi), phi = Omega t + phase + alpha2, J = m R^2/2:

        m x2'' - m e sin(phi) alpha'' = Q_x2 + m e phi'^2 cos(phi)
        m y2'' + m e cos(phi) alpha'' = Q_y2 + m e phi'^2 sin(phi)
        -m e sin(phi) x2'' + m e cos(phi) y2'' + (J + m e^2) alpha'' = Q_alpha

    Gravity acts on x/y only (no torsional term), the torsion spring ties
    alpha2 to the drive.
    """
    x1, x2, y1, y2, a = y[:5]
    x1d, x2d, y1d, y2d, ad = y[5:]
    m, e, m1 = v["m"], v["e"], v["m1"]
    J = m * v["radius"] ** 2 / 2
    phi, phid = v["speed"] * t + v["phase"] + a, v["speed"] + ad
    s, c = math.sin(phi), math.cos(phi)
    kb, cb = v["kb"], v["cb"]
    Q = {
        "x1": -v["k1"] * x1 - v["c1"] * x1d - kb * (x1 - x2) - cb * (x1d - x2d),
        "y1": -v["k1"] * y1 - v["c1"] * y1d - kb * (y1 - y2) - cb * (y1d - y2d) - m1 * v["g"],
        "x2": -kb * (x2 - x1) - cb * (x2d - x1d),
        "y2": -kb * (y2 - y1) - cb * (y2d - y1d) - m * v["g"],
        "a": -v["kt"] * a - v["ct"] * ad,
    }
    A = np.array([[m, 0, -m * e * s], [0, m, m * e * c], [-m * e * s, m * e * c, J + m * e**2]])
    b = np.array([Q["x2"] + m * e * phid**2 * c, Q["y2"] + m * e * phid**2 * s, Q["a"]])
    x2dd, y2dd, add = np.linalg.solve(A, b)
    return np.array([Q["x1"] / m1, x2dd, Q["y1"] / m1, y2dd, add])


def test_torsional_disk_mass_matrix_entries():
    v = TORSION
    model = torsional_disk_model()
    eq = model.equations()
    assert tuple(map(str, eq.coordinates)) == ("x1", "x2", "y1", "y2", "alpha2")
    values = {p: model.parameters[p.name] for p in eq.parameters}
    ix, iy, ia = 1, 3, 4
    M = eq.mass_matrix
    J = v["m"] * v["radius"] ** 2 / 2
    t_sym, alpha = eq.t, eq.coordinates[ia]
    for t, a in [(0.0, 0.0), (0.013, 0.2), (1.7, -0.05), (2.345, 1.3)]:
        at = {**values, t_sym: t, alpha: a}
        phi = v["speed"] * t + v["phase"] + a
        assert float(M[ix, ia].subs(at)) == pytest.approx(-v["m"] * v["e"] * math.sin(phi), rel=1e-12, abs=1e-15)
        assert float(M[ia, ix].subs(at)) == pytest.approx(-v["m"] * v["e"] * math.sin(phi), rel=1e-12, abs=1e-15)
        assert float(M[iy, ia].subs(at)) == pytest.approx(v["m"] * v["e"] * math.cos(phi), rel=1e-12, abs=1e-15)
        assert float(M[ia, ia].subs(at)) == pytest.approx(J + v["m"] * v["e"] ** 2, rel=1e-12)
        assert float(M[ix, ix].subs(at)) == pytest.approx(v["m"], rel=1e-12)
        assert float(M[0, 0].subs(at)) == pytest.approx(v["m1"], rel=1e-12)
        assert float(M[ix, iy].subs(at)) == 0.0
        assert float(M[0, ia].subs(at)) == 0.0
    # the constant part, as printed in papers: diag(m1, m, m1, m, J + m e^2)
    constant = np.array(eq.linear_mass_matrix().subs(values), dtype=float)
    np.testing.assert_allclose(constant, np.diag([v["m1"], v["m"], v["m1"], v["m"], J + v["m"] * v["e"] ** 2]),
                               rtol=1e-12)


@pytest.mark.parametrize("backend", rotorkit.available_backends())
def test_torsional_disk_rhs_matches_hand_derived_lagrange(backend):
    system = torsional_disk_model().compile(backend=backend)
    assert system.state_names[:5] == ("x1", "x2", "y1", "y2", "alpha2")
    rng = np.random.default_rng(3)
    for _ in range(20):
        t = rng.uniform(0.0, 5.0)
        y = np.concatenate([rng.normal(0, 1e-4, 4), rng.normal(0, 0.05, 1),
                            rng.normal(0, 1e-2, 4), rng.normal(0, 2.0, 1)])
        dydt = system.rhs(t, y)
        np.testing.assert_allclose(dydt[:5], y[5:], rtol=0, atol=0)
        expected = hand_derived_accelerations(t, y)
        np.testing.assert_allclose(dydt[5:], expected, rtol=1e-9, atol=1e-9 * np.max(np.abs(expected)))


# ---------------------------------------------------------------------------
# back ends
# ---------------------------------------------------------------------------


def _random_states(system, rng, count):
    for _ in range(count):
        torsion = np.array([n.startswith("alpha") for n in system.coordinate_names])
        q = np.where(torsion, rng.normal(0.0, 2e-2, torsion.size), rng.normal(0.0, 2e-4, torsion.size))
        qd = np.where(torsion, rng.normal(0.0, 3.0, torsion.size), rng.normal(0.0, 0.2, torsion.size))
        yield rng.uniform(0.0, 6.0), np.concatenate([q, qd])


@pytest.mark.skipif("numba" not in rotorkit.available_backends(), reason="numba not installed")
@pytest.mark.parametrize("which", ["jeffcott", "torsional_disk", "al31f"])
def test_python_and_numba_backends_agree(which):
    if which == "jeffcott":
        model = jeffcott(speed=130.0, eccentricity=1e-4, damping=damping_for(0.05), gravity=G)
    elif which == "torsional_disk":
        model = torsional_disk_model()
    else:  # rub contact, ball bearing with clearance, barrel roll: the guarded piecewise code paths
        model = rotorkit.preset("al31f")
    py, nb = model.compile(backend="python"), model.compile(backend="numba")
    assert (py.backend, nb.backend) == ("python", "numba")
    rng = np.random.default_rng(11)
    for t, y in _random_states(py, rng, 25):
        a, b = py.rhs(t, y), nb.rhs(t, y)
        assert np.all(np.isfinite(a))
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.max(np.abs(a)))
