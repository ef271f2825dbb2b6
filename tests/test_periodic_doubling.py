"""A period doubling on a rubbing rotor: located by Floquet multipliers against time integration, and the switch
onto the period-doubled branch (``nu = 2``) against a settled time run.

The rotor: a Jeffcott disk (2 kg, unbalance 20 um) on an anisotropic linear bearing (1.2 / 1.0 MN/m, 40 N s/m),
with gravity, in a rub stator of clearance 10 um and contact stiffness 4 MN/m (no friction): contact over part
of each period. Near 2928 rad/s (about twice the support's frequency in contact) the synchronous orbit loses
stability through a Floquet multiplier crossing -1, and the rotor settles on an orbit of twice the period.

- Independent location: time integrations at a constant speed, started from the settled synchronous orbit of a
  speed where it attracts, bisected on the speed by whether the alternating part of the once-per-revolution
  samples grows (period doubled) or decays (synchronous orbit stable). The harmonic-balance doubling (where the
  Hill multiplier crosses -1) lies within 0.5 % of it.
- The switched branch: ``nu = 2``, its points 2T-periodic with odd harmonics of ``Omega / 2``; at one speed past
  the doubling its max radius equals the settled time run's (which is 2T-periodic) to 1e-3.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorkit import Disk, Maneuver, Model, Rotor, RubStator, simulate
from rotorkit.analysis.periodic import period_doubled_branch, periodic_response, periodic_solution
from rotorkit.elements import LinearBearing
from rotorkit.errors import ParameterError

SPEEDS = (2990.0, 2900.0)  # rad/s: the synchronous orbit is stable at the first, period doubled at the second


@pytest.fixture(scope="module")
def system():
    return Model([Rotor(name="R", stations=(1,), speed=2990.0),
                  Disk(station=1, mass=2.0, radius=0.1, eccentricity=2e-5, torsion=False),
                  LinearBearing(station=1, kxx=1.2e6, kyy=1.0e6, cxx=40.0, cyy=40.0),
                  RubStator(station=1, clearance=1e-5, contact_stiffness=4e6, friction_coefficient=0.0),
                  Maneuver.steady(gravity=9.81)], name="pdrub").compile(backend="c")


@pytest.fixture(scope="module")
def branch(system):
    return periodic_response(system, speeds=SPEEDS, harmonics=10, max_step=0.02)


@pytest.fixture(scope="module")
def settled(system):
    """The state on the settled synchronous orbit at SPEEDS[0] (800 periods from rest), at a whole period."""
    W = SPEEDS[0]
    run = simulate(system.with_parameters(R_speed=W), (0.0, 800 * 2 * math.pi / W), rtol=1e-10, atol=1e-14,
                   sample_times=[800 * 2 * math.pi / W])
    return np.array([run[name][-1] for name in system.state_names])


def doubled_in_time(system, W, y0, periods=1500):
    """Whether the once-per-revolution samples' alternating part grows (the synchronous orbit unstable)."""
    T = 2 * math.pi / W
    run = simulate(system.with_parameters(R_speed=W), (0.0, periods * T), y0=y0, rtol=1e-10, atol=1e-14,
                   sample_times=np.arange(periods + 1) * T)
    x, y = run["x1"], run["y1"]
    alternating = np.hypot(x[2:] - x[1:-1], y[2:] - y[1:-1])
    # growing, or grown already to a doubled orbit (where it saturates)
    return bool(alternating[-1] > alternating[periods // 3] or alternating[-1] > 1e-2 * np.max(np.hypot(x, y)))


def test_period_doubling_located_within_half_a_percent_of_time_integration(system, branch, settled):
    doublings = [b for b in branch.bifurcations if b.kind == "period doubling"]
    assert len(doublings) == 1
    i = doublings[0].index
    assert branch.stable[i] and not branch.stable[i + 1]
    mu = branch.multipliers[i + 1]
    assert np.min(np.abs(mu + 1.0)) < 0.02  # the multiplier left the unit circle through -1
    lo, hi = sorted(SPEEDS)
    assert doubled_in_time(system, lo, settled) and not doubled_in_time(system, hi, settled)
    while hi - lo > 1e-3 * lo:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if doubled_in_time(system, mid, settled) else (lo, mid)
    assert doublings[0].parameter == pytest.approx(0.5 * (lo + hi), rel=5e-3)


def test_switch_to_the_period_doubled_branch_matches_a_settled_time_run(system, branch, settled):
    doubling = [b for b in branch.bifurcations if b.kind == "period doubling"][0]
    doubled = period_doubled_branch(system, branch, stop=2918.0, stability="none")
    assert doubled.subharmonic == 2 and doubled.harmonics == 2 * branch.harmonics
    assert doubled.reason.startswith("parameter bound")
    assert abs(doubled.parameter[0] - doubling.parameter) < 1e-3 * doubling.parameter
    odd = doubled.harmonic_amplitude("x1", 1) + doubled.harmonic_amplitude("y1", 1)
    assert odd[0] > 0 and odd[-1] > 10 * odd[0]  # leaves the synchronous branch, odd harmonics grow
    W = 2920.0
    k = int(np.argmin(np.abs(doubled.parameter - W)))
    hb = periodic_solution(system, harmonics=doubled.harmonics, subharmonic=2, samples=doubled.samples,
                           start=doubled.coefficients[k], R_speed=W, stability="none")
    T = 2 * math.pi / W
    N = 3000
    times = np.linspace((N - 4) * T, N * T, 4097)
    run = simulate(system.with_parameters(R_speed=W), (0.0, N * T), y0=settled, rtol=1e-11, atol=1e-14,
                   sample_times=times)
    x, y = run["x1"], run["y1"]
    assert np.max(np.abs(x[2048:] - x[:2049])) < 1e-9 * np.max(np.abs(x))  # 2T-periodic
    assert np.max(np.abs(x[1024:] - x[:-1024])) > 1e-2 * np.max(np.abs(x))  # not T-periodic
    assert hb.max_radius(1)[0] == pytest.approx(np.max(np.hypot(x, y)), rel=1e-3)


def test_a_branch_without_period_doubling_is_refused(system):
    branch = periodic_response(system, speeds=(2990.0, 2960.0), harmonics=4, max_points=5)
    assert not any(b.kind == "period doubling" for b in branch.bifurcations)
    with pytest.raises(ParameterError, match="no period doubling"):
        period_doubled_branch(system, branch)
