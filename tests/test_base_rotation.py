"""Base rotation loads against hand-derived closed forms.

- Steady level turn at rate W about a vertical axis at distance R: the
  centripetal load on a mass at rest is m W^2 R, outward.
- Coriolis: a mass moving at v along y in a base turning at W_z about the
  rotor axis feels 2 m W_z v along x.
- Euler: a pitch acceleration W_x' = a acting on a station at axial
  position z_s gives F_y = m a z_s.
- A Jeffcott rotor (k, m) in a base turning at W_z about the rotor axis:
  with z = x + i y, m z'' + 2 i m W z' + (k - m W^2) z = 0, so its whirl
  frequencies seen in the base are wn - W and wn + W.
- Coriolis forces do no work: the Jacobi integral
  1/2 m |q'|^2 + 1/2 (k - m W^2) |q|^2 is conserved by an undamped run.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from rotorkit import ElasticSupport, LumpedMass, Maneuver, Model, ParameterError, Rotor, simulate
from rotorkit.analysis.modes import linearize
from rotorkit.elements import BaseRotation

M, K = 2.0, 2.0e4
WN = math.sqrt(K / M)


def jeffcott(base, *extra):
    return Model([Rotor(name="R", stations=(1,), speed=300.0), LumpedMass(station=1, mass=M),
                  ElasticSupport(station=1, stiffness=K), base, *extra])


def test_steady_turn_centripetal_load_m_W2_R():
    W, R = 0.5, 800.0
    system = jeffcott(BaseRotation(rate_y=W, center_x=-R)).compile(backend="python")
    acc = system.rhs(0.0, np.zeros(4))[2:]
    np.testing.assert_allclose(acc, [W * W * R, 0.0], atol=1e-12)
    # with gravity as a Maneuver field the two add
    system = jeffcott(BaseRotation(rate_y=W, center_x=-R), Maneuver.steady()).compile(backend="python")
    np.testing.assert_allclose(system.rhs(0.0, np.zeros(4))[2:], [W * W * R, -9.81], atol=1e-12)


def test_coriolis_load_2_m_Wz_v():
    W, v = 3.0, 0.2
    system = jeffcott(BaseRotation(rate_z=W)).compile(backend="python")
    acc = system.rhs(0.0, np.array([0.0, 0.0, 0.0, v]))[2:]
    np.testing.assert_allclose(acc, [2 * W * v, 0.0], atol=1e-12)


def test_euler_load_of_a_pitch_acceleration():
    a, z = 4.0, 0.5
    base = BaseRotation(rate=(lambda t: a * t, lambda t: 0, lambda t: 0), axial_positions={1: z})
    system = jeffcott(base).compile(backend="python")
    # at t = 0 (W = 0) only the Euler term: F_y = m a z
    np.testing.assert_allclose(system.rhs(0.0, np.zeros(4))[2:], [0.0, a * z], atol=1e-12)
    # at t = 1: W_x = a, centripetal -m W x (W x r) along y is zero for r along the axis; along y it is m W^2 y
    y = 1e-3
    acc = system.rhs(1.0, np.array([0.0, y, 0.0, 0.0]))[2:]
    np.testing.assert_allclose(acc, [0.0, a * z + a * a * y - K * y / M], rtol=1e-12)


def test_rotating_base_splits_whirl_frequencies():
    W = 7.0
    system = jeffcott(BaseRotation(rate_z=W)).compile(backend="python")
    A = linearize(system, np.zeros(2), method="analytic")[0]
    w = np.sort(np.abs(np.linalg.eigvals(A).imag))
    np.testing.assert_allclose(w, [WN - W, WN - W, WN + W, WN + W], rtol=1e-10)


def test_coriolis_does_no_work_jacobi_integral_conserved():
    W = 20.0
    system = jeffcott(BaseRotation(rate_z=W)).compile(backend="python")
    y0 = system.initial_state(x1=1e-3, y1_dot=0.05)
    result = simulate(system, (0.0, 1.0), y0=y0, rtol=1e-11, atol=1e-16, sample_rate=2000.0)
    q2 = result["x1"] ** 2 + result["y1"] ** 2
    v2 = result["x1_dot"] ** 2 + result["y1_dot"] ** 2
    h = 0.5 * M * v2 + 0.5 * (K - M * W * W) * q2
    assert np.ptp(h) < 1e-7 * h[0]
    # and the motion is not trivial: Coriolis turns the orbit
    assert np.max(np.abs(result["y1"])) > 1e-4


def test_loads_match_the_vector_formula_symbolically():
    base = BaseRotation(rate_x=0.3, rate_y=-0.2, rate_z=0.7, center_x=1.0, center_y=-2.0, center_z=0.5,
                        axial_positions={1: 0.25})
    eom = jeffcott(base).equations()
    F = eom.forces["base_rotation"]
    x, y, xd, yd = eom.coordinates + eom.speeds
    p = {s.name: s for s in eom.parameters}
    W = sp.Matrix([p["base_rotation_rate_x"], p["base_rotation_rate_y"], p["base_rotation_rate_z"]])
    c = sp.Matrix([p["base_rotation_center_x"], p["base_rotation_center_y"], p["base_rotation_center_z"]])
    r = sp.Matrix([x, y, sp.Rational(1, 4)]) - c
    # hand-expanded: W x (W x r) = W (W.r) - r |W|^2 ; Coriolis 2 W x (x', y', 0)
    m = p["mass1_mass"]
    acc = W * W.dot(r) - r * W.dot(W) + 2 * sp.Matrix([-W[2] * yd, W[2] * xd, W[0] * yd - W[1] * xd])
    assert sp.simplify(F[0] + m * acc[0]) == 0
    assert sp.simplify(F[1] + m * acc[1]) == 0


@pytest.mark.parametrize("kwargs, match", [
    (dict(rate=(lambda t: t,)), "three functions"),
    (dict(rate=(lambda t: t, lambda t: sp.Symbol("q"), lambda t: 0)), "unknown symbols"),
    (dict(axial_positions={-1: 0.2}), "axial_positions"),
    (dict(axial_positions=3), "expected a dict"),
    (dict(event_times=1.0), "event_times"),
    (dict(rate_x="fast"), "rate_x"),
])
def test_bad_input_raises_named_errors(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        BaseRotation(**kwargs)
