"""Linear matrices from the symbolic equations, speed profiles in the analyses, whirl of tilting stations, reactions.

Closed forms: a disk of mass m on a bearing whose stiffness k(W) is
tabulated against the speed whirls at ``sqrt(k(W) / m)`` at every speed
(no gyroscopics); a station that only tilts whirls in its slope
``(thy, -thx)``; the reactions of the supports of a gravity-loaded rotor
add up to its weight.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from rotorkit import Disk, Maneuver, Model, Rotor
from rotorkit.analysis.campbell import campbell
from rotorkit.analysis.linear_matrices import frozen_speed_model, linear_evaluator, linear_matrices
from rotorkit.analysis.linear_model import linear_model
from rotorkit.analysis.linearize import _rotor_speeds
from rotorkit.analysis.modes import natural_frequencies
from rotorkit.analysis.static import holds_rotor, static_deflection
from rotorkit.analysis.whirl import shape_whirl
from rotorkit.elements import BeamSegment, Element, LinearBearing, Terms
from rotorkit.elements.speed import SpeedProfile
from rotorkit.errors import ParameterError

MASS = 2.0
SPEEDS, KS = (0.0, 1000.0), (2e4, 8e4)


def k_of(speed):
    return float(np.interp(speed, SPEEDS, KS))


def jeffcott(speed=0.0):
    return Model([Rotor(name="R", stations=(1,), speed=speed), Disk(station=1, mass=MASS, radius=0.1),
                  LinearBearing.tabulated(station=1, speeds=SPEEDS, kxx=KS, kyy=KS)], name="tabulated")


def test_speed_dependent_bearing_is_exact_at_every_speed_of_the_campbell_diagram():
    speeds = np.linspace(0.0, 1000.0, 11)
    diagram = campbell(jeffcott(), speeds, n_modes=2, speed_parameter="R_speed")
    expected = np.sqrt([k_of(w) / MASS for w in speeds])
    np.testing.assert_allclose(diagram.frequencies, np.column_stack([expected, expected]), rtol=1e-12)
    # the 1x line meets sqrt(k(W)/m) where W^2 m = k(W): k = 2e4 + 60 W -> 2 W^2 - 60 W - 2e4 = 0
    critical = (60.0 + math.sqrt(60.0**2 + 8 * 2e4)) / 4
    np.testing.assert_allclose([c.speed for c in diagram.critical_speeds()], [critical, critical], rtol=1e-9)


def test_linear_matrices_of_a_linear_model_and_none_for_contacts():
    M, C, K = linear_matrices(jeffcott(300.0))
    np.testing.assert_allclose(M.toarray(), MASS * np.eye(2))
    np.testing.assert_allclose(K.toarray(), k_of(300.0) * np.eye(2))
    assert C.count_nonzero() == 0
    from rotorkit import ElasticSupport, RubStator

    rub = Model([Rotor(name="R", stations=(1,), speed=0.0), Disk(station=1, mass=MASS, radius=0.1),
                 ElasticSupport(station=1, stiffness=2e4),
                 RubStator(station=1, clearance=1e-4, contact_stiffness=1e6, friction_coefficient=0.1)], name="rub")
    assert linear_evaluator(rub) is None  # a contact is not linear: the analyses linearise the system


# ---------------------------------------------------------------------------
# Speed profiles
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def run_up():
    """The tabulated-bearing rotor spun up linearly from 0 to 1000 rad/s over 10 s."""
    model = Model([Rotor(name="R", stations=(1,), speed=SpeedProfile.table([0.0, 10.0], [0.0, 1000.0])),
                   Disk(station=1, mass=MASS, radius=0.1),
                   LinearBearing.tabulated(station=1, speeds=SPEEDS, kxx=KS, kyy=KS)], name="run_up")
    return model.compile(backend="python")


def test_analyses_of_a_speed_profile_rotor_use_its_speed_at_t(run_up):
    assert _rotor_speeds(run_up, 5.0) == {"R": pytest.approx(500.0)}
    modes = natural_frequencies(run_up, t=5.0)
    np.testing.assert_allclose(modes.frequencies, math.sqrt(k_of(500.0) / MASS), rtol=1e-9)
    linear = linear_model(run_up, t=5.0)
    assert linear.speed_parameter == "R_speed" and linear.rotor_speeds == {"R": (0.0, 1.0)}
    np.testing.assert_allclose(linear.modes(500.0).frequencies, math.sqrt(k_of(500.0) / MASS), rtol=1e-9)
    explicit = linear_model(run_up, speed=800.0)  # an explicit speed replaces the profile's
    np.testing.assert_allclose(explicit.modes(800.0).frequencies, math.sqrt(k_of(800.0) / MASS), rtol=1e-9)
    speeds = np.array([100.0, 400.0, 900.0])
    diagram = campbell(run_up, speeds, n_modes=2)
    np.testing.assert_array_equal(diagram.rotor_speeds["R"], speeds)
    np.testing.assert_allclose(diagram.frequencies[:, 0], np.sqrt([k_of(w) / MASS for w in speeds]), rtol=1e-12)


def test_speed_profile_errors_name_the_choice(run_up):
    with pytest.raises(ParameterError, match=r"speed_parameter='R_speed_w1' is not a rotor speed.*R_speed"):
        campbell(run_up, [0.0, 1.0], speed_parameter="R_speed_w1")
    with pytest.raises(ParameterError, match=r"\['S'\] have no speed profile"):
        frozen_speed_model(run_up.model, speeds={"S": 1.0})
    assert frozen_speed_model(jeffcott()) is not None


# ---------------------------------------------------------------------------
# Whirl of tilting stations
# ---------------------------------------------------------------------------


def test_a_station_that_only_tilts_whirls_in_its_slope():
    names = ("x1", "x2", "y1", "y2", "thx2", "thy2")
    # station 1 whirls forward (x = cos, y = sin); station 2 does not move but its slope whirls
    # (dx/dz, dy/dz) = (thy, -thx): thy = 1, thx = 1j -> (1, -1j) like station 1: forward; thx = -1j: backward
    backward = np.array([[1.0, 0.0, -1j, 0.0, -1j, 1.0]]).T
    forward = np.array([[1.0, 0.0, -1j, 0.0, 1j, 1.0]]).T
    modes, stations = shape_whirl(backward, names)
    assert modes == ("mixed",) and stations["1"][0] == "forward" and stations["2"][0] == "backward"
    modes, stations = shape_whirl(forward, names)
    assert modes == ("forward",) and stations["2"][0] == "forward"
    # a slope far below the displacements (weighed by the 2 m span) does not decide anything
    tiny = np.array([[1.0, 1.0, -1j, -1j, -1e-4j, 1e-4]]).T  # a backward slope
    modes, stations = shape_whirl(tiny, names, positions={"1": 0.0, "2": 2.0})
    assert modes == ("forward",) and stations["2"][0] == "forward"


# ---------------------------------------------------------------------------
# Reactions from the element contract
# ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, kw_only=True)
class MassiveStop(Element):
    """A ground spring whose class name contains 'Mass' (the old name heuristic skipped it)."""

    station: int = None
    stiffness: float = None
    _units = {"stiffness": ("N/m", "positive")}

    def attached_stations(self):
        return (self.station,)

    def grounds(self):
        return ((self.station, "x"), (self.station, "y"))

    def contribute(self, ctx):
        x, y = ctx.coord(self.station, "x")[0], ctx.coord(self.station, "y")[0]
        return Terms(potential=ctx.p["stiffness"] * (x**2 + y**2) / 2)


def test_reactions_of_every_grounding_element_add_up_to_the_weight():
    section = dict(outer_diameter=0.04, density=7800.0, youngs_modulus=2.1e11, shear_modulus=8.1e10)
    beams = [BeamSegment(start=1, end=2, length=0.3, **section), BeamSegment(start=2, end=3, length=0.3, **section)]
    stop = MassiveStop(station=2, stiffness=5e5)
    model = Model([Rotor(name="R", stations=(1, 2, 3), speed=0.0), *beams, Disk(station=2, mass=4.0, radius=0.1),
                   LinearBearing(station=1, kxx=1e6, kyy=1e6), LinearBearing(station=3, kxx=1e6, kyy=1e6), stop,
                   Maneuver.steady(gravity=9.81)], name="reactions")
    assert [holds_rotor(e, model) for e in model.elements] == [False, False, False, False, True, True, True, False]
    result = static_deflection(model.compile(backend="python"))
    assert set(result.reactions) == {"linearbearing1", "linearbearing3", stop.label()}
    weight = (4.0 + sum(b.mass_value() for b in beams)) * 9.81
    assert sum(result.reaction(label, s)[1] for label, s in (("linearbearing1", 1), ("linearbearing3", 3),
                                                               (stop.label(), 2))) == pytest.approx(weight, rel=1e-9)
    assert result.reaction(stop.label(), 2)[1] > 0  # it carries part of the load
