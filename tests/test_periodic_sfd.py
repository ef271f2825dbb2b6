"""The bi-stable unbalance response of a Jeffcott rotor on a squeeze-film damper, as a periodic-response branch.

A rigid rotor (mass ``m``, unbalance ``u``) on a pi-film short-bearing damper with a centring spring ``k_s``
(isotropic, no gravity). A centred circular orbit of radius ``e = eps c`` at the whirl speed ``W`` meets the
closed-form pi-film forces (San Andres; Vance), with ``K = mu R L^3 W / c^2``,
``F_r = -K 2 eps^2 / (1 - eps^2)^2`` and ``F_t = -K pi eps / (2 (1 - eps^2)^(3/2))``, so the circle solves
``((k_s - m W^2) e - F_r)^2 + F_t^2 = (m u W^2)^2``. The radial force stiffens the support with the amplitude
and the speed: the response curve bends over, three circles coexist between two folds. Checked here:

- every point of the harmonic-balance branch lies on that circle (independent closed form);
- the branch has exactly two folds, at the closed-form turning points of the speed along the circle curve,
  and its points are stable outside them and unstable between them (Floquet multipliers by Hill);
- a time integration at one speed inside the bi-stable range, started from the settled orbit of a speed
  just below it (a run-up's start) and just above it (a run-down's start), settles on the large and on
  the small stable HB orbit respectively (max radius to 1e-3).

The pi-film force switches where the squeeze velocity vanishes; on these circular orbits the squeeze velocity
(the whirl at ``W`` relative to a frame turning at ``Omega / 2 = 0``) never vanishes, so the AFT samples never
straddle a switch and Newton converges quadratically.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import rotorkit as rk
from rotorkit.analysis.periodic import periodic_response, periodic_solution
from rotorkit.elements import Disk

MASS, CAGE = 10.0, 1.0e6  # kg, N/m
R, L, C, MU = 0.05, 0.015, 2.0e-4, 0.004  # m, m, m, Pa s
U = 0.15 * C  # m
CRITICAL = math.sqrt(CAGE / MASS)  # rad/s
SPEEDS = (0.9 * CRITICAL, 1.5 * CRITICAL)
BISTABLE = 1.23 * CRITICAL  # inside the fold pair (about 1.198 and 1.265 times the critical speed)


def sfd_model():
    film = rk.SqueezeFilmDamper(station=1, centring_stiffness=CAGE, radius=R, length=L, clearance=C, viscosity=MU)
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=CRITICAL),
                     Disk(station=1, mass=MASS, radius=0.1, eccentricity=U, torsion=False), film], name="sfd_jeffcott")


def balance(eps, W):
    """The circle equation, relative to the unbalance force squared (zero on a steady circular orbit)."""
    K = MU * R * L**3 * W / C**2
    radial, tangential = -K * 2 * eps**2 / (1 - eps**2) ** 2, -K * math.pi * eps / (2 * (1 - eps**2) ** 1.5)
    return (((CAGE - MASS * W**2) * eps * C - radial) ** 2 + tangential**2) / (MASS * U * W**2) ** 2 - 1.0


def circles(W):
    """Eccentricity ratios of all steady circular orbits at speed W (closed form)."""
    grid = np.linspace(1e-6, 0.99, 4000)
    g = np.array([balance(e, W) for e in grid])
    return [brentq(balance, grid[i], grid[i + 1], args=(W,), xtol=1e-14) for i in np.flatnonzero(g[:-1] * g[1:] < 0)]


def fold_speeds():
    """The turning points of W along the circle curve eps -> W(eps) on its bent-over part (closed form)."""
    def speed_of(eps, pick):  # the speed in the bent-over window where the orbit of ratio eps is a solution
        grid = np.linspace(1.1 * CRITICAL, 1.4 * CRITICAL, 600)
        g = np.array([balance(eps, W) for W in grid])
        roots = [brentq(lambda W: balance(eps, W), grid[i], grid[i + 1], xtol=1e-12)
                 for i in np.flatnonzero(g[:-1] * g[1:] < 0)]
        return pick(roots) if roots else np.nan

    upper = minimize_scalar(lambda e: -speed_of(e, max), bounds=(0.78, 0.83), method="bounded",
                            options={"xatol": 1e-9}).fun
    lower = minimize_scalar(lambda e: speed_of(e, min), bounds=(0.55, 0.75), method="bounded",
                            options={"xatol": 1e-9}).fun
    return -upper, lower


@pytest.fixture(scope="module")
def system():
    return sfd_model().compile(backend="c")


@pytest.fixture(scope="module")
def branch(system):
    return periodic_response(system, speeds=SPEEDS, harmonics=3)


def test_branch_lies_on_the_closed_form_circles(branch):
    assert branch.reason.startswith("parameter bound")
    eps = branch.max_radius(1) / C
    for W, e in zip(branch.parameter, eps):
        assert abs(balance(e, W)) < 1e-8
    # circular orbits: the higher harmonics vanish
    assert np.max(branch.harmonic_amplitude("x1", 2)) < 1e-10 * C
    assert np.max(branch.harmonic_amplitude("x1", 3)) < 1e-10 * C
    # all three circles found where they coexist
    found = sorted(e for W, e in zip(branch.parameter, eps) if abs(W - BISTABLE) < 0.03 * CRITICAL)
    assert len(circles(BISTABLE)) == 3
    assert min(found) < circles(BISTABLE)[0] + 0.05 and max(found) > circles(BISTABLE)[2] - 0.05


def test_two_folds_bound_the_one_unstable_segment(branch):
    folds = [b for b in branch.bifurcations if b.kind == "fold"]
    assert [b.kind for b in branch.bifurcations] == ["fold", "fold"]
    upper, lower = fold_speeds()
    assert folds[0].parameter == pytest.approx(upper, rel=5e-4)
    assert folds[1].parameter == pytest.approx(lower, rel=5e-4)
    stable = branch.stable
    i, j = folds[0].index, folds[1].index
    assert np.all(stable[: i + 1]) and np.all(stable[j + 1:])
    assert not np.any(stable[i + 1: j + 1])
    # one unstable segment: stability changes exactly twice along the branch
    assert np.count_nonzero(np.diff(stable.astype(int))) == 2


def _settle(system, speed, y0, periods):
    """Integrate ``periods`` whole periods at a constant speed (so the unbalance phase restarts at zero);
    return the final state and the max radius over the last 5 periods."""
    T = 2 * math.pi / speed
    result = rk.simulate(system.with_parameters(R_speed=speed), (0.0, periods * T), y0=y0, rtol=1e-10,
                         atol=1e-14, sample_rate=400 / T)
    last = result.t > (periods - 5) * T
    final = np.array([result[name][-1] for name in system.state_names])
    return final, float(np.max(np.hypot(result["x1"][last], result["y1"][last])))


def test_run_up_and_run_down_settle_on_the_stable_hb_orbits(system, branch):
    eps = branch.max_radius(1) / C
    near = np.abs(branch.parameter - BISTABLE)
    small, middle, large = circles(BISTABLE)
    hb = {}
    for label, target in (("small", small), ("large", large)):  # HB at the test speed from the nearest point
        k = int(np.argmin(near + np.where(branch.stable, 0.0, np.inf) + 10 * CRITICAL * np.abs(eps - target)))
        solution = periodic_solution(system, harmonics=3, start=branch.coefficients[k], R_speed=BISTABLE)
        assert solution.stable[0]
        hb[label] = solution.max_radius(1)[0] / C
        assert hb[label] == pytest.approx(target, rel=1e-8)
    radii = {}
    for label, before in (("run-up", 1.15 * CRITICAL), ("run-down", 1.32 * CRITICAL)):
        y0, _ = _settle(system, before, None, 300)
        radii[label] = _settle(system, BISTABLE, y0, 400)[1] / C
    assert radii["run-up"] == pytest.approx(hb["large"], rel=1e-3)
    assert radii["run-down"] == pytest.approx(hb["small"], rel=1e-3)
