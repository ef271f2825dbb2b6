"""The squeeze-film damper against closed forms and an independent quadrature of the film pressure.

- A centred circular orbit of radius ``e = eps c`` at whirl speed ``w`` has the
  textbook short-bearing forces (San Andres, *Squeeze film dampers*, notes;
  Vance, *Rotordynamics of Turbomachinery*, ch. 6), with
  ``K = mu R L^3 w / c^2``: pi film ``F_r = -K 2 eps^2 / (1 - eps^2)^2``,
  ``F_t = -K pi eps / (2 (1 - eps^2)^(3/2))``; full film ``F_r = 0`` and twice
  that ``F_t``.
- For any state ``(x, y, x', y')`` the force equals the pressure of the
  short-bearing Reynolds equation, ``p = 6 mu (L^2/4 - z^2)(-dh/dt) / h^3``
  with ``h = c - x cos(theta) - y sin(theta)``, integrated numerically over
  the land and the circle (the pi film keeps only ``p > 0``). The quadrature
  knows nothing of the closed form's arc ends or of its ``atan``.
- At the centre the film is a linear damper ``pi mu R L^3 / c^3`` (full),
  half that (pi film).
- A rigid rotor on a damper with a centring spring has, near and above its
  critical speed, two stable circular orbits at one speed (the bi-stable
  response): the amplitudes solve the force balance written with the closed
  forms above, and a run-up and a run-down reach the two.

Forces are read from the compiled system: ``F = M q'' + k_s q``.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import integrate
from scipy.optimize import brentq

from rotorkit import Model, Rotor, SqueezeFilmDamper, simulate
from rotorkit.elements import Disk, LumpedMass
from rotorkit.elements.speed import SpeedProfile
from rotorkit.elements.squeeze_film import ShortBearingWarning
from rotorkit.errors import ParameterError, UnitError

MASS = 10.0  # kg
R, L, C, MU = 0.05, 0.015, 2e-4, 0.01  # m, m, m, Pa s
KS = 1e6  # N/m centring spring


def damper(cavitation="pi", **extra):
    fields = dict(station=1, radius=R, length=L, clearance=C, viscosity=MU, cavitation=cavitation,
                  centring_stiffness=KS)
    fields.update(extra)
    return SqueezeFilmDamper(**fields)


_SYSTEMS = {}


def system(cavitation="pi"):
    if cavitation not in _SYSTEMS:
        model = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=MASS),
                       damper(cavitation)], name=f"sfd_{cavitation}")
        _SYSTEMS[cavitation] = model.compile(backend="python")
    return _SYSTEMS[cavitation]


def film_force(cavitation, x, y, vx, vy):
    """The film force on the journal at a state, from the compiled equations."""
    acc = system(cavitation).rhs(0.0, np.array([x, y, vx, vy]))[2:]
    return MASS * acc + KS * np.array([x, y])


def quadrature_force(cavitation, x, y, vx, vy, omega=0.0):
    """Film force from the short-bearing pressure, integrated numerically over z and theta."""
    def pressure(theta, z):
        h = C - x * math.cos(theta) - y * math.sin(theta)
        dh_dtheta = x * math.sin(theta) - y * math.cos(theta)
        dh_dt = -vx * math.cos(theta) - vy * math.sin(theta)
        p = 6 * MU * (L**2 / 4 - z**2) * (-(omega / 2) * dh_dtheta - dh_dt) / h**3
        return max(p, 0.0) if cavitation == "pi" else p

    nodes, weights = np.polynomial.legendre.leggauss(4)  # exact for the quadratic profile in z
    zs, wz = nodes * L / 2, weights * L / 2

    def per_radian(theta):
        return sum(w * pressure(theta, z) for z, w in zip(zs, wz))

    grid = np.linspace(0.0, 2 * math.pi, 73)
    values = [per_radian(t) for t in grid]
    cuts = [brentq(per_radian, grid[i], grid[i + 1], xtol=1e-15)
            for i in range(len(grid) - 1) if values[i] * values[i + 1] < 0]
    edges = [0.0, *cuts, 2 * math.pi]
    force, tiny = [], 1e-12 * max(np.abs(values))
    for f in (math.cos, math.sin):
        total = sum(integrate.quad(lambda t: per_radian(t) * f(t), a, b, epsabs=tiny, epsrel=1e-12, limit=200)[0]
                    for a, b in zip(edges[:-1], edges[1:]))
        force.append(-R * total)
    return np.array(force)


@pytest.mark.parametrize("cavitation", ["pi", "full"])
@pytest.mark.parametrize("eps", [0.05, 0.3, 0.6, 0.9])
@pytest.mark.parametrize("whirl", [150.0, -400.0])
@pytest.mark.parametrize("angle", [0.0, 2.1])
def test_centred_circular_orbit_matches_the_short_bearing_closed_form(cavitation, eps, whirl, angle):
    e = eps * C
    x, y = e * math.cos(angle), e * math.sin(angle)
    vx, vy = -whirl * y, whirl * x  # circular whirl about the centre at `whirl` rad/s
    F = film_force(cavitation, x, y, vx, vy)
    er = np.array([math.cos(angle), math.sin(angle)])
    et = np.sign(whirl) * np.array([-math.sin(angle), math.cos(angle)])  # the direction of whirl
    K = MU * R * L**3 * abs(whirl) / C**2
    if cavitation == "pi":
        radial, tangential = -K * 2 * eps**2 / (1 - eps**2) ** 2, -K * math.pi * eps / (2 * (1 - eps**2) ** 1.5)
    else:
        radial, tangential = 0.0, -K * math.pi * eps / (1 - eps**2) ** 1.5
    scale = math.hypot(radial, tangential)
    assert abs(F @ et - tangential) <= 1e-10 * scale
    assert abs(F @ er - radial) <= 1e-10 * scale


@pytest.mark.parametrize("cavitation", ["pi", "full"])
@pytest.mark.parametrize("state", [(0.0, 0.0), (0.5, 0.2), (-0.9, 0.3)])
def test_no_film_force_at_rest(cavitation, state):
    x, y = state[0] * C, state[1] * C
    F = film_force(cavitation, x, y, 0.0, 0.0)
    assert np.all(F == 0.0) or np.max(np.abs(F)) <= 1e-12 * KS * C


STATES = [(0.3, -0.2, 0.01, 0.02), (-0.7, 0.4, -0.05, 0.01), (0.05, 0.85, 0.02, -0.03), (0.6, 0.0, -0.04, 0.0),
          (0.0, 0.0, 0.01, -0.02)]


@pytest.mark.parametrize("cavitation", ["pi", "full"])
@pytest.mark.parametrize("state", STATES)
def test_general_motion_matches_a_quadrature_of_the_pressure(cavitation, state):
    """Non-circular, off-centre motion: the closed form equals the integrated short-bearing pressure."""
    x, y, vx, vy = state[0] * C, state[1] * C, state[2], state[3]
    F, Q = film_force(cavitation, x, y, vx, vy), quadrature_force(cavitation, x, y, vx, vy)
    assert np.max(np.abs(F - Q)) <= 1e-9 * np.max(np.abs(Q))


def test_pi_film_only_pushes():
    """Only positive pressure acts: the force opposes the squeeze velocity and is not the full film's."""
    rng = np.random.default_rng(7)
    for _ in range(40):
        r, a = 0.95 * C * math.sqrt(rng.uniform()), rng.uniform(0, 2 * math.pi)
        x, y = r * math.cos(a), r * math.sin(a)
        v = rng.normal(size=2) * 0.05
        assert film_force("pi", x, y, *v) @ v < 0.0
    # moving away from the near wall (film opening there): the full film pulls the journal after it, the pi
    # film only pushes from the far side, much more weakly
    x, vx = 0.8 * C, -0.01
    pull, push = film_force("full", x, 0.0, vx, 0.0)[0], film_force("pi", x, 0.0, vx, 0.0)[0]
    towards = film_force("pi", x, 0.0, -vx, 0.0)[0]
    assert pull > 0 and 0 < push < 0.05 * pull and towards < -20 * push


@pytest.mark.parametrize("cavitation, factor", [("pi", 0.5), ("full", 1.0)])
def test_centred_damper_is_linear_damping(cavitation, factor):
    """At the centre the film is a viscous damper pi mu R L^3 / c^3 (times 1/2 for the pi film)."""
    from rotorkit.analysis.linearize import linearize

    A, _ = linearize(system(cavitation), [0.0, 0.0], method="analytic")
    expected = factor * math.pi * MU * R * L**3 / C**3
    assert damper(cavitation).centred_damping() == pytest.approx(expected, rel=1e-14)
    np.testing.assert_allclose(-A[2:, 2:] * MASS, expected * np.eye(2), rtol=1e-12, atol=1e-9 * expected)
    np.testing.assert_allclose(-A[2:, :2] * MASS, KS * np.eye(2), rtol=1e-12, atol=1e-9 * KS)


def test_static_offset_and_centring_damping():
    """The spring's neutral point is the journal's rest position; c_s adds to the film."""
    model = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=MASS),
                   damper(centring_damping=300.0, offset_x=2e-5, offset_y=-5e-5)])
    sys_ = model.compile(backend="python")
    assert set(model.parameters) >= {"sfd1_offset_x", "sfd1_offset_y", "sfd1_centring_damping"}
    np.testing.assert_allclose(sys_.rhs(0.0, np.array([2e-5, -5e-5, 0.0, 0.0]))[2:], 0.0, atol=1e-12)
    x, y, vx, vy = 1e-5, 3e-5, 0.02, -0.01
    acc = sys_.rhs(0.0, np.array([x, y, vx, vy]))[2:]
    film = MASS * acc + KS * np.array([x - 2e-5, y + 5e-5]) + 300.0 * np.array([vx, vy])
    np.testing.assert_allclose(film, film_force("pi", x, y, vx, vy), rtol=1e-12)


def test_switches_mark_the_arc_flip_and_a_run_with_events_works():
    """The pi film declares the radial and tangential squeeze (zero together where the arc flips)."""
    pi_sys, full_sys = system("pi"), system("full")
    assert pi_sys.n_switches == 2 and full_sys.n_switches == 0
    x, y, vx, vy = 3e-5, -4e-5, 0.01, 0.02
    np.testing.assert_allclose(pi_sys.switch_values(0.0, np.array([x, y, vx, vy])),
                               [x * vx + y * vy, x * vy - y * vx], rtol=1e-14)
    result = simulate(pi_sys, (0.0, 0.02), y0=[5e-5, 0.0, 0.0, 0.0], contact_events=True)
    assert result.stats["events"] >= 1
    assert np.max(np.hypot(result["x1"], result["y1"])) < C


def test_units_model_file_and_label(tmp_path):
    from rotorkit import load_model

    d = SqueezeFilmDamper(station="brg", radius="50 mm", length="15 mm", clearance="0.2 mm", viscosity="10 mPa*s",
                          centring_stiffness="1 MN/m", offset_y="-20 um")
    assert d.label() == "sfdbrg"
    assert (d.radius, d.length, d.clearance, d.viscosity, d.centring_stiffness) == pytest.approx(
        (0.05, 0.015, 2e-4, 0.01, 1e6), rel=1e-12)
    assert d.offset_y == pytest.approx(-2e-5) and d.offset_x is None and d.parameters().keys() == {
        "radius", "length", "clearance", "viscosity", "centring_stiffness", "offset_y"}
    model = Model([Rotor(name="R", stations=("brg",), speed=0.0), LumpedMass(station="brg", mass=MASS), d])
    again = load_model(model.save(tmp_path / "sfd.toml"))
    assert again.parameters == model.parameters and again.structure_key == model.structure_key


@pytest.mark.parametrize("fields, match", [
    (dict(viscosity=-0.01), r"SqueezeFilmDamper\.viscosity = -0\.01 must be > 0"),
    (dict(clearance=0.0), r"SqueezeFilmDamper\.clearance = 0\.0 must be > 0"),
    (dict(clearance=0.06), r"clearance = 0\.06 m is not smaller than radius"),
    (dict(cavitation="half"), r"cavitation = 'half': expected 'pi'"),
    (dict(viscosity=None), r"viscosity is required"),
    (dict(centring_stiffness=None, offset_x=1e-5), r"give centring_stiffness"),
    (dict(offset_x=1.5e-4, offset_y=1.5e-4), r"static offset 0\.0002121 m is not inside the clearance"),
    (dict(centring_stiffness=None, centring_damping=10.0), r"centring_damping needs centring_stiffness"),
    (dict(station=-1), r"station = -1: expected a station"),
])
def test_bad_input_is_named(fields, match):
    with pytest.raises(ParameterError, match=match):
        damper(**fields)


def test_wrong_unit_and_long_land():
    with pytest.raises(UnitError, match="viscosity"):
        damper(viscosity="3 m")
    with pytest.warns(ShortBearingWarning, match=r"L/D = length / \(2 radius\) = 0\.6 > 0\.5"):
        damper(length=0.06)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        damper(length=0.05)  # L/D = 0.5: no warning


# -- bi-stable unbalance response ------------------------------------------------------------------------------
M_ROTOR, K_CAGE, MU_BI, UNBALANCE = 10.0, 1e6, 0.004, 0.15 * C  # kg, N/m, Pa s, m
WN = math.sqrt(K_CAGE / M_ROTOR)


def circular_orbits(speed):
    """Eccentricity ratios of the steady synchronous circular orbits (closed-form pi-film forces)."""
    def balance(eps):
        K = MU_BI * R * L**3 * speed / C**2
        radial = -K * 2 * eps**2 / (1 - eps**2) ** 2
        tangential = -K * math.pi * eps / (2 * (1 - eps**2) ** 1.5)
        return ((K_CAGE - M_ROTOR * speed**2) * eps * C - radial) ** 2 + tangential**2 \
            - (M_ROTOR * UNBALANCE * speed**2) ** 2

    eps = np.linspace(1e-6, 0.99, 3000)
    g = [balance(e) for e in eps]
    return [brentq(balance, eps[i], eps[i + 1], xtol=1e-14) for i in range(len(eps) - 1) if g[i] * g[i + 1] < 0]


@pytest.mark.slow
def test_bistable_response_of_an_sfd_supported_rotor():
    """At 1.23 wn two stable orbits coexist: the run-up arrives on the large one, the run-down on the small one."""
    speed = 1.23 * WN
    small, middle, large = circular_orbits(speed)
    assert small < 0.55 and large > 0.75  # three orbits: the middle one is unstable

    def run(start):
        profile = SpeedProfile.table(times=[0.0, 1.0], speeds=[start * WN, speed])
        model = Model([Rotor(name="R", stations=(1,), speed=profile),
                       Disk(station=1, mass=M_ROTOR, radius=0.1, eccentricity=UNBALANCE, torsion=False),
                       SqueezeFilmDamper(station=1, radius=R, length=L, clearance=C, viscosity=MU_BI,
                                         centring_stiffness=K_CAGE)])
        result = simulate(model.compile(backend="c"), (0.0, 2.5), sample_rate=4000.0, rtol=1e-8, atol=1e-12)
        late = result.window(2.2, 2.5)
        return np.hypot(late["x1"], late["y1"]) / C

    up, down = run(1.05), run(1.4)
    # steady circular orbits, each on its closed-form branch
    assert np.ptp(up) < 0.01 and abs(up.mean() - large) < 0.01
    assert np.ptp(down) < 0.01 and abs(down.mean() - small) < 0.01


@pytest.mark.slow
def test_sfd_runup_example(tmp_path):
    """The example runs; the damper passes the critical speed with a smaller peak than its centred linearisation."""
    import os
    import re
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")]),
           "MPLBACKEND": "Agg"}
    proc = subprocess.run([sys.executable, str(root / "examples" / "sfd_runup.py"), "--plot",
                           str(tmp_path / "runup.png")], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                          env=env)
    assert proc.returncode == 0, proc.stderr
    peaks = dict(re.findall(r"^(.+?): peak whirl radius ([\d.]+) um", proc.stdout, flags=re.M))
    ratios = [float(r) for r in re.findall(r"= ([\d.]+) x critical", proc.stdout)]
    assert float(peaks["squeeze-film damper"]) < 0.8 * float(peaks["linear damper (centred coefficient)"])
    assert len(ratios) == 2 and all(1.0 < r < 1.3 for r in ratios)
    assert (tmp_path / "runup.png").stat().st_size > 10_000


def test_c_back_end_computes_the_same_film_forces():
    """The C translation of the generated code (atan, sqrt, guarded divisions) gives the Python numbers."""
    from rotorkit import JournalBearing, available_backends

    if "c" not in available_backends():
        pytest.skip("no C compiler")
    model = Model([Rotor(name="R", stations=(1, 2), speed=800.0), LumpedMass(station=1, mass=MASS),
                   LumpedMass(station=2, mass=MASS), damper(),
                   JournalBearing(station=2, radius=0.025, length=0.02, clearance=5e-5, viscosity=0.02)],
                  name="films_c")
    py, c = model.compile(backend="python"), model.compile(backend="c")
    assert py.coordinate_names == ("x1", "x2", "y1", "y2")
    scale = np.array([C, 5e-5, C, 5e-5])  # the damper at 1, the bearing at 2
    rng = np.random.default_rng(3)
    for _ in range(5):
        y = np.concatenate([rng.uniform(-0.6, 0.6, 4) * scale, rng.normal(size=4) * 0.02])
        np.testing.assert_allclose(c.rhs(0.1, y), py.rhs(0.1, y), rtol=1e-12, atol=1e-9)
    rest = np.zeros(8)
    np.testing.assert_allclose(c.rhs(0.0, rest), py.rhs(0.0, rest), atol=1e-12)


def test_a_damper_without_cage_holds_nothing_statically():
    """The film has no stiffness at rest: without a centring spring another element must hold the rotor."""
    from rotorkit import ElasticSupport
    from rotorkit.errors import TopologyError

    bare = SqueezeFilmDamper(station=1, radius=R, length=L, clearance=C, viscosity=MU)
    assert bare.grounds() == () and damper().grounds() == ((1, "x"), (1, "y"))
    with pytest.raises(TopologyError, match="no support"):
        Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=MASS), bare])
    held = Model([Rotor(name="R", stations=(1,), speed=0.0), LumpedMass(station=1, mass=MASS), bare,
                  ElasticSupport(station=1, stiffness=KS)]).compile(backend="python")
    state = np.array([3e-5, -2e-5, 0.01, 0.02])
    np.testing.assert_allclose(MASS * held.rhs(0.0, state)[2:] + KS * state[:2], film_force("pi", *state),
                               rtol=1e-12)


@pytest.mark.parametrize("cavitation", ["pi", "full"])
def test_generated_jacobian_matches_finite_differences(cavitation):
    """The symbolic derivatives of the guarded pieces (safe_div, hypot, ramp) are those of the force."""
    s = system(cavitation)
    for state in STATES[:3]:
        y = np.array([state[0] * C, state[1] * C, state[2], state[3]])
        J = s.jacobian(0.0, y)
        steps = np.array([1e-9, 1e-9, 1e-6, 1e-6])
        fd = np.column_stack([(s.rhs(0.0, y + h * e) - s.rhs(0.0, y - h * e)) / (2 * h)
                              for h, e in zip(steps, np.eye(4))])
        np.testing.assert_allclose(J, fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())
