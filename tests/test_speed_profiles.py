"""Speed profiles (run-up, coast-down) checked against independent integrations.

The reference for a Jeffcott rotor run through its critical speed is the
closed-form equation of motion of an eccentric disk on an isotropic
support, written by hand and integrated with scipy's ``solve_ivp``::

    m x'' + c x' + k x = m e (Omega^2 cos phi + Omega' sin phi)
    m y'' + c y' + k y = m e (Omega^2 sin phi - Omega' cos phi)

with ``Omega`` from ``numpy.interp`` (held at the end values outside the
table) and ``phi`` the integral of ``Omega`` computed here segment by
segment with the trapezoid rule (exact for a linear segment).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

from rotorkit import Disk, ElasticSupport, Model, ParameterError, Rotor, simulate
from rotorkit.elements import SpeedProfile

MASS, STIFFNESS, DAMPING, ECC = 2.0, 2.0e4, 8.0, 1.0e-4  # wn = 100 rad/s, zeta = 0.02
WN = math.sqrt(STIFFNESS / MASS)


def jeffcott(speed, *, phase=0.3):
    return Model([
        Rotor(name="R", stations=(1,), speed=speed),
        Disk(station=1, mass=MASS, radius=0.1, eccentricity=ECC, phase=phase),
        ElasticSupport(station=1, stiffness=STIFFNESS, damping=DAMPING),
    ])


def reference_angle(t, times, speeds):
    """integral_0^t of the held piecewise-linear speed, by hand (t >= 0, times[0] >= 0)."""
    knots = np.concatenate(([0.0], times))
    values = np.interp(knots, times, speeds)
    total = 0.0
    for a, b, wa, wb in zip(knots[:-1], knots[1:], values[:-1], values[1:]):
        if t <= a:
            break
        u = min(t, b)
        wu = wa + (wb - wa) * (u - a) / (b - a) if b > a else wa
        total += 0.5 * (wa + wu) * (u - a)
    if t > knots[-1]:
        total += speeds[-1] * (t - knots[-1])
    return total


def reference_run(times, speeds, t_end, t_eval, phase=0.3):
    times, speeds = np.asarray(times, float), np.asarray(speeds, float)
    slopes = np.diff(speeds) / np.diff(times)

    def accel(t):
        i = np.searchsorted(times, t, side="right") - 1
        return slopes[i] if 0 <= i < len(slopes) else 0.0

    def rhs(t, z):
        x, y, vx, vy = z
        w = np.interp(t, times, speeds)
        phi = reference_angle(t, times, speeds) + phase
        a = accel(t)
        fx = MASS * ECC * (w * w * math.cos(phi) + a * math.sin(phi))
        fy = MASS * ECC * (w * w * math.sin(phi) - a * math.cos(phi))
        return [vx, vy, (fx - DAMPING * vx - STIFFNESS * x) / MASS, (fy - DAMPING * vy - STIFFNESS * y) / MASS]

    # integrate segment by segment so the solver never steps across a jump of Omega'
    edges = sorted({0.0, t_end, *[s for s in times if 0.0 < s < t_end]})
    z, out_t, out_z = np.zeros(4), [], []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = t_eval[(t_eval >= a) & ((t_eval < b) | (b == t_end))]
        sol = solve_ivp(rhs, (a, b), z, method="DOP853", rtol=1e-11, atol=1e-15, t_eval=sel)
        out_t.append(sol.t)
        out_z.append(sol.y)
        z = solve_ivp(rhs, (a, b), z, method="DOP853", rtol=1e-11, atol=1e-15).y[:, -1]
    return np.concatenate(out_t), np.concatenate(out_z, axis=1)


def test_run_up_through_critical_speed_matches_hand_written_equations():
    times, speeds = [0.1, 1.1, 1.6], [20.0, 180.0, 150.0]  # through wn = 100 rad/s, then a coast-down
    model = jeffcott(SpeedProfile.table(times=times, speeds=speeds))
    system = model.compile(backend="python")
    assert system.time_events == (0.1, 1.1, 1.6)
    result = simulate(system, (0.0, 2.0), rtol=1e-10, atol=1e-14, sample_rate=1000.0)
    t_ref, z_ref = reference_run(times, speeds, 2.0, result.t)
    np.testing.assert_allclose(t_ref, result.t)
    scale = np.max(np.abs(z_ref[0]))
    assert scale > 3 * ECC  # it did pass through a resonance (static whirl radius e at high speed)
    np.testing.assert_allclose(result["x1"], z_ref[0], atol=2e-6 * scale)
    np.testing.assert_allclose(result["y1"], z_ref[1], atol=2e-6 * scale)


def test_tangential_unbalance_load_is_m_e_alpha():
    """At t = 0.5 (Omega = 80, alpha = 160 rad/s^2) with the disk at rest on the axis."""
    model = jeffcott(SpeedProfile.table(times=[0.0, 1.0], speeds=[0.0, 160.0]), phase=0.0)
    system = model.compile(backend="python")
    t = 0.5
    phi = 160.0 * t**2 / 2  # exact angle of a linear run-up from rest
    acc = system.rhs(t, np.zeros(4))[2:]
    expected = ECC * np.array([80.0**2 * math.cos(phi) + 160.0 * math.sin(phi),
                               80.0**2 * math.sin(phi) - 160.0 * math.cos(phi)])
    np.testing.assert_allclose(acc, expected, rtol=1e-12)


def test_constant_profile_equals_constant_speed_model():
    const = jeffcott(120.0).compile(backend="python")
    flat = jeffcott(SpeedProfile.table(times=[0.0, 5.0], speeds=[120.0, 120.0])).compile(backend="python")
    rng = np.random.default_rng(1)
    for t in (0.0, 0.3, 2.5, 7.0):
        y = rng.normal(scale=1e-4, size=4)
        np.testing.assert_allclose(flat.rhs(t, y), const.rhs(t, y), rtol=1e-12, atol=1e-12)
    a = simulate(const, (0.0, 0.5), rtol=1e-10, atol=1e-14, sample_rate=2000.0)
    b = simulate(flat, (0.0, 0.5), rtol=1e-10, atol=1e-14, sample_rate=2000.0)
    np.testing.assert_allclose(b["x1"], a["x1"], atol=1e-9 * np.max(np.abs(a["x1"])))


def test_constant_speed_equations_unchanged():
    eom = jeffcott(120.0).equations()
    t, m, e, w, ph = sp.symbols("t disk1_mass disk1_eccentricity R_speed disk1_phase", real=True)
    F = eom.nonlinear_forcing()
    assert sp.simplify(F[0] - m * e * w**2 * sp.cos(w * t + ph)) == 0
    assert "table" not in str(eom.forcing)


def test_table_holds_end_values_and_angle_is_piecewise_quadratic():
    prof = SpeedProfile.table(times=[1.0, 2.0, 4.0], speeds=[10.0, 30.0, 20.0])
    t = sp.Symbol("t", real=True)
    p = {k: sp.Float(v) for k, v in prof.values().items()}
    speed, angle = prof.speed(t, p), prof.angle(t, p)
    for tv in (-1.0, 0.0, 0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0):
        assert float(speed.subs(t, tv)) == pytest.approx(np.interp(tv, [1, 2, 4], [10, 30, 20]), abs=1e-12)
        if tv >= 0:
            assert float(angle.subs(t, tv)) == pytest.approx(reference_angle(tv, [1, 2, 4], [10, 30, 20]), abs=1e-12)
    # the derivative of the angle is the speed, of the speed the segment slope
    assert float(sp.diff(angle, t).subs(t, 1.5)) == pytest.approx(20.0)
    assert float(sp.diff(speed, t).subs(t, 3.0)) == pytest.approx(-5.0)
    assert float(sp.diff(speed, t).subs(t, 5.0)) == 0.0


def test_expression_profile_parameters_and_integrated_angle():
    prof = SpeedProfile.expression(lambda t, w0, a: w0 + a * t, parameters={"w0": 10.0, "a": 50.0})
    model = jeffcott(prof)
    assert {"R_speed_w0", "R_speed_a"} <= set(model.parameters)
    system = model.compile(backend="python")
    t, phi = 0.4, 10.0 * 0.4 + 50.0 * 0.4**2 / 2 + 0.3
    w = 10.0 + 50.0 * t
    acc = system.rhs(t, np.zeros(4))[2:]
    np.testing.assert_allclose(acc, ECC * np.array([w * w * math.cos(phi) + 50 * math.sin(phi),
                                                    w * w * math.sin(phi) - 50 * math.cos(phi)]), rtol=1e-12)
    # values change without a new derivation
    faster = system.with_parameters(R_speed_a=80.0)
    assert faster.structure_key == system.structure_key
    w, phi = 10.0 + 80.0 * t, 10.0 * t + 80.0 * t**2 / 2 + 0.3
    np.testing.assert_allclose(faster.rhs(t, np.zeros(4))[2], ECC * (w * w * math.cos(phi) + 80 * math.sin(phi)),
                               rtol=1e-12)


def test_table_values_are_parameters():
    model = jeffcott(SpeedProfile.table(times=[0.0, 1.0], speeds=[0.0, 100.0]))
    changed = model.with_values(R_speed_w1=200.0, R_speed_t1=2.0)
    assert changed.structure_key == model.structure_key
    assert changed.parameters["R_speed_w1"] == 200.0
    with pytest.raises(ParameterError, match="strictly increasing"):
        model.with_values(R_speed_t1=-1.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(times=[0.0, 1.0, 1.0], speeds=[0, 1, 2]), "not strictly increasing at index 2"),
    (dict(times=[0.0, 2.0, 1.0], speeds=[0, 1, 2]), "not strictly increasing"),
    (dict(times=[0.0, 1.0], speeds=[0, 1, 2]), "times has 2 entries but speeds has 3"),
    (dict(times=[0.0], speeds=[1.0]), "at least 2 points"),
    (dict(times=[0.0, float("nan")], speeds=[1.0, 2.0]), r"times\[1\]"),
    (dict(times="0 1", speeds=[1.0, 2.0]), "expected a sequence"),
])
def test_bad_tables_raise_named_errors(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        SpeedProfile.table(**kwargs)


def test_bad_expressions_raise_named_errors():
    with pytest.raises(ParameterError, match="unknown symbols"):
        SpeedProfile.expression(lambda t: sp.Symbol("k") * t)
    with pytest.raises(ParameterError, match="calling it failed"):
        SpeedProfile.expression(lambda t, a: a * t)
    with pytest.raises(ParameterError, match="cannot integrate"):
        SpeedProfile.expression(lambda t: sp.Piecewise((t, t < 1), (1, True)))
