"""Bearings on pedestals (support masses) and moment bearing coefficients, against closed forms.

- Journal m1 on a bearing k1 on a pedestal m2 with k2, c2 to the ground, per
  direction: ``det([[m1 s^2 + k1, -k1], [-k1, m2 s^2 + c2 s + k1 + k2]]) = 0``
  (undamped: ``w^2 = (b -/+ sqrt(b^2 - 4 m1 m2 k1 k2)) / (2 m1 m2)``,
  ``b = m1 (k1 + k2) + m2 k1``), anisotropic bearing and pedestal.
- Static sag under gravity: pedestal ``(m1 + m2) g / k2``, journal
  ``m1 g / k1`` more.
- Moment coefficients: the moment on the journal is ``-K_t theta - C_t theta'``
  (full unsymmetric matrices, to ground and inter-shaft); a rigid rotor
  (disk between two bearings at +/- a) has the conical modes of
  ``(2 k_x a^2 + 2 kt_yy - I_d w^2)(2 k_y a^2 + 2 kt_xx - I_d w^2) = (I_p Omega w)^2``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg
import sympy as sp

from rotorkit import Disk, LumpedMass, Maneuver, Model, ParameterError, Rotor, TopologyError
from rotorkit.elements import BeamSegment, LinearBearing, Material, Pedestal
from rotorkit.modelfile import dumps_model, loads_model

STEEL = Material.steel()
M1, M2 = 2.0, 5.0


def on_pedestal(bearing_kw=None, pedestal_kw=None, extra=()):
    pedestal = Pedestal(**{"mass": M2, "kxx": 3e4, "kyy": 1.5e4, **(pedestal_kw or {})})
    bearing = LinearBearing(station=1, **{"kxx": 2e4, "kyy": 1e4, **(bearing_kw or {})}, pedestal=pedestal)
    return Model([Rotor(name="R", stations=(1,), speed=300.0), LumpedMass(station=1, mass=M1), bearing, *extra])


def eigenvalues(model):
    """(eigenvalues, M, K, C) of the derived equations linearised at rest (generalised eigenproblem)."""
    eom = model.equations()
    values = {p: sp.Float(model.parameters[str(p)]) for p in eom.parameters}
    values[eom.t] = sp.S.Zero
    zero = {s: sp.S.Zero for s in eom.coordinates + eom.speeds}
    f = sp.Matrix(eom.forcing).xreplace(values)  # numbers first: small expressions
    M = np.array(sp.Matrix(eom.mass_matrix).xreplace(values).xreplace(zero), dtype=float)
    K = -np.array(f.jacobian(eom.coordinates).xreplace(zero), dtype=float)
    C = -np.array(f.jacobian(eom.speeds).xreplace(zero), dtype=float)
    n = len(M)
    # no inverse of M: the near-massless shafts below have tiny tilt inertias
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    lam = scipy.linalg.eig(A, B, right=False)
    return lam[np.isfinite(lam)], M, K, C


def test_pedestal_two_dof_frequencies_anisotropic():
    model = on_pedestal()
    assert model.coordinate_names == ("x1", "y1", "px1", "py1")
    expected = []
    for k1, k2 in ((2e4, 3e4), (1e4, 1.5e4)):
        b = M1 * (k1 + k2) + M2 * k1
        root = math.sqrt(b * b - 4 * M1 * M2 * k1 * k2)
        expected += [math.sqrt((b - root) / (2 * M1 * M2)), math.sqrt((b + root) / (2 * M1 * M2))]
    lam = eigenvalues(model)[0]
    np.testing.assert_allclose(np.sort(np.abs(lam.imag)), np.sort(np.repeat(expected, 2)), rtol=1e-10)
    assert np.max(np.abs(lam.real)) < 1e-9


def test_pedestal_damping_roots_of_the_characteristic_polynomial():
    c2x, c2y = 40.0, 15.0
    model = on_pedestal(pedestal_kw={"cxx": c2x, "cyy": c2y})
    expected = []
    for k1, k2, c2 in ((2e4, 3e4, c2x), (1e4, 1.5e4, c2y)):
        # (m1 s^2 + k1)(m2 s^2 + c2 s + k1 + k2) - k1^2
        poly = np.polysub(np.polymul([M1, 0, k1], [M2, c2, k1 + k2]), [k1 * k1])
        expected += list(np.roots(poly))
    lam, expected = eigenvalues(model)[0], np.array(expected)
    np.testing.assert_allclose(lam[np.argsort(lam.imag)], expected[np.argsort(expected.imag)], rtol=1e-9)


def test_no_pedestal_adds_no_coordinates_or_terms():
    plain = Model([Rotor(name="R", stations=(1,), speed=300.0), LumpedMass(station=1, mass=M1),
                   LinearBearing(station=1, kxx=2e4, kyy=1e4)])
    assert plain.coordinate_names == ("x1", "y1")
    assert not any(k.startswith("linearbearing1_pedestal") for k in plain.parameters)
    assert plain.equations().kinetic.free_symbols == {sp.Symbol(n, real=True) for n in
                                                      ("x1_dot", "y1_dot", "mass1_mass")}


def test_pedestal_values_are_parameters():
    model = on_pedestal()
    assert model.parameters["linearbearing1_pedestal_mass"] == M2
    heavier = model.with_values(linearbearing1_pedestal_mass=4 * M2, linearbearing1_pedestal_kyy="30 kN/m")
    assert heavier.structure_key == model.structure_key  # no new derivation
    assert heavier.elements[2].pedestal.kyy == 3e4
    m2, expected = 4 * M2, []
    for k1, k2 in ((2e4, 3e4), (1e4, 3e4)):
        b = M1 * (k1 + k2) + m2 * k1
        root = math.sqrt(b * b - 4 * M1 * m2 * k1 * k2)
        expected += [math.sqrt((b - root) / (2 * M1 * m2)), math.sqrt((b + root) / (2 * M1 * m2))]
    w = np.sort(np.abs(eigenvalues(heavier)[0].imag))
    np.testing.assert_allclose(w, np.sort(np.repeat(expected, 2)), rtol=1e-10)


def test_gravity_sags_pedestal_and_journal():
    g = 9.81
    model = on_pedestal(extra=[Maneuver.steady(gravity=g)])
    eom = model.equations()
    _, _, K, _ = eigenvalues(model)
    values = {p: model.parameters[str(p)] for p in eom.parameters}
    zero = {s: 0 for s in eom.coordinates + eom.speeds}
    F = np.array(sp.Matrix(eom.forcing).subs(eom.t, 0).subs(values).subs(zero), dtype=float).ravel()
    q = dict(zip(model.coordinate_names, np.linalg.solve(K, F)))
    assert q["py1"] == pytest.approx(-(M1 + M2) * g / 1.5e4, rel=1e-12)
    assert q["y1"] - q["py1"] == pytest.approx(-M1 * g / 1e4, rel=1e-12)
    assert q["x1"] == pytest.approx(0.0, abs=1e-15)


def test_pedestal_and_moment_coefficients_round_trip_through_model_files():
    model = rigid_rotor(3000.0, pedestal=Pedestal(mass=30.0, kxx=5e7, kyy=2e7, cyy=500.0),
                        ktxy=1e3, ktyx=-2e3, ctxx=4.0)
    again, _ = loads_model(dumps_model(model))
    assert again.parameters == model.parameters
    assert again.structure_key == model.structure_key
    assert again.elements[-1].pedestal == model.elements[-1].pedestal


@pytest.mark.parametrize("kwargs, error, match", [
    (dict(pedestal={"mass": 1.0}), ParameterError, "expected a Pedestal"),
    (dict(other_station=2, pedestal=Pedestal(mass=1.0, kxx=1.0, kyy=1.0)), ParameterError, "inter-shaft"),
    (dict(ktxx=-1.0), ParameterError, "ktxx"),
])
def test_bad_bearing_input_raises_named_errors(kwargs, error, match):
    with pytest.raises(error, match=match):
        LinearBearing(station=1, kxx=1.0, kyy=1.0, **kwargs)


@pytest.mark.parametrize("kwargs, match", [
    (dict(kxx=1.0, kyy=1.0), "mass is required"),
    (dict(mass=0.0, kxx=1.0, kyy=1.0), "mass"),
    (dict(mass=1.0, kyy=1.0), "kxx is required"),
    (dict(mass=1.0, kxx=1.0, kyy=1.0, cxx=-2.0), "cxx"),
])
def test_bad_pedestal_input_raises_named_errors(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        Pedestal(**kwargs)


def test_two_pedestals_at_one_station_and_tilt_without_tilts_are_topology_errors():
    p = Pedestal(mass=1.0, kxx=1e4, kyy=1e4)
    with pytest.raises(TopologyError, match="second pedestal"):
        Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=1.0),
               LinearBearing(station=1, kxx=1e4, kyy=1e4, pedestal=p),
               LinearBearing(name="other", station=1, kxx=1e4, kyy=1e4, pedestal=p)])
    with pytest.raises(TopologyError, match="thx1, thy1"):
        Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=1.0),
               LinearBearing(station=1, kxx=1e4, kyy=1e4, ktxx=1.0, ktyy=1.0)])


# -- moment (tilt) coefficients -------------------------------------------------------------------------
def rigid_rotor(speed, *, a=0.2, kx=1.0e6, ky=0.6e6, ktxx=2.0e4, ktyy=5.0e4, pedestal=None, **tilt):
    disk = Disk.from_geometry(station=2, width=0.05, outer_diameter=0.3, material=STEEL)
    rigid = Material(density=1e-6, youngs_modulus=STEEL.youngs_modulus * 1e4, shear_modulus=STEEL.shear_modulus * 1e4)
    return Model([Rotor(name="R", stations=(1, 2, 3), speed=speed), disk,
                  BeamSegment(name="left", start=1, end=2, length=a, outer_diameter=0.05, material=rigid),
                  BeamSegment(name="right", start=2, end=3, length=a, outer_diameter=0.05, material=rigid),
                  LinearBearing(station=1, kxx=kx, kyy=ky, ktxx=ktxx, ktyy=ktyy, **tilt),
                  LinearBearing(station=3, kxx=kx, kyy=ky, ktxx=ktxx, ktyy=ktyy, pedestal=pedestal, **tilt)])


@pytest.mark.parametrize("speed", [0.0, 3000.0])
def test_rigid_rotor_tilting_modes_with_moment_stiffness(speed):
    a, kx, ky, ktxx, ktyy = 0.2, 1.0e6, 0.6e6, 2.0e4, 5.0e4
    model = rigid_rotor(speed)
    disk = model.elements[1]
    m, Id, Ip = disk.mass, disk.diametral_inertia, disk.polar_inertia
    cylindrical = [math.sqrt(2 * ky / m), math.sqrt(2 * kx / m)]
    kt_y = 2 * kx * a**2 + 2 * ktyy  # x-z plane: x = z thy
    kt_x = 2 * ky * a**2 + 2 * ktxx  # y-z plane: y = -z thx
    poly = [Id**2, -(Id * (kt_x + kt_y) + (Ip * speed) ** 2), kt_x * kt_y]
    conical = [math.sqrt(r.real) for r in np.roots(poly)]
    lam = eigenvalues(model)[0]
    w = np.sort(lam.imag[(lam.imag > 1e-6) & (lam.imag < 1e5)])  # above: the near-rigid shaft's own modes
    np.testing.assert_allclose(w, np.sort(cylindrical + conical), rtol=1e-4)


@pytest.mark.parametrize("inter_shaft", [False, True])
def test_moment_is_minus_kt_theta_minus_ct_theta_dot(inter_shaft):
    kt = np.array([[3e4, 2e3], [-5e3, 4e4]])
    ct = np.array([[7.0, -1.0], [2.5, 9.0]])
    coefficients = dict(ktxx=kt[0, 0], ktxy=kt[0, 1], ktyx=kt[1, 0], ktyy=kt[1, 1],
                        ctxx=ct[0, 0], ctxy=ct[0, 1], ctyx=ct[1, 0], ctyy=ct[1, 1])

    def model(**tilt):
        elements = [Rotor(name="A", stations=(1, 2), speed=100.0),
                    BeamSegment(start=1, end=2, length=0.3, outer_diameter=0.03, material=STEEL),
                    LinearBearing(station=1, kxx=1e6, kyy=1e6)]
        if inter_shaft:
            elements += [Rotor(name="B", stations=(3, 4), speed=-50.0),
                         BeamSegment(start=3, end=4, length=0.3, outer_diameter=0.05, material=STEEL),
                         LinearBearing(station=4, kxx=1e6, kyy=1e6),
                         LinearBearing(station=2, other_station=3, kxx=1e6, kyy=1e6, **tilt)]
        else:
            elements += [LinearBearing(station=2, kxx=1e6, kyy=1e6, **tilt)]
        return Model(elements)

    with_moments, without = model(**coefficients), model()
    eom, eom0 = with_moments.equations(), without.equations()
    assert eom.coordinates == eom0.coordinates
    names = [str(q) for q in eom.coordinates]
    values = {p: with_moments.parameters[str(p)] for p in eom.parameters}
    values.update({p: without.parameters[str(p)] for p in eom0.parameters})
    rng = np.random.default_rng(3)
    state = dict(zip(eom.coordinates + eom.speeds, rng.normal(size=2 * eom.n)))
    diff = (sp.Matrix(eom.forcing) - sp.Matrix(eom0.forcing)).subs(values).subs(state).subs(eom.t, 0.1)
    diff = dict(zip(names, np.array(diff, dtype=float).ravel()))
    sym = dict(zip(names, eom.coordinates))
    speed = dict(zip(names, eom.speeds))
    theta = np.array([state[sym["thx2"]], state[sym["thy2"]]])
    theta_dot = np.array([state[speed["thx2"]], state[speed["thy2"]]])
    if inter_shaft:
        theta = theta - [state[sym["thx3"]], state[sym["thy3"]]]
        theta_dot = theta_dot - [state[speed["thx3"]], state[speed["thy3"]]]
    moment = -kt @ theta - ct @ theta_dot
    np.testing.assert_allclose([diff["thx2"], diff["thy2"]], moment, rtol=1e-10)
    if inter_shaft:
        np.testing.assert_allclose([diff["thx3"], diff["thy3"]], -moment, rtol=1e-10)
    others = [v for n, v in diff.items() if n not in ("thx2", "thy2", "thx3", "thy3")]
    np.testing.assert_allclose(others, 0.0, atol=1e-9)
