"""Bad input gives rotorkit's own errors, with messages that name the culprit.

Every error a user can trigger is a ``ParameterError``, ``UnitError`` or
``TopologyError`` (``ValueError``/``TypeError`` subclasses); the message names
the parameter (or element, station, rotor), shows the bad value and says what
is expected. Also checked: pint quantities are converted to SI at the
boundary, preset switches remove exactly the effects they name, and
``System.with_parameters`` changes numbers without re-deriving.
"""

from __future__ import annotations

import math

import numpy as np
import pint
import pytest

import rotorkit
from rotorkit import (
    BallBearing,
    Disk,
    ElasticSupport,
    LumpedMass,
    Maneuver,
    Model,
    ParameterError,
    Rotor,
    RotorkitError,
    ShaftSegment,
    TopologyError,
    UnitError,
)

u = pint.UnitRegistry()  # a registry of our own: rotorkit must accept quantities from any registry


# ---------------------------------------------------------------------------
# the error types
# ---------------------------------------------------------------------------


def test_error_hierarchy():
    assert issubclass(ParameterError, ValueError) and issubclass(ParameterError, RotorkitError)
    assert issubclass(UnitError, ParameterError) and issubclass(UnitError, TypeError)
    assert issubclass(TopologyError, ValueError) and issubclass(TopologyError, RotorkitError)
    assert rotorkit.ParameterError is ParameterError
    assert rotorkit.UnitError is UnitError
    assert rotorkit.TopologyError is TopologyError


# ---------------------------------------------------------------------------
# bad values
# ---------------------------------------------------------------------------

BAD_VALUES = {
    "negative disk mass": (
        lambda: Disk(station=1, mass=-1.0, radius=0.1), ParameterError, r"Disk\.mass = -1\.0 must be > 0 \(kg\)"),
    "negative lumped mass": (
        lambda: LumpedMass(station=1, mass=-2.5), ParameterError, r"LumpedMass\.mass = -2\.5 must be > 0 \(kg\)"),
    "zero mass": (
        lambda: LumpedMass(station=1, mass=0.0), ParameterError, r"LumpedMass\.mass = 0\.0 must be > 0 \(kg\)"),
    "zero stiffness": (
        lambda: ElasticSupport(station=1, stiffness=0.0), ParameterError,
        r"ElasticSupport\.stiffness = 0\.0 must be > 0 \(N/m\)"),
    "negative damping": (
        lambda: ElasticSupport(station=1, stiffness=1e6, damping=-3.0), ParameterError,
        r"ElasticSupport\.damping = -3\.0 must be >= 0 \(N\*s/m\)"),
    "negative eccentricity": (
        lambda: Disk(station=1, mass=1.0, radius=0.1, eccentricity=-1e-5), ParameterError,
        r"Disk\.eccentricity = -1e-05 must be >= 0 \(m\)"),
    "zero shaft stiffness": (
        lambda: ShaftSegment(start=1, end=2, bending_stiffness=0.0), ParameterError,
        r"ShaftSegment\.bending_stiffness = 0\.0 must be > 0 \(N/m\)"),
    "NaN mass": (
        lambda: LumpedMass(station=1, mass=float("nan")), ParameterError,
        r"LumpedMass\.mass = nan is not finite: expected a finite value in kg"),
    "infinite stiffness": (
        lambda: ElasticSupport(station=1, stiffness=math.inf), ParameterError,
        r"ElasticSupport\.stiffness = inf is not finite: expected a finite value in N/m"),
    "NaN speed": (
        lambda: Rotor(name="R", stations=(1,), speed=float("nan")), ParameterError,
        r"Rotor\.speed = nan is not finite.*rad/s"),
    "string for a mass": (
        lambda: LumpedMass(station=1, mass="ten kg"), UnitError,
        r"LumpedMass\.mass = 'ten kg' is not a number: expected a float in kg"),
    "string for a speed": (
        lambda: Rotor(name="R", stations=(1,), speed="fast"), UnitError,
        r"Rotor\.speed = 'fast' is not a number: expected a float in rad/s"),
    "bool for a stiffness": (
        lambda: ElasticSupport(station=1, stiffness=True), UnitError,
        r"ElasticSupport\.stiffness = True is not a number: expected a float in N/m"),
    "bool for a mass": (
        lambda: Disk(station=1, mass=False, radius=0.1), UnitError,
        r"Disk\.mass = False is not a number: expected a float in kg"),
    "list for a mass": (
        lambda: LumpedMass(station=1, mass=[1.0]), UnitError, r"LumpedMass\.mass = \[1\.0\] is not a number"),
    "missing mass": (
        lambda: LumpedMass(station=3), ParameterError, r"LumpedMass at station 3: mass is required \(kg\)"),
    "missing stiffness": (
        lambda: ElasticSupport(station=4), ParameterError,
        r"ElasticSupport at station 4: stiffness is required \(N/m\)"),
    "torsion not a bool": (
        lambda: Disk(station=2, mass=1.0, radius=0.1, torsion="yes"), ParameterError,
        r"Disk at station 2: torsion='yes' must be True or False"),
    "negative station": (
        lambda: LumpedMass(station=-1, mass=1.0), ParameterError,
        r"station = -1: expected a station \(a non-negative int or an identifier"),
    "unknown end condition": (
        lambda: ShaftSegment(start=1, end=2, length=0.3, youngs_modulus=2e11, area_moment=1e-7,
                             end_condition="pinned"),
        ParameterError, r"end_condition='pinned' is unknown; expected one of \['clamped-free', 'clamped-guided'\]"),
    "roll ends before it starts": (
        lambda: Maneuver.barrel_roll(rate=math.pi, radius=3.0, start=3.0, end=2.0), ParameterError,
        r"end=2\.0 s must be after start=3\.0 s"),
    "too few balls": (
        lambda: BallBearing(inner_station=4, outer_station=7, contact_stiffness=1e10, n_balls=2,
                            inner_race_radius=0.04, outer_race_radius=0.06),
        ParameterError, r"n_balls=2 must be an int >= 3"),
}


@pytest.mark.parametrize("case", list(BAD_VALUES))
def test_bad_value_raises_named_error(case):
    make, error, pattern = BAD_VALUES[case]
    with pytest.raises(error, match=pattern):
        make()


@pytest.mark.parametrize("builtin, make", [
    (ValueError, lambda: Disk(station=1, mass=-1.0, radius=0.1)),
    (ValueError, lambda: LumpedMass(station=1, mass=float("nan"))),
    (TypeError, lambda: LumpedMass(station=1, mass="ten")),
    (TypeError, lambda: ElasticSupport(station=1, stiffness=1e6 * u.kg)),
])


def test_errors_are_caught_as_builtin_types(builtin, make):
    with pytest.raises(builtin):
        make()


# ---------------------------------------------------------------------------
# units
# ---------------------------------------------------------------------------

WRONG_UNITS = {
    "length for a mass": (
        lambda: Disk(station=1, mass=3 * u.m, radius=0.1), r"Disk\.mass = .*meter.* wrong unit: expected .* kg"),
    "mass for a stiffness": (
        lambda: ElasticSupport(station=1, stiffness=3 * u.kg),
        r"ElasticSupport\.stiffness = .*kilogram.* wrong unit: expected .* N/m"),
    "length for a speed": (
        lambda: Rotor(name="R", stations=(1,), speed=3 * u.m), r"Rotor\.speed = .*meter.* wrong unit.* rad/s"),
    "mass for a length": (
        lambda: ShaftSegment(start=1, end=2, length=1 * u.kg, torsional_stiffness=1.0),
        r"ShaftSegment\.length = .*kilogram.* wrong unit.* m"),
    "stiffness for a damping": (
        lambda: ElasticSupport(station=1, stiffness=1e6, damping=300 * u.N / u.m),
        r"ElasticSupport\.damping = .*newton / meter.* wrong unit.* N\*s/m"),
}


@pytest.mark.parametrize("case", list(WRONG_UNITS))
def test_wrong_unit_raises_unit_error(case):
    make, pattern = WRONG_UNITS[case]
    with pytest.raises(UnitError, match=pattern):
        make()


def test_sign_is_checked_after_unit_conversion():
    with pytest.raises(ParameterError, match=r"Disk\.mass = .*-10.*gram.* must be > 0 \(kg\)"):
        Disk(station=1, mass=-10 * u.g, radius=0.1)


@pytest.mark.parametrize("make, field, expected", [
    (lambda: Disk(station=1, mass=10 * u.g, radius=0.1), "mass", 0.01),
    (lambda: Disk(station=1, mass=1.0, radius=5 * u.cm), "radius", 0.05),
    (lambda: Disk(station=1, mass=1.0, radius=0.1, eccentricity=46.35 * u.um), "eccentricity", 46.35e-6),
    (lambda: Disk(station=1, mass=1.0, polar_inertia=2.5e3 * u.kg * u.cm**2), "polar_inertia", 0.25),
    (lambda: Rotor(name="R", stations=(1,), speed=3000 * u.rpm), "speed", 3000 * 2 * math.pi / 60),
    (lambda: Rotor(name="R", stations=(1,), speed=50 * u.turn / u.s), "speed", 100 * math.pi),
    (lambda: ElasticSupport(station=1, stiffness=2 * u.kN / u.mm), "stiffness", 2e6),
    (lambda: ElasticSupport(station=1, stiffness=1e6, damping=0.3 * u.kN * u.s / u.m), "damping", 300.0),
    (lambda: ShaftSegment(start=1, end=2, length=330 * u.mm, torsional_stiffness=1.0), "length", 0.33),
    (lambda: ShaftSegment(start=1, end=2, length=0.3, youngs_modulus=200 * u.GPa, area_moment=1e-7,
                          end_condition="clamped-free"), "youngs_modulus", 2e11),
    (lambda: Maneuver.steady(gravity=1 * u.standard_gravity), "gravity", 9.80665),
])


def test_pint_quantities_are_converted_to_si_floats(make, field, expected):
    element = make()
    value = getattr(element, field)
    assert type(value) is float
    assert value == pytest.approx(expected, rel=1e-12)


def test_model_parameters_hold_si_values_from_quantities():
    model = Model([
        Rotor(name="R", stations=(1,), speed=600 * u.rpm),
        Disk(station=1, mass=500 * u.g, radius=8 * u.cm, eccentricity=0.1 * u.mm),
        ElasticSupport(station=1, stiffness=20 * u.N / u.mm),
    ])
    p = model.parameters
    assert p["R_speed"] == pytest.approx(20 * math.pi, rel=1e-12)
    assert p["disk1_mass"] == pytest.approx(0.5, rel=1e-12)
    assert p["disk1_radius"] == pytest.approx(0.08, rel=1e-12)
    assert p["disk1_eccentricity"] == pytest.approx(1e-4, rel=1e-12)
    assert p["support1_stiffness"] == pytest.approx(2e4, rel=1e-12)
    # and the compiled system uses them: restoring acceleration -k x / m
    system = model.compile(backend="python")
    dydt = system.rhs(0.0, system.initial_state(x1=1e-3))
    # (plus the unbalance e Omega^2 at phase 0)
    assert dydt[2] == pytest.approx(-2e4 * 1e-3 / 0.5 + 1e-4 * (20 * math.pi) ** 2, rel=1e-12)


def test_preset_accepts_quantities():
    model = rotorkit.preset("al31f", lp_speed=3000 * u.rpm, rub_clearance=0.2 * u.mm)
    assert model.parameters["LP_speed"] == pytest.approx(100 * math.pi, rel=1e-12)
    assert model.parameters["rub2_clearance"] == pytest.approx(2e-4, rel=1e-12)


# ---------------------------------------------------------------------------
# topology
# ---------------------------------------------------------------------------


def _rotor(name="R", stations=(1,), **kw):
    if "speed_ratio" not in kw:
        kw["speed"] = 100.0
    return Rotor(name=name, stations=stations, **kw)


def _bearing(inner, outer):
    return BallBearing(inner_station=inner, outer_station=outer, contact_stiffness=1e10, clearance=5e-6,
                       n_balls=8, inner_race_radius=0.04, outer_race_radius=0.06)


def _mass(s):
    return LumpedMass(station=s, mass=1.0)


def _support(s):
    return ElasticSupport(station=s, stiffness=1e6)


TOPOLOGY = {
    "unknown station in an element": (
        [_rotor(), _mass(1), _support(1), _support(2)],
        r"ElasticSupport 'support2': station 2 is not on any rotor \(known stations: \[1\]\)"),
    "unknown station in a shaft": (
        [_rotor(), _mass(1), _support(1), ShaftSegment(start=1, end=9, bending_stiffness=1e5)],
        r"ShaftSegment 'shaft1_9': station 9 is not on any rotor"),
    "station on two rotors": (
        [_rotor(), _rotor("S", (1,)), _mass(1), _support(1)],
        r"station 1 is on rotor 'R' and rotor 'S'; a station belongs to one rotor"),
    "station with no mass": (
        [_rotor(stations=(1, 2)), _mass(1), _support(1), _support(2)],
        r"station 2 \(rotor 'R'\) has no mass.*add LumpedMass"),
    "rotor with no support": (
        [_rotor(), _mass(1)], r"Rotor 'R' has no support: it would drift freely; add an ElasticSupport"),
    "station with no stiffness path": (
        [_rotor(stations=(1, 2)), _mass(1), _mass(2), _support(1)],
        r"Rotor 'R' has stations \[2\] with no stiffness path to a support"),
    "bearing within one rotor": (
        [_rotor(stations=(1, 2)), _mass(1), _mass(2), _support(1), _support(2), _bearing(1, 2)],
        r"BallBearing 'bearing1_2': inner_station 1 and outer_station 2 are both on rotor 'R'"),
    "torsion with no stiffness path": (
        [_rotor(), Disk(station=1, mass=1.0, radius=0.1, torsion=True), _support(1)],
        r"Disk at station 1 has torsion=True but no torsional stiffness path to the drive"),
    "torsion only between torsional disks": (
        [_rotor(stations=(1, 2)), Disk(station=1, mass=1.0, radius=0.1, torsion=True),
         Disk(station=2, mass=1.0, radius=0.1, torsion=True), _support(1), _support(2),
         ShaftSegment(start=1, end=2, torsional_stiffness=1e3)],
        r"Disk at station 1 has torsion=True but no torsional stiffness path to the drive"),
    "torsional shaft with no torsional coordinate": (
        [_rotor(stations=(1, 2)), _mass(1), _mass(2), _support(1), _support(2),
         ShaftSegment(start=1, end=2, torsional_stiffness=1e3)],
        r"ShaftSegment 'shaft1_2': torsional stiffness between stations with no torsional coordinate"),
    "shaft segment across rotors": (
        [_rotor(), _rotor("S", (2,)), _mass(1), _mass(2), _support(1), _support(2),
         ShaftSegment(start=1, end=2, bending_stiffness=1e5)],
        r"ShaftSegment 'shaft1_2': stations 1 \(rotor 'R'\) and 2 \(rotor 'S'\) are on different rotors"),
    "two maneuvers": (
        [_rotor(), _mass(1), _support(1), Maneuver.steady(), Maneuver(name="second", gravity=1.0)],
        r"more than one Maneuver"),
    "two maneuvers with the same label": (
        [_rotor(), _mass(1), _support(1), Maneuver.steady(), Maneuver.steady(gravity=1.0)],
        r"two elements are labelled 'maneuver'.*distinct name"),
    "speed reference to an unknown rotor": (
        [_rotor("LP"), _rotor("HP", (2,), speed_ratio=1.8, reference="LPX"), _mass(1), _mass(2), _support(1),
         _support(2)],
        r"Rotor 'HP': reference='LPX' is not a rotor of the model \(rotors: \['HP', 'LP'\]\)"),
    "speed references in a loop": (
        [_rotor("A", (1,), speed_ratio=2.0, reference="B"), _rotor("B", (2,), speed_ratio=0.5, reference="A"),
         _mass(1), _mass(2), _support(1), _support(2)],
        r"Rotor speeds refer to each other in a loop"),
    "no rotor": ([_mass(1), _support(1)], r"no Rotor given"),
    "not an element": ([_rotor(), _mass(1), _support(1), 3.0], r"3\.0 is not a rotorkit element"),
    "two disks at one station": (
        [_rotor(), Disk(station=1, mass=1.0, radius=0.1), Disk(name="other", station=1, mass=1.0, radius=0.1),
         _support(1)],
        r"station 1 has more than one Disk"),
}


@pytest.mark.parametrize("case", list(TOPOLOGY))
def test_bad_topology_raises_topology_error(case):
    elements, pattern = TOPOLOGY[case]
    with pytest.raises(TopologyError, match=pattern):
        Model(elements)


def test_valid_two_rotor_topology_builds():
    """Control for the topology cases: the same pieces, put together right, are accepted."""
    model = Model([_rotor("LP", (1, 2)), _rotor("HP", (3,), speed_ratio=1.8, reference="LP"),
                   _mass(1), Disk(station=2, mass=1.0, radius=0.1, torsion=True), _mass(3), _support(1),
                   ShaftSegment(start=1, end=2, bending_stiffness=1e5, torsional_stiffness=1e3), _bearing(2, 3)])
    assert model.coordinate_names == ("x1", "x2", "x3", "y1", "y2", "y3", "alpha2")


# ---------------------------------------------------------------------------
# presets and systems
# ---------------------------------------------------------------------------


def _jeffcott(**support):
    support = {"stiffness": 2e4, "damping": 0.0, **support}
    return Model([Rotor(name="R", stations=(1,), speed=0.0), Disk(station=1, mass=2.0, radius=0.1),
                  ElasticSupport(station=1, **support)], name="jeffcott")


@pytest.fixture(scope="module")
def jeffcott_system():
    return _jeffcott().compile(backend="python")


PRESET_ERRORS = {
    "override typo": (
        dict(name="al31f", rub_stiffnes=1), ParameterError,
        r"al31f: unknown override 'rub_stiffnes'; did you mean rub_stiffness"),
    "unknown override listed with the known ones": (
        dict(name="al31f", warp_drive=1), ParameterError, r"unknown override 'warp_drive'.*known: .*lp_speed"),
    "unknown preset near a known one": (
        dict(name="al31g"), ParameterError, r"unknown preset 'al31g'; did you mean al31f"),
    "unknown preset": (
        dict(name="no_such_engine"), ParameterError, r"unknown preset 'no_such_engine' \(presets: .*al31f"),
    "switch not a bool": (
        dict(name="al31f", rub="no"), ParameterError, r"rub='no' must be True or False"),
    "negative override": (
        dict(name="al31f", support_stiffness=-1.0), ParameterError, r"stiffness = -1\.0 must be > 0"),
    "override in a wrong unit": (
        dict(name="al31f", lp_speed=3 * u.m), UnitError, r"speed = .*meter.* wrong unit.*rad/s"),
}


@pytest.mark.parametrize("case", list(PRESET_ERRORS))
def test_preset_errors(case):
    kwargs, error, pattern = PRESET_ERRORS[case]
    kwargs = dict(kwargs)
    name = kwargs.pop("name")
    with pytest.raises(error, match=pattern):
        rotorkit.preset(name, **kwargs)


WITH_PARAMETERS_ERRORS = {
    "unknown name": (dict(bogus=1), ParameterError, r"unknown parameter 'bogus'"),
    "typo": (dict(support1_stifness=1e4), ParameterError,
             r"unknown parameter 'support1_stifness'; did you mean support1_stiffness"),
    "wrong unit": (dict(support1_stiffness=3 * u.kg), UnitError,
                   r"support1_stiffness = .*kilogram.* wrong unit: expected a quantity in N/m"),
    "negative": (dict(support1_stiffness=-3.0), ParameterError, r"support1_stiffness = -3\.0 must be > 0 \(N/m\)"),
    "NaN": (dict(disk1_mass=float("nan")), ParameterError, r"disk1_mass = nan is not finite.*kg"),
    "string": (dict(disk1_mass="one"), UnitError, r"disk1_mass = 'one' is not a number.*kg"),
    "bool": (dict(disk1_mass=True), UnitError, r"disk1_mass = True is not a number.*kg"),
}


@pytest.mark.parametrize("case", list(WITH_PARAMETERS_ERRORS))
def test_with_parameters_errors(jeffcott_system, case):
    overrides, error, pattern = WITH_PARAMETERS_ERRORS[case]
    with pytest.raises(error, match=pattern):
        jeffcott_system.with_parameters(**overrides)
    assert jeffcott_system.parameters["support1_stiffness"] == 2e4  # a failed call changes nothing


def test_with_parameters_unknown_name_says_what_is_expected(jeffcott_system):
    with pytest.raises(ParameterError, match=r"unknown parameter 'bogus'.*support1_stiffness"):
        jeffcott_system.with_parameters(bogus=1)


def test_with_parameters_converts_units(jeffcott_system):
    system = jeffcott_system.with_parameters(support1_stiffness=3 * u.kN / u.m, disk1_mass=1500 * u.g)
    assert system.parameters["support1_stiffness"] == pytest.approx(3000.0, rel=1e-12)
    assert system.parameters["disk1_mass"] == pytest.approx(1.5, rel=1e-12)
    assert system.rhs(0.0, system.initial_state(x1=1e-3))[2] == pytest.approx(-3000.0 * 1e-3 / 1.5, rel=1e-12)


def test_with_parameters_accepts_hertz_constant_in_its_unit():
    system = rotorkit.preset("al31f").compile(backend="python")
    changed = system.with_parameters(bearing4_7_contact_stiffness=2e7 * u.kN / u.m**1.5)
    assert changed.parameters["bearing4_7_contact_stiffness"] == pytest.approx(2e10, rel=1e-12)


def test_with_parameters_rejects_roll_ending_before_start():
    system = rotorkit.preset("al31f").compile(backend="python")
    with pytest.raises(ParameterError, match=r"roll_end"):
        system.with_parameters(maneuver_roll_end=1.0)  # start stays at 2.0 s


def test_compile_rejects_unknown_backend():
    with pytest.raises(ParameterError, match=r"backend='fortran' is unknown; expected 'auto', 'python', 'numba' or 'c'"):
        _jeffcott().compile(backend="fortran")


# ---------------------------------------------------------------------------
# with_parameters: new numbers, same equations
# ---------------------------------------------------------------------------


def test_with_parameters_doubles_restoring_acceleration(jeffcott_system, monkeypatch):
    import rotorkit.codegen.generate
    import rotorkit.symbolic.lagrange

    def forbidden(*args, **kwargs):
        raise AssertionError("with_parameters must not re-derive or regenerate the equations")

    monkeypatch.setattr(rotorkit.symbolic.lagrange, "derive", forbidden)
    monkeypatch.setattr(rotorkit.codegen.generate, "generate", forbidden)
    monkeypatch.setattr(Model, "equations", forbidden)

    x = 1.3e-3
    y = jeffcott_system.initial_state(x1=x, y1=-0.4e-3)
    before = jeffcott_system.rhs(0.0, y)
    k = jeffcott_system.parameters["support1_stiffness"]
    doubled = jeffcott_system.with_parameters(support1_stiffness=2 * k)

    np.testing.assert_allclose(before[2:], [-k * x / 2.0, k * 0.4e-3 / 2.0], rtol=1e-14)
    np.testing.assert_allclose(doubled.rhs(0.0, y)[2:], 2.0 * before[2:], rtol=1e-14)
    # a new object over the same compiled code; the original is untouched
    assert doubled is not jeffcott_system
    assert doubled.core is jeffcott_system.core
    assert doubled.parameters["support1_stiffness"] == 2 * k
    assert jeffcott_system.parameters["support1_stiffness"] == k
    np.testing.assert_array_equal(jeffcott_system.rhs(0.0, y), before)
    # the parameters dict handed out is a copy
    jeffcott_system.parameters["support1_stiffness"] = 1.0
    assert jeffcott_system.parameters["support1_stiffness"] == k


def test_with_parameters_moves_time_events():
    system = rotorkit.preset("al31f").compile(backend="python")
    moved = system.with_parameters(maneuver_roll_start=1.0, maneuver_roll_end=3.5)
    assert moved.time_events == (1.0, 3.5)
    assert system.time_events == (2.0, 4.0)


# ---------------------------------------------------------------------------
# preset switches remove exactly their effect
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def default_al31f():
    model = rotorkit.preset("al31f")
    return model, model.compile(backend="python")


def _free_symbol_names(eq):
    return {s.name for s in eq.mass_matrix.free_symbols | eq.forcing.free_symbols}


def test_default_preset(default_al31f):
    model, system = default_al31f
    assert len(model.coordinate_names) == 16
    assert model.coordinate_names[-2:] == ("alpha2", "alpha5")
    assert system.time_events == (2.0, 4.0)
    # positive controls for the switch tests below
    assert any("rub" in n for n in system.parameters)
    assert any("rub" in n for n in _free_symbol_names(model.equations()))
    assert any("alpha" in n for n in system.state_names)


def test_preset_without_torsion():
    model = rotorkit.preset("al31f", torsion=False)
    assert len(model.coordinate_names) == 14
    assert model.coordinate_names == tuple(f"x{i}" for i in range(1, 8)) + tuple(f"y{i}" for i in range(1, 8))
    system = model.compile(backend="python")
    assert system.n_states == 28
    assert not any("alpha" in n for n in system.state_names)
    assert "torsion" not in model.effects
    # without torsion the mass matrix is constant: diag of the station masses
    eq = model.equations()
    values = {p: model.parameters[p.name] for p in eq.parameters}
    M = eq.mass_matrix.subs(values)
    assert not (M.free_symbols & (set(eq.coordinates) | {eq.t}))
    masses = [2.0, 10.0, 2.0, 2.0, 6.0, 2.0, 8.0]
    np.testing.assert_allclose(np.array(M, dtype=float), np.diag(masses + masses), rtol=1e-12)


def test_preset_without_rub():
    model = rotorkit.preset("al31f", rub=False)
    assert len(model.coordinate_names) == 16
    assert not any("rub" in n for n in _free_symbol_names(model.equations()))
    system = model.compile(backend="python")
    assert not any("rub" in n for n in system.parameters)
    assert "rub" not in model.effects


def test_preset_without_maneuver(default_al31f):
    model = rotorkit.preset("al31f", maneuver=False)
    system = model.compile(backend="python")
    assert system.time_events == ()
    assert not any("roll" in n for n in system.parameters)
    assert "maneuver" not in model.effects and "gravity" in model.effects
    # gravity stays: at rest on the undeflected axis every station accelerates at -g in y
    _, default = default_al31f
    for s in (system, default):
        g = s.parameters["maneuver_gravity"]
        dydt = s.rhs(0.5, np.zeros(s.n_states))
        accel = dict(zip(s.state_names, dydt[s.n_states // 2:]))
        # station 4/7 feel the bearing (clearance: no load at zero) and disks the unbalance; x1, y1 are clean
        assert accel["y1"] == pytest.approx(-g, rel=1e-12)
        assert accel["x1"] == pytest.approx(0.0, abs=1e-12)
