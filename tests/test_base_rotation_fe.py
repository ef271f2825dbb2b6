"""A turning base on finite-element rotors: gyroscopic moments and loads on distributed mass.

- The kinetic energy a turning base adds to a spinning, tilting body
  (``tilt_kinetic``, written out by hand) equals the second-order series of
  the exact ``T = 1/2 [I_d (w1^2 + w2^2) + I_p w3^2]`` with the angular
  velocity from the rotation matrices (derived here with sympy).
- Precession moment of a rigid disk: an overhung disk spinning at ``Omega``
  on a massless cantilever, the base pitching at ``W_x``: the disk needs the
  moment ``I_p Omega W_x`` about ``y``; the cantilever's tip then deflects by
  ``M L^2 / (2 EI)`` and tilts by ``M L / EI``.
- The same for a spinning shaft alone: a distributed moment
  ``rho I_p Omega W_x`` per length gives ``x(L) = m L^3 / (3 EI)``,
  ``thy(L) = m L^2 / (2 EI)``.
- Steady turn about a vertical axis at distance R: the beam's distributed
  mass feels the uniform centrifugal load ``rho A R W^2``: a simply
  supported shaft sags ``5 q L^4 / (384 EI)`` sideways.
"""

from __future__ import annotations

import math
import numpy as np
import pytest
import sympy as sp

from rotorkit import Disk, ElasticSupport, Model, Rotor, TopologyError
from rotorkit.elements import BaseRotation, BeamSegment, LinearBearing, Material, Pedestal
from rotorkit.elements.base_motion import tilt_kinetic, tilt_loads
from helpers import Clamp  # noqa: E402

STEEL = Material.steel()
E = STEEL.youngs_modulus


def static(model, t=0.0):
    """Coordinate name -> static deflection q = K^-1 F of the equations linearised at rest."""
    eom = model.equations()
    values = {p: sp.Float(model.parameters[str(p)]) for p in eom.parameters}
    values[eom.t] = sp.Float(t)
    zero = {s: sp.S.Zero for s in eom.coordinates + eom.speeds}
    f = sp.Matrix(eom.forcing).xreplace(values)
    K = -np.array(f.jacobian(eom.coordinates).xreplace(zero), dtype=float)
    F = np.array(f.xreplace(zero), dtype=float).ravel()
    return dict(zip(model.coordinate_names, np.linalg.solve(K, F)))


def test_tilt_kinetic_equals_the_series_of_the_exact_rigid_body_energy():
    a, b, ad, bd, Id, Ip, spin, eps = sp.symbols("a b ad bd I_d I_p Omega epsilon", real=True)
    W = sp.symbols("W_x W_y W_z", real=True)

    def Rx(t):
        return sp.Matrix([[1, 0, 0], [0, sp.cos(t), -sp.sin(t)], [0, sp.sin(t), sp.cos(t)]])

    def Ry(t):
        return sp.Matrix([[sp.cos(t), 0, sp.sin(t)], [0, 1, 0], [-sp.sin(t), 0, sp.cos(t)]])

    # body: turn thx about x, then thy about the new y, then spin; W given in the base frame
    relative = sp.Matrix([ad * sp.cos(b), bd, spin + ad * sp.sin(b)])
    omega = relative + Ry(b).T * Rx(a).T * sp.Matrix(W)
    T = (Id * (omega[0] ** 2 + omega[1] ** 2) + Ip * omega[2] ** 2) / 2
    added = T - T.subs({w: 0 for w in W})
    small = {a: eps * a, b: eps * b, ad: eps * ad, bd: eps * bd}
    f = added.subs(small)
    series = sp.expand(sum(sp.diff(f, eps, k).subs(eps, 0) / math.factorial(k) for k in range(3)))  # Taylor
    constant = series.subs({a: 0, b: 0, ad: 0, bd: 0})
    assert sp.simplify(series - constant - tilt_kinetic(Id, Ip, spin, (a, b), (ad, bd), W)) == 0


def test_tilt_loads_are_the_lagrange_equations_of_the_interpolated_energy():
    """Two-node tilt field with a symmetric Mr, time-varying base rates and spin: matrices vs differentiation."""
    t = sp.Symbol("t", real=True)
    q = sp.Matrix(sp.symbols("q0:4", real=True))
    u = sp.Matrix(sp.symbols("u0:4", real=True))
    Va = sp.Matrix([[1, 0, 0, 0], [0, 0, 1, 0]])  # thx at the two nodes
    Vb = sp.Matrix([[0, 1, 0, 0], [0, 0, 0, 1]])
    Mr = sp.Matrix([[sp.Rational(1, 3), sp.Rational(1, 7)], [sp.Rational(1, 7), sp.Rational(2, 5)]])
    R = sp.Matrix([sp.Rational(1, 2), sp.Rational(3, 4)])
    W = (sp.sin(t), 2 * t, sp.Rational(1, 3) + t**2)
    Id, Ip, spin = sp.Rational(3, 2), sp.Rational(5, 2), 10 + 3 * t
    # the energy integrated by hand: int N^T N = Mr, int N^T = R over the fields a = N Va q, b = N Vb q
    a, b, ad, bd = sp.symbols("a b ad bd")
    energy = sp.Poly(tilt_kinetic(Id, Ip, spin, (a, b), (ad, bd), W), a, b, ad, bd)
    vec = {a: Va * q, b: Vb * q, ad: Va * u, bd: Vb * u}
    T = sp.S.Zero
    for monomial, c in zip(energy.monoms(), energy.coeffs()):
        gens = [g for g, power in zip((a, b, ad, bd), monomial) for _ in range(power)]
        if len(gens) == 2:
            T += c * (vec[gens[0]].T * Mr * vec[gens[1]])[0]
        elif len(gens) == 1:
            T += c * (R.T * vec[gens[0]])[0]
    lagrange = [sp.diff(T, q[i]) - (sp.diff(sp.diff(T, u[i]), t)
                                    + sum(sp.diff(sp.diff(T, u[i]), q[j]) * u[j] for j in range(4)))
                for i in range(4)]
    loads = tilt_loads(Id, Ip, spin, W, t, q, u, Va, Vb, Mr, R)
    assert all(sp.expand(loads[i] - lagrange[i]) == 0 for i in range(4))


def overhung(rate_x, speed, L=0.3, D=0.02):
    massless = Material(density=1e-9, youngs_modulus=E, shear_modulus=STEEL.shear_modulus)
    disk = Disk.from_geometry(station=2, width=0.03, outer_diameter=0.25, material=STEEL)
    return disk, Model([Rotor(name="R", stations=(1, 2), speed=speed), Clamp(station=1, stiffness=1e13), disk,
                        BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=massless,
                                    theory="euler-bernoulli", rotary_inertia=False),
                        BaseRotation(rate_x=rate_x, axial_positions={1: 0.0, 2: L})])


@pytest.mark.parametrize("speed", [1000.0, -1500.0])
def test_precession_moment_of_a_spinning_disk_bends_the_cantilever(speed):
    Wx, L, D = 0.5, 0.3, 0.02
    disk, model = overhung(Wx, speed, L, D)
    EI = E * math.pi * D**4 / 64
    moment = disk.polar_inertia * speed * Wx  # about +y: the base pitches the spin axis
    q = static(model)
    # the centrifugal terms of W_x (I_d W_x^2 on thy, m W_x^2 in y) change these by ~1e-5
    assert q["x2"] == pytest.approx(moment * L**2 / (2 * EI), rel=1e-4)
    assert q["thy2"] == pytest.approx(moment * L / EI, rel=1e-4)
    assert abs(q["y2"]) < 1e-9 * abs(q["x2"]) and abs(q["thx2"]) < 1e-9 * abs(q["thy2"])


def test_no_spin_no_precession_moment():
    _, model = overhung(0.5, 0.0)
    q = static(model)
    assert max(abs(v) for v in q.values()) < 1e-15


def test_spinning_shaft_carries_a_distributed_precession_moment():
    Wx, speed, L, D, n = 1.0, 3000.0, 0.5, 0.03, 4
    model = Model([Rotor(name="R", stations=(1, 2), speed=speed), Clamp(station=1, stiffness=1e14),
                   BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL,
                               theory="euler-bernoulli", elements=n),
                   BaseRotation(rate_x=Wx, axial_positions={1: 0.0})])
    EI = E * math.pi * D**4 / 64
    m = STEEL.density * math.pi * D**4 / 32 * speed * Wx  # rho I_p Omega W_x per unit length
    q = static(model)
    assert q["x2"] == pytest.approx(m * L**3 / (3 * EI), rel=1e-5)
    assert q["thy2"] == pytest.approx(m * L**2 / (2 * EI), rel=1e-5)


def test_steady_turn_sags_a_simply_supported_shaft_sideways():
    L, D, W, R = 1.5, 0.05, 0.5, 4.0e4  # R W^2 = 1e4 m/s^2 towards -x, the centre of the turn
    A, I = math.pi * D**2 / 4, math.pi * D**4 / 64
    model = Model([Rotor(name="R", stations=(1, 2), speed=0.0),
                   BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=STEEL,
                               theory="euler-bernoulli", rotary_inertia=False, elements=4),
                   ElasticSupport(station=1, stiffness=1e13), ElasticSupport(station=2, stiffness=1e13),
                   BaseRotation(rate_y=W, center_x=-R, axial_positions={1: 0.0, 2: L})])
    q = static(model)
    load = STEEL.density * A * R * W**2  # centrifugal, outwards: +x
    # the centripetal term also softens the shaft by rho A W^2 (a 3e-6 effect here)
    assert q["xbeam1_2_2"] == pytest.approx(5 * load * L**4 / (384 * E * I), rel=1e-5)
    assert abs(q["ybeam1_2_2"]) < 1e-12


def test_pedestal_mass_feels_the_turn():
    W, R, m1, m2 = 0.5, 100.0, 2.0, 5.0
    from rotorkit import LumpedMass

    model = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=m1),
                   LinearBearing(station=1, kxx=2e6, kyy=2e6, pedestal=Pedestal(mass=m2, kxx=3e6, kyy=3e6)),
                   BaseRotation(rate_y=W, center_x=-R)])
    q = static(model)
    # the softening m W^2 (2.5e-7 of the stiffnesses) is below the tolerance
    assert q["px1"] == pytest.approx((m1 + m2) * R * W**2 / 3e6, rel=1e-5)
    assert q["x1"] - q["px1"] == pytest.approx(m1 * R * W**2 / 2e6, rel=1e-5)


def test_beam_ends_inconsistent_with_its_length_is_a_topology_error():
    with pytest.raises(TopologyError, match="expected end = start \\+ length"):
        Model([Rotor(name="R", stations=(1, 2), speed=0.0),
               BeamSegment(start=1, end=2, length=0.5, outer_diameter=0.03, material=STEEL),
               ElasticSupport(station=1, stiffness=1e6), ElasticSupport(station=2, stiffness=1e6),
               BaseRotation(rate_y=0.1, axial_positions={1: 0.0, 2: 0.4})])


def test_lumped_model_without_tilts_is_unchanged_by_beam_support():
    """A Disk without diametral inertia gets no tilt terms from the turning base (lumped models unchanged)."""
    model = Model([Rotor(name="R", stations=(1,), speed=100.0), Disk(station=1, mass=2.0, radius=0.1),
                   ElasticSupport(station=1, stiffness=2e4), BaseRotation(rate_y=0.5, center_x=-10.0)])
    eom = model.equations()
    assert model.coordinate_names == ("x1", "y1")
    assert not any("thx" in str(s) for s in eom.forcing.free_symbols)
