"""Beam shaft elements and disks with inertia against closed forms and independent derivations.

- The element matrices derived from the energies with shape functions equal
  the Timoshenko element printed in Friswell et al., *Dynamics of Rotating
  Machines* (2010), section 5.4 (typed in below from the book's formulas).
- Uniform shafts: pinned-pinned Euler-Bernoulli ``w_k = (k pi / L)^2 sqrt(EI / rho A)``;
  cantilever and free-free from ``1 + cos(bL) cosh(bL) = 0`` and
  ``cos(bL) cosh(bL) = 1`` with ``w = b^2 sqrt(EI / rho A)``; pinned-pinned
  Timoshenko from the 2x2 frequency determinant of ``w = W sin kz``,
  ``beta = B cos kz``; convergence with the element count.
- Static sag of a simply supported shaft under gravity: ``5 rho A g L^4 / (384 EI)``.
- Overhung rigid disk on a massless cantilever: forward/backward whirl from
  ``(k11 - m w^2)(k22 - I_d w^2 +- I_p Omega w) - k12^2 = 0``.
- Rigid rotor (central disk) on anisotropic bearings: cylindrical modes
  ``sqrt(2 k / m)`` per direction; conical modes from
  ``(2 k_x a^2 - I_d w^2)(2 k_y a^2 - I_d w^2) = (I_p Omega w)^2``.
- The element-by-element derivation equals sympy's whole-system
  ``LagrangesMethod`` for a 2-element beam with a disk and bearings.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest
import scipy.linalg
import scipy.optimize
import sympy as sp

from rotorkit import Disk, ElasticSupport, Maneuver, Model, Rotor
from rotorkit.elements import BeamSegment, Material
from rotorkit.elements.base import Element, Terms
from rotorkit.elements.beam import cowper_shear_coefficient, plane_template
from rotorkit.errors import ParameterError, TopologyError
from helpers import Clamp  # noqa: E402

STEEL = Material.steel()
E, G, RHO = STEEL.youngs_modulus, STEEL.shear_modulus, STEEL.density
PIN = 1e13  # N/m: a pinned support


@dataclass(frozen=True, slots=True, kw_only=True)
class AxisSupport(Element):
    """Test-local: an orthotropic support, kxx in x and kyy in y."""

    station: int = None
    kxx: float = None
    kyy: float = None
    _units = {"kxx": ("N/m", "positive"), "kyy": ("N/m", "positive")}

    def attached_stations(self):
        return (self.station,)

    def grounds(self):
        return ((self.station, "x"), (self.station, "y"))

    def contribute(self, ctx):
        x, y = ctx.coord(self.station, "x")[0], ctx.coord(self.station, "y")[0]
        return Terms(potential=(ctx.p["kxx"] * x**2 + ctx.p["kyy"] * y**2) / 2)


def linear(model):
    """(M, K, C + G, F) of the derived equations at q = q' = 0 with the parameter values."""
    eom = model.equations()
    # the parameter values go in before differentiating (the same numbers, and sympy differentiates
    # numeric coefficients much faster than products of parameter symbols)
    values = {p: sp.Float(model.parameters[str(p)]) for p in eom.parameters}
    zero = {s: 0 for s in eom.coordinates + eom.speeds}
    f = eom.forcing.subs(eom.t, 0).xreplace(values)
    M = np.array(sp.Matrix(eom.mass_matrix).xreplace(values).xreplace(zero), dtype=float)
    K = -np.array(f.jacobian(eom.coordinates).xreplace(zero), dtype=float)
    C = -np.array(f.jacobian(eom.speeds).xreplace(zero), dtype=float)
    F = np.array(f.xreplace(zero), dtype=float).ravel()
    return M, K, C, F


def undamped(model):
    M, K, _, _ = linear(model)
    return np.sqrt(np.abs(scipy.linalg.eigh(K, M, eigvals_only=True)))


def whirl(model):
    """Positive imaginary parts of the eigenvalues (rad/s), ascending."""
    M, K, C, _ = linear(model)
    n = len(M)
    # generalised form: no inverse of M (near-singular with the near-massless shafts below)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    lam = scipy.linalg.eig(A, B, right=False)
    lam = lam[np.isfinite(lam)]
    return np.sort(lam.imag[lam.imag > 1e-6])


def distinct(values, count, floor=1.0):
    """The first ``count`` distinct values above ``floor`` (x and y planes give pairs)."""
    out = []
    for v in np.sort(values):
        if v > floor and (not out or v > out[-1] * (1 + 1e-4)):
            out.append(v)
    return np.array(out[:count])


def shaft(length, diameter, n, *, theory="euler-bernoulli", rotary_inertia=False, supports="pinned", **kw):
    beam = BeamSegment(start=1, end=2, length=length, outer_diameter=diameter, material=STEEL, theory=theory,
                       rotary_inertia=rotary_inertia, elements=n, **kw)
    elements = [Rotor(name="R", stations=(1, 2), speed=0.0), beam]
    if supports == "pinned":
        elements += [ElasticSupport(station=1, stiffness=PIN), ElasticSupport(station=2, stiffness=PIN)]
    elif supports == "cantilever":
        elements += [Clamp(station=1, stiffness=PIN)]
    else:  # free-free: supports soft enough to leave rigid-body modes near 0
        elements += [ElasticSupport(station=1, stiffness=1e-3), ElasticSupport(station=2, stiffness=1e-3)]
    return elements


def section(diameter):
    return math.pi * diameter**2 / 4, math.pi * diameter**4 / 64


# -- the derivation yields the textbook element ----------------------------------------------------
def test_template_equals_friswell_timoshenko_element():
    tpl = plane_template()
    L, phi = tpl["symbols"]
    K = sp.Matrix([[12, 6 * L, -12, 6 * L], [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
                   [-12, -6 * L, 12, -6 * L], [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2]]) / (L**3 * (1 + phi))
    m1, m2 = 312 + 588 * phi + 280 * phi**2, (44 + 77 * phi + 35 * phi**2) * L
    m3, m4 = 108 + 252 * phi + 140 * phi**2, (26 + 63 * phi + 35 * phi**2) * L
    m5, m6 = (8 + 14 * phi + 7 * phi**2) * L**2, (6 + 14 * phi + 7 * phi**2) * L**2
    MT = sp.Matrix([[m1, m2, m3, -m4], [m2, m5, m4, -m6], [m3, m4, m1, -m2], [-m4, -m6, -m2, m5]]) * L / (
        840 * (1 + phi) ** 2)
    m7, m8 = 36, (3 - 15 * phi) * L
    m9, m10 = (4 + 5 * phi + 10 * phi**2) * L**2, (1 + 5 * phi - 5 * phi**2) * L**2
    MR = sp.Matrix([[m7, m8, -m7, m8], [m8, m9, -m8, -m10], [-m7, -m8, m7, -m8], [m8, -m10, -m8, m9]]) / (
        30 * L * (1 + phi) ** 2)
    for derived, book in ((tpl["stiffness"], K), (tpl["translational_mass"], MT), (tpl["rotary_mass"], MR)):
        assert (derived - book).applyfunc(sp.simplify) == sp.zeros(4, 4)


def test_cowper_coefficient_of_solid_section():
    assert cowper_shear_coefficient(0.3, 0.0) == pytest.approx(6 * 1.3 / (7 + 1.8))


# -- natural frequencies of uniform shafts ----------------------------------------------------------
def test_pinned_pinned_euler_bernoulli_converges_to_closed_form():
    L, D = 1.0, 0.05
    A, I = section(D)
    exact = np.array([(k * math.pi / L) ** 2 * math.sqrt(E * I / (RHO * A)) for k in (1, 2, 3)])
    errors = []
    for n in (2, 4, 8):
        w = distinct(undamped(Model(shaft(L, D, n))), 3)
        errors.append(abs(w[0] - exact[0]) / exact[0])
        if n == 8:
            np.testing.assert_allclose(w, exact, rtol=2e-3)
    assert errors[2] < 2e-5
    assert errors[0] / errors[1] > 12 and errors[1] / errors[2] > 12  # O(h^4) for cubic elements


def _beam_roots(equation, count):
    roots, x = [], 0.5
    while len(roots) < count:
        if equation(x) * equation(x + 0.01) < 0:
            roots.append(scipy.optimize.brentq(equation, x, x + 0.01, xtol=1e-14))
        x += 0.01
    return np.array(roots)


def test_cantilever_euler_bernoulli_matches_frequency_equation():
    L, D = 0.8, 0.04
    A, I = section(D)
    bl = _beam_roots(lambda b: 1 + math.cos(b) * math.cosh(b), 3)  # 1.8751, 4.6941, 7.8548
    exact = bl**2 / L**2 * math.sqrt(E * I / (RHO * A))
    w = distinct(undamped(Model(shaft(L, D, 10, supports="cantilever"))), 3)
    np.testing.assert_allclose(w, exact, rtol=5e-4)  # measured: 1.3e-5, 3.3e-5, 2.5e-4


def test_free_free_euler_bernoulli_matches_frequency_equation():
    L, D = 1.2, 0.06
    A, I = section(D)
    bl = _beam_roots(lambda b: math.cos(b) * math.cosh(b) - 1, 3)  # 4.7300, 7.8532, 10.9956
    exact = bl**2 / L**2 * math.sqrt(E * I / (RHO * A))
    w = distinct(undamped(Model(shaft(L, D, 12, supports="free"))), 3)
    np.testing.assert_allclose(w, exact, rtol=1e-3)


def test_pinned_pinned_timoshenko_matches_frequency_determinant():
    L, D = 0.5, 0.1  # stubby: shear and rotary inertia lower the frequencies by percents
    A, I = section(D)
    kappa = cowper_shear_coefficient(E / (2 * G) - 1, 0.0)
    kGA = kappa * G * A

    def exact(k):
        q = k * math.pi / L
        # [kGA q^2 - rho A w^2, -kGA q; -kGA q, EI q^2 + kGA - rho I w^2] (W, B) = 0
        a = RHO * A * RHO * I
        b = -(RHO * A * (E * I * q**2 + kGA) + RHO * I * kGA * q**2)
        c = kGA * q**2 * (E * I * q**2 + kGA) - (kGA * q) ** 2
        return math.sqrt((-b - math.sqrt(b * b - 4 * a * c)) / (2 * a))

    expected = np.array([exact(k) for k in (1, 2, 3)])
    euler = np.array([(k * math.pi / L) ** 2 * math.sqrt(E * I / (RHO * A)) for k in (1, 2, 3)])
    assert np.all(expected < 0.97 * euler)  # the case does test shear
    w = distinct(undamped(Model(shaft(L, D, 12, theory="timoshenko", rotary_inertia=True))), 3)
    # measured: 1.7e-4, 2.3e-3, 8.8e-3 with 12 elements (2e-3, 2.3e-2, 8e-2 with 4: about O(h^2) here)
    np.testing.assert_allclose(w[0], expected[0], rtol=5e-4)
    np.testing.assert_allclose(w, expected, rtol=1.2e-2)


# -- static sag -------------------------------------------------------------------------------------
def test_static_sag_of_simply_supported_shaft():
    L, D = 1.5, 0.05
    A, I = section(D)
    model = Model(shaft(L, D, 4) + [Maneuver.steady(gravity=9.81)])
    M, K, _, F = linear(model)
    q = np.linalg.solve(K, F)
    mid = q[model.coordinate_names.index("ybeam1_2_2")]
    assert mid == pytest.approx(-5 * RHO * A * 9.81 * L**4 / (384 * E * I), rel=1e-6)
    assert q[model.coordinate_names.index("xbeam1_2_2")] == pytest.approx(0.0, abs=1e-15)


# -- gyroscopics ------------------------------------------------------------------------------------
@pytest.mark.parametrize("speed", [0.0, 500.0, 2000.0, 5000.0])
def test_overhung_disk_whirl_matches_gyroscopic_frequency_equation(speed):
    L, D = 0.3, 0.02
    A, I = section(D)
    disk = Disk.from_geometry(station=2, width=0.03, outer_diameter=0.25, material=STEEL)
    # a nearly massless shaft: 1e-3 kg/m^3, its mass 1e-10 of the disk's (the frequencies move by < 1e-6); at
    # 1e-6 kg/m^3 the mass matrix's condition number (6e14) left LAPACK's QZ 5e-4 off at zero speed on one
    # machine's OpenBLAS (the double whirl frequencies)
    massless = Material(density=1e-3, youngs_modulus=E, shear_modulus=G)
    model = Model([Rotor(name="R", stations=(1, 2), speed=speed), Clamp(station=1, stiffness=PIN), disk,
                   BeamSegment(start=1, end=2, length=L, outer_diameter=D, material=massless,
                               theory="euler-bernoulli", rotary_inertia=False)])
    k11, k12, k22 = 12 * E * I / L**3, -6 * E * I / L**2, 4 * E * I / L
    m, Id, Ip = disk.mass, disk.diametral_inertia, disk.polar_inertia
    roots = []
    for sign in (+1, -1):  # forward: gyroscopic stiffening
        poly = np.polymul([-m, 0, k11], [-Id, sign * Ip * speed, k22])
        poly[-1] -= k12**2
        roots += [r.real for r in np.roots(poly) if abs(r.imag) < 1e-9 and r.real > 0]
    expected = np.sort(roots)
    w = whirl(model)
    np.testing.assert_allclose(w[w < 1e5], expected, rtol=1e-4)  # above: the massless shaft's own modes
    if speed > 0:  # the split is the gyroscopic effect
        assert expected[-1] > expected[-2] * 1.01


@pytest.mark.parametrize("speed", [0.0, 3000.0])
def test_rigid_rotor_on_anisotropic_bearings(speed):
    a, kx, ky = 0.2, 1.0e6, 0.6e6
    disk = Disk.from_geometry(station=2, width=0.05, outer_diameter=0.3, material=STEEL)
    rigid = Material(density=1e-6, youngs_modulus=E * 1e4, shear_modulus=G * 1e4)
    model = Model([Rotor(name="R", stations=(1, 2, 3), speed=speed), disk,
                   AxisSupport(station=1, kxx=kx, kyy=ky), AxisSupport(station=3, kxx=kx, kyy=ky),
                   BeamSegment(name="left", start=1, end=2, length=a, outer_diameter=0.05, material=rigid),
                   BeamSegment(name="right", start=2, end=3, length=a, outer_diameter=0.05, material=rigid)])
    m, Id, Ip = disk.mass, disk.diametral_inertia, disk.polar_inertia
    cylindrical = [math.sqrt(2 * ky / m), math.sqrt(2 * kx / m)]
    kt_x, kt_y = 2 * kx * a**2, 2 * ky * a**2
    # (kt_x - Id w^2)(kt_y - Id w^2) - (Ip Omega w)^2 = 0, a quadratic in w^2
    poly = [Id**2, -(Id * (kt_x + kt_y) + (Ip * speed) ** 2), kt_x * kt_y]
    conical = [math.sqrt(r.real) for r in np.roots(poly)]
    w = whirl(model)
    w = w[w < 1e5]  # drop the (near-rigid) shaft's own modes
    np.testing.assert_allclose(w, np.sort(cylindrical + conical), rtol=1e-4)


# -- independent whole-system derivation ------------------------------------------------------------
def test_element_derivation_equals_whole_system_lagranges_method():
    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

    model = Model([Rotor(name="R", stations=(1, 2), speed=300.0),
                   BeamSegment(start=1, end=2, length=0.6, outer_diameter=0.04, material=STEEL, elements=2),
                   Disk.from_geometry(station=2, width=0.02, outer_diameter=0.2, material=STEEL),
                   AxisSupport(station=1, kxx=1e6, kyy=8e5), AxisSupport(station=2, kxx=1e6, kyy=8e5)])
    eom = model.equations()
    qt = [dynamicsymbols(str(q)) for q in eom.coordinates]
    to_t = {**dict(zip(eom.coordinates, qt)), **{u: sp.diff(q, dynamicsymbols._t) for u, q in zip(eom.speeds, qt)}}
    lagrangian = (eom.kinetic - eom.potential).subs(to_t).subs(eom.t, dynamicsymbols._t)
    lm = LagrangesMethod(lagrangian, qt)
    lm.form_lagranges_equations()
    back = {v: k for k, v in to_t.items()}
    mass = lm.mass_matrix.subs(back)
    forcing = lm.forcing.subs(back).subs(dynamicsymbols._t, eom.t)
    assert (mass - eom.mass_matrix).applyfunc(sp.expand) == sp.zeros(eom.n, eom.n)
    assert (forcing - eom.forcing).applyfunc(sp.expand) == sp.zeros(eom.n, 1)


def test_beam_coordinates_and_nodes():
    model = Model([Rotor(name="R", stations=(1, 2, 3), speed=0.0),
                   BeamSegment(start=1, end=2, length=0.5, outer_diameter=0.05, material=STEEL, elements=2),
                   Disk(station=3, mass=1.0, radius=0.1), ElasticSupport(station=1, stiffness=1e6),
                   ElasticSupport(station=3, stiffness=1e6), ElasticSupport(station=2, stiffness=1e6)])
    assert model.stations == (1, "beam1_2_1", 2, 3)
    assert model.coordinate_names == ("x1", "xbeam1_2_1", "x2", "x3", "y1", "ybeam1_2_1", "y2", "y3",
                                      "thx1", "thxbeam1_2_1", "thx2", "thy1", "thybeam1_2_1", "thy2")
    assert "gyroscopic" in model.effects


# -- bad input --------------------------------------------------------------------------------------
BAD = {
    "inner >= outer": (dict(outer_diameter=0.05, inner_diameter=0.05), r"inner_diameter = 0.05 m must be smaller"),
    "zero length": (dict(length=0.0), r"length"),
    "negative density": (dict(density=-7800.0, material=None, youngs_modulus=2e11, shear_modulus=8e10),
                         r"density"),
    "no material": (dict(material=None), r"density is required .*material=Material.steel\(\)"),
    "elements": (dict(elements=0), r"elements = 0: expected an int >= 1"),
    "theory": (dict(theory="rayleigh"), r"theory = 'rayleigh'"),
    "poisson via G": (dict(material=None, density=7800.0, youngs_modulus=2e11, shear_modulus=6e10),
                      r"Poisson ratio 0.6667 outside \(-1, 0.5\)"),
}


@pytest.mark.parametrize("case", list(BAD))
def test_bad_beam_input_is_a_named_error(case):
    kw = dict(start=1, end=2, length=0.5, outer_diameter=0.05, material=STEEL)
    changes, pattern = BAD[case]
    kw.update(changes)
    with pytest.raises(ParameterError, match=pattern):
        BeamSegment(**kw)


@pytest.mark.parametrize("kw, pattern", [
    (dict(density=7800, youngs_modulus=2e11, poisson_ratio=0.5), r"poisson_ratio = 0.5: expected a number in \(-1, 0.5\)"),
    (dict(density=7800, youngs_modulus=2e11, poisson_ratio=-1.2), r"poisson_ratio = -1.2"),
    (dict(density=-1.0, youngs_modulus=2e11, poisson_ratio=0.3), r"density"),
    (dict(density=7800, youngs_modulus=2e11), r"give shear_modulus \(Pa\) or poisson_ratio"),
])
def test_bad_material_is_a_named_error(kw, pattern):
    with pytest.raises(ParameterError, match=pattern):
        Material(**kw)


def test_disk_geometry_errors_and_tilt_requirement():
    with pytest.raises(ParameterError, match=r"inner_diameter = 0.3 m must be smaller than outer_diameter"):
        Disk.from_geometry(station=1, width=0.05, inner_diameter=0.3, outer_diameter=0.2, material=STEEL)
    disk = Disk.from_geometry(station=1, width=0.05, outer_diameter=0.2, material=STEEL)
    with pytest.raises(TopologyError, match=r"Disk 'disk1': needs the coordinates thx1, thy1.*BeamSegment"):
        Model([Rotor(name="R", stations=(1,), speed=0.0), disk, ElasticSupport(station=1, stiffness=1e6)])


def test_disk_from_geometry_values():
    disk = Disk.from_geometry(station=1, width=0.07, inner_diameter=0.05, outer_diameter=0.28, material=STEEL)
    m = RHO * math.pi * (0.14**2 - 0.025**2) * 0.07
    assert disk.mass == pytest.approx(m)
    assert disk.polar_inertia == pytest.approx(m * (0.14**2 + 0.025**2) / 2)
    assert disk.diametral_inertia == pytest.approx(m * (0.14**2 + 0.025**2) / 4 + m * 0.07**2 / 12)
