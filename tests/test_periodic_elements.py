"""The periodic-response analysis on the engine elements of issue 21 (beyond the squeeze-film damper,
tests/test_periodic_sfd.py): an inter-shaft rub whose outer rotor is held still and does not spin gives the
periodic solution of the same rotor in a rub stator (its closed form is checked in tests/test_periodic.py)."""

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.analysis.periodic import periodic_solution

RADIUS, CLEARANCE, KR, MU = 0.05, 1e-4, 5e6, 0.15


def inner_rotor():
    return [
        rk.Rotor(name="R", stations=(0, 1), speed=300.0),
        rk.LumpedMass(station=0, mass=1.0),
        rk.ElasticSupport(station=0, stiffness=1e7, damping=50.0),
        rk.Disk(station=1, mass=4.0, radius=RADIUS, eccentricity=2e-4),
        rk.ShaftSegment(start=0, end=1, length=0.3, bending_stiffness=2e5, bending_damping=5.0),
    ]


@pytest.mark.parametrize("speed", [240.0, 260.0, 280.0])
def test_intershaft_rub_on_a_still_outer_rotor_is_a_rub_stator(speed):
    stator = rk.Model(inner_rotor() + [rk.RubStator(station=1, clearance=CLEARANCE, contact_stiffness=KR,
                                                    friction_coefficient=MU, contact_radius=RADIUS)], name="pst")
    outer = [rk.Rotor(name="S", stations=(9,), speed=0.0), rk.LumpedMass(station=9, mass=3.0),
             rk.ElasticSupport(station=9, stiffness=1e13, damping=20.0)]
    rub = rk.IntershaftRub(inner_station=1, outer_station=9, clearance=CLEARANCE, contact_stiffness=KR,
                           friction_coefficient=MU, contact_radius=RADIUS)
    intershaft = rk.Model(inner_rotor() + outer + [rub], name="pis")
    a = periodic_solution(stator, harmonics=6, speed_parameter="R_speed", R_speed=speed, stability="none")
    b = periodic_solution(intershaft, harmonics=6, speed_parameter="R_speed", R_speed=speed, stability="none")
    ra, rb = a.max_radius(1)[0], b.max_radius(1)[0]
    assert ra > CLEARANCE  # in contact: the rub acts
    assert rb == pytest.approx(ra, rel=1e-5)
    for k in (1, 2, 3):
        assert b.harmonic_amplitude("x1", k)[0] == pytest.approx(a.harmonic_amplitude("x1", k)[0], rel=1e-4,
                                                                  abs=1e-6 * ra)
    assert b.max_radius(9)[0] < 1e-9  # the outer station hardly moves
