"""The element contract: a new element type is one class, the model only gathers.

Element types defined here, in the test file, are used in models exactly as
the library's own:

- ``TunedAbsorber``: a mass on a spring hanging from a station. It creates
  its own coordinates ``u<s>``, ``v<s>``, gives them inertia, ties them
  elastically to the station's ``x``/``y`` and checks its own rule (one per
  station). The Jeffcott rotor with an absorber is a two-mass chain whose
  frequencies are the roots of
  ``m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0``; under gravity the
  rotor sags by ``(m1 + m2) g / k1`` and the absorber by ``m2 g / k2`` more.
- ``TiltingHub``: creates tilt coordinates ``thx<s>``, ``thy<s>`` at one
  station, with diametral inertia I_d and polar inertia I_p spinning at the
  rotor speed; ``TiltSpring`` needs tilts (creates none) and ties them to
  the ground with stiffness k. The hub's tilt whirl frequencies solve
  ``I_d w^2 -+ I_p Omega w - k = 0`` (forward +, backward -).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest
import sympy as sp

import rotorkit.model
from rotorkit import ElasticSupport, LumpedMass, Maneuver, Model, Rotor
from rotorkit.elements.base import Element, Terms
from rotorkit.errors import ParameterError, TopologyError


@dataclass(frozen=True, slots=True, kw_only=True)
class TunedAbsorber(Element):
    """A mass ``mass`` on an isotropic spring ``stiffness`` hanging from ``station``."""

    station: int = None
    mass: float = None
    stiffness: float = None

    _units = {"mass": ("kg", "positive"), "stiffness": ("N/m", "positive")}

    def _validate(self):
        if self.mass is None or self.stiffness is None:
            raise ParameterError("TunedAbsorber: mass and stiffness are required")

    def attached_stations(self):
        return (self.station,)

    def coordinates(self):
        return ((self.station, "u"), (self.station, "v"))

    def inertia(self):
        return self.coordinates()

    def stiffness_links(self):
        s = self.station
        return (((s, "u"), (s, "x")), ((s, "v"), (s, "y")))

    def check(self, model):
        if sum(isinstance(e, TunedAbsorber) for e in model.elements_at(self.station)) > 1:
            raise TopologyError(f"TunedAbsorber {self.label()!r}: station {self.station!r} has two absorbers")

    def effects(self):
        return frozenset({"absorber"})

    def rigid_body_mass(self, ctx):
        u, v = ctx.coord(self.station, "u")[0], ctx.coord(self.station, "v")[0]
        return {u: (ctx.p["mass"], 0), v: (0, ctx.p["mass"])}

    def contribute(self, ctx):
        (x, _), (y, _) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        (u, ud), (v, vd) = ctx.coord(self.station, "u"), ctx.coord(self.station, "v")
        m, k = ctx.p["mass"], ctx.p["stiffness"]
        return Terms(kinetic=m * (ud**2 + vd**2) / 2, potential=k * ((u - x) ** 2 + (v - y) ** 2) / 2)


@dataclass(frozen=True, slots=True, kw_only=True)
class TiltingHub(Element):
    """A rigid hub that creates tilt coordinates at its station (diametral and polar inertia)."""

    station: int = None
    diametral_inertia: float = None
    polar_inertia: float = None

    _units = {"diametral_inertia": ("kg*m**2", "positive"), "polar_inertia": ("kg*m**2", "nonnegative")}

    def attached_stations(self):
        return (self.station,)

    def coordinates(self):
        return ((self.station, "thx"), (self.station, "thy"))

    def inertia(self):
        return self.coordinates()

    def contribute(self, ctx):
        (_, ad), (b, bd) = ctx.coord(self.station, "thx"), ctx.coord(self.station, "thy")
        Id, Ip, spin = ctx.p["diametral_inertia"], ctx.p["polar_inertia"], ctx.speed(self.station)
        return Terms(kinetic=Id * (ad**2 + bd**2) / 2 + Ip * spin * ad * b)


@dataclass(frozen=True, slots=True, kw_only=True)
class TiltSpring(Element):
    """A moment spring from a station's tilts to the ground: needs tilts, creates none."""

    station: int = None
    stiffness: float = None

    _units = {"stiffness": ("N*m/rad", "positive")}

    def attached_stations(self):
        return (self.station,)

    def requires(self):
        return ((self.station, "thx"), (self.station, "thy"))

    def grounds(self):
        return self.requires()

    def contribute(self, ctx):
        a, b = ctx.coord(self.station, "thx")[0], ctx.coord(self.station, "thy")[0]
        return Terms(potential=ctx.p["stiffness"] * (a**2 + b**2) / 2)


M1, K1, M2, K2, G = 2.0, 2.0e4, 0.5, 3.0e3, 9.81


def linear_matrices(model):
    """M, K, C+G at q = q' = 0 with the parameter values, from the derived equations."""
    eom = model.equations()
    values = {p: model.parameters[str(p)] for p in eom.parameters}
    zero = {s: 0 for s in eom.coordinates + eom.speeds}
    f = eom.forcing
    M = np.array(eom.mass_matrix.subs(zero).subs(values), dtype=float)
    K = -np.array(f.jacobian(eom.coordinates).subs(zero).subs(values), dtype=float)
    C = -np.array(f.jacobian(eom.speeds).subs(zero).subs(values), dtype=float)
    F = np.array(f.subs(zero).subs(values).subs(eom.t, 0), dtype=float).ravel()
    return M, K, C, F


def frequencies(M, K, C):
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    lam = np.linalg.eigvals(A)
    return np.sort(lam.imag[lam.imag > 1e-9])


def absorber_model(gravity=False):
    elements = [Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=M1),
                ElasticSupport(station=1, stiffness=K1), TunedAbsorber(station=1, mass=M2, stiffness=K2)]
    if gravity:
        elements.append(Maneuver.steady(gravity=G))
    return Model(elements)


def test_model_module_imports_no_concrete_element():
    names = vars(rotorkit.model)
    for concrete in ("Disk", "LumpedMass", "ShaftSegment", "ElasticSupport", "BallBearing", "RubStator",
                     "Maneuver", "Rotor"):
        assert concrete not in names


def test_new_element_creates_its_coordinates_after_the_standard_ones():
    model = absorber_model()
    assert model.coordinate_names == ("x1", "y1", "u1", "v1")
    assert model.effects == frozenset({"absorber"})


def test_new_element_frequencies_match_two_mass_chain():
    M, K, C, _ = linear_matrices(absorber_model())
    b = M1 * K2 + M2 * (K1 + K2)
    disc = math.sqrt(b * b - 4 * M1 * M2 * K1 * K2)
    expected = sorted([math.sqrt((b - disc) / (2 * M1 * M2)), math.sqrt((b + disc) / (2 * M1 * M2))] * 2)
    np.testing.assert_allclose(frequencies(M, K, C), expected, rtol=1e-10)


def test_new_element_carries_its_weight_under_gravity():
    M, K, C, F = linear_matrices(absorber_model(gravity=True))
    q = np.linalg.solve(K, F)
    y1, v1 = q[1], q[3]
    np.testing.assert_allclose(y1, -(M1 + M2) * G / K1, rtol=1e-12)
    np.testing.assert_allclose(v1 - y1, -M2 * G / K2, rtol=1e-12)


def test_new_element_checks_its_own_attachments():
    with pytest.raises(TopologyError, match=r"TunedAbsorber 'a1': station 1 has two absorbers"):
        Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=M1),
               ElasticSupport(station=1, stiffness=K1), TunedAbsorber(name="a1", station=1, mass=M2, stiffness=K2),
               TunedAbsorber(name="a2", station=1, mass=M2, stiffness=K2)])


def test_new_coordinates_without_inertia_or_path_are_reported_generically():
    @dataclass(frozen=True, slots=True, kw_only=True)
    class Massless(TunedAbsorber):
        def inertia(self):
            return ()

    @dataclass(frozen=True, slots=True, kw_only=True)
    class Unlinked(TunedAbsorber):
        def stiffness_links(self):
            return ()

    base = [Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=M1),
            ElasticSupport(station=1, stiffness=K1)]
    with pytest.raises(TopologyError, match=r"Massless 'massless1': coordinates u1, v1: no element gives them mass"):
        Model(base + [Massless(station=1, mass=M2, stiffness=K2)])
    with pytest.raises(TopologyError, match=r"Unlinked 'unlinked1': coordinates u1, v1: no elastic path"):
        Model(base + [Unlinked(station=1, mass=M2, stiffness=K2)])


def hub_model(speed, Id=0.02, Ip=0.035, k=800.0):
    return Model([Rotor(name="R", stations=(1, 2), speed=speed), LumpedMass(station=1, mass=M1),
                  LumpedMass(station=2, mass=M1), ElasticSupport(station=1, stiffness=K1),
                  ElasticSupport(station=2, stiffness=K1), TiltingHub(station=2, diametral_inertia=Id, polar_inertia=Ip),
                  TiltSpring(station=2, stiffness=k)])


def test_tilt_coordinates_appear_only_where_an_element_creates_them():
    model = hub_model(0.0)
    assert model.coordinate_names == ("x1", "x2", "y1", "y2", "thx2", "thy2")
    assert model.tilt_stations == (2,)
    latex = model.equations().latex_names
    assert latex[sp.Symbol("thx2", real=True)] == r"\theta_{x}_{2}"


@pytest.mark.parametrize("speed", [0.0, 300.0, 1500.0])
def test_tilt_whirl_frequencies_match_gyroscopic_closed_form(speed):
    Id, Ip, k = 0.02, 0.035, 800.0
    M, K, C, _ = linear_matrices(hub_model(speed, Id, Ip, k))
    w = frequencies(M, K, C)
    lateral = math.sqrt(K1 / M1)
    half = Ip * speed / (2 * Id)
    forward = half + math.sqrt(half**2 + k / Id)
    backward = -half + math.sqrt(half**2 + k / Id)
    np.testing.assert_allclose(w, sorted([lateral] * 4 + [forward, backward]), rtol=1e-10)


def test_tilt_only_element_on_station_without_tilt_is_a_named_error():
    with pytest.raises(TopologyError, match=r"TiltSpring 'tiltspring1': needs the coordinates thx1, thy1.*BeamSegment"):
        Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=M1),
               ElasticSupport(station=1, stiffness=K1), TiltSpring(station=1, stiffness=1.0)])
