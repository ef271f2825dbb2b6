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


# at 300 rad/s Newton from zero fails: the solution comes from the homotopy start (newton_from_linear)
@pytest.mark.parametrize("speed", [240.0, 260.0, 280.0, 300.0])
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


def test_journal_bearing_unbalance_orbit_equals_the_settled_time_run():
    """A rigid unbalanced rotor on a short journal bearing under gravity, below the whip threshold: the
    harmonic-balance orbit (about the off-centre equilibrium) is the orbit a long time run settles on."""
    from rotorkit.analysis.linearize import static_equilibrium

    speed = 600.0  # rad/s; the whip threshold of this bearing (tests/test_journal_bearing.py) is higher
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=speed),
                      rk.Disk(station=1, mass=50.0, radius=0.1, eccentricity=4e-6),
                      rk.JournalBearing(station=1, radius=0.025, length=0.02, clearance=5e-5, viscosity=0.02),
                      rk.Maneuver.steady(gravity=9.81)], name="journal_hb")
    system = model.compile(backend="python")
    branch = periodic_solution(system, harmonics=8, speed_parameter="R_speed", stability="monodromy")
    assert branch.stable[0]
    q = static_equilibrium(system, tol=1e-12)
    period = 2 * np.pi / speed
    run = rk.simulate(system, (0.0, 400 * period), y0=[q[0], q[1], 0.0, 0.0], sample_rate=200 * speed / np.pi,
                      rtol=1e-10, atol=1e-15)
    last = run.t > 390 * period
    radius = np.hypot(run["x1"][last], run["y1"][last])
    assert radius.max() == pytest.approx(branch.max_radius(1)[0], rel=1e-3)
    mean_x, mean_y = run["x1"][last].mean(), run["y1"][last].mean()
    assert np.hypot(mean_x, mean_y) == pytest.approx(abs(complex(*[branch.harmonic_amplitude(c, 0)[0]
                                                                   for c in ("x1", "y1")])), rel=1e-3)


def test_newton_from_zero_fails_at_300_and_the_homotopy_start_solves_it():
    from rotorkit.periodic import ConvergenceError
    from rotorkit.periodic.hb import HarmonicBalance, newton, newton_from_linear

    system = rk.Model(inner_rotor() + [rk.RubStator(station=1, clearance=CLEARANCE, contact_stiffness=KR,
                                                    friction_coefficient=MU, contact_radius=RADIUS)],
                      name="pst").compile()
    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=6)
    frame = hb.frame({"R_speed": 300.0})

    def fun(z, jacobian):
        return hb.residual(z, frame, jacobian)

    with pytest.raises(ConvergenceError, match="no convergence"):
        newton(fun, np.zeros(hb.size), tol=1e-10, scale=frame.scale, max_iterations=50)
    z = newton_from_linear(fun, np.zeros(hb.size), tol=1e-10, scale=frame.scale, max_iterations=50)[0]
    assert np.max(np.abs(fun(z, False)[0])) <= 1e-10 * frame.scale
    radius = np.hypot(*(np.reshape(z, (13, -1))[1:3, [system.coordinate_names.index(c) for c in ("x1", "y1")]]))
    assert np.max(radius) > CLEARANCE  # a rubbing solution, not the linear one
