"""The short plain journal bearing against the closed-form short-bearing results.

- Static equilibrium (Ocvirk; Friswell et al., *Dynamics of Rotating
  Machines*, eqs. of section 5.5): with ``S_s = mu D Omega L^3 / (8 W c^2)``,
  ``1 / S_s = eps sqrt(16 eps^2 + pi^2 (1 - eps^2)) / (1 - eps^2)^2`` and
  ``tan(phi) = pi sqrt(1 - eps^2) / (4 eps)``, phi from the load line in the
  direction of rotation; checked on the model's own static equilibrium
  (:func:`rotorkit.analysis.linearize.static_equilibrium` of the compiled
  equations), not only on the closed-form helper.
- The eight coefficients: the closed-form short-bearing stiffness and damping
  (Friswell et al., same section; with ``h0 = 1/(pi^2 (1-eps^2) + 16 eps^2)^(3/2)``,
  ``K = (W/c) a``, ``C = (W/(c Omega)) b``) against the derivatives of the
  film force, both from :meth:`JournalBearing.operating_point` and from the
  model's generated analytic Jacobian.
- Oil whip of a rigid symmetric rotor (mass ``2 m`` on two identical bearings:
  by symmetry its cylindrical whirl is that of ``m`` on one bearing): the
  threshold from Lund's stability formula with the closed-form coefficients,
  ``c Omega^2 / g = K_eq / gamma^2``, against the speed where the model's
  linearised eigenvalues cross the imaginary axis, and time runs on both
  sides of it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rotorkit import JournalBearing, Maneuver, Model, Rotor, simulate
from rotorkit.analysis.linearize import linearize, static_equilibrium
from rotorkit.elements import LumpedMass
from rotorkit.elements.journal_bearing import short_bearing_eccentricity
from rotorkit.elements.squeeze_film import ShortBearingWarning
from rotorkit.errors import ParameterError

M, R, L, C, MU, G = 50.0, 0.025, 0.02, 5e-5, 0.02, 9.81  # kg (per bearing), m, m, m, Pa s, m/s^2
W = M * G


def bearing(**extra):
    fields = dict(station=1, radius=R, length=L, clearance=C, viscosity=MU)
    fields.update(extra)
    return JournalBearing(**fields)


_SYSTEMS = {}


def system(cavitation="pi"):
    if cavitation not in _SYSTEMS:
        model = Model([Rotor(name="R", stations=(1,), speed=1000.0), LumpedMass(station=1, mass=M),
                       bearing(cavitation=cavitation), Maneuver.steady(gravity=G)], name=f"journal_{cavitation}")
        _SYSTEMS[cavitation] = model.compile(backend="python")
    return _SYSTEMS[cavitation]


def modified_sommerfeld(speed):
    return MU * 2 * R * abs(speed) * L**3 / (8 * W * C**2)


def closed_form_coefficients(eps, speed):
    """Short-bearing K (N/m) and C (N s/m), x horizontal, y up, load along -y, rotation about +z."""
    pi, r = math.pi, math.sqrt(1 - eps**2)
    h0 = 1 / (pi**2 * (1 - eps**2) + 16 * eps**2) ** 1.5
    a = h0 * np.array([
        [4 * (pi**2 * (2 - eps**2) + 16 * eps**2), pi * (pi**2 * (1 - eps**2) ** 2 - 16 * eps**4) / (eps * r)],
        [-pi * (pi**2 * (1 - eps**2) * (1 + 2 * eps**2) + 32 * eps**2 * (1 + eps**2)) / (eps * r),
         4 * (pi**2 * (1 + 2 * eps**2) + 32 * eps**2 * (1 + eps**2) / (1 - eps**2))]])
    b = h0 * np.array([
        [2 * pi * r * (pi**2 * (1 + 2 * eps**2) - 16 * eps**2) / eps, -8 * (pi**2 * (1 + 2 * eps**2) - 16 * eps**2)],
        [-8 * (pi**2 * (1 + 2 * eps**2) - 16 * eps**2), 2 * pi * (pi**2 * (1 - eps**2) ** 2 + 48 * eps**2) / (eps * r)]])
    return W / C * a, W / (C * speed) * b


SPEEDS = [60.0, 300.0, 1000.0, 4000.0]  # rad/s: eps from about 0.8 down to 0.1


@pytest.mark.parametrize("speed", SPEEDS)
def test_static_equilibrium_is_the_closed_form_eccentricity_and_attitude(speed):
    s = system().with_parameters(R_speed=speed)
    x, y = static_equilibrium(s, tol=1e-12)
    eps = math.hypot(x, y) / C
    attitude = math.atan2(y, x) + math.pi / 2  # from the load (-y) towards +x: the direction of rotation
    inverse_s = eps * math.sqrt(16 * eps**2 + math.pi**2 * (1 - eps**2)) / (1 - eps**2) ** 2
    assert inverse_s * modified_sommerfeld(speed) == pytest.approx(1.0, rel=1e-9)
    assert math.tan(attitude) == pytest.approx(math.pi * math.sqrt(1 - eps**2) / (4 * eps), rel=1e-9)
    op = bearing().operating_point(load=W, speed=speed)
    assert op.eccentricity_ratio == pytest.approx(eps, rel=1e-9)
    assert op.attitude_angle == pytest.approx(attitude, rel=1e-9)
    np.testing.assert_allclose(op.position, [x, y], rtol=1e-8, atol=1e-9 * C)
    S, Ss = bearing().sommerfeld_numbers(W, speed)
    assert Ss == pytest.approx(modified_sommerfeld(speed), rel=1e-14)
    assert S == pytest.approx(MU * speed / (2 * math.pi) * L * 2 * R * (R / C) ** 2 / W, rel=1e-14)


def test_operating_point_follows_the_load_direction_and_the_sense_of_rotation():
    jb = bearing()
    down = jb.operating_point(load=W, speed=1000.0)
    sideways = jb.operating_point(load=(W, 0.0), speed=1000.0)  # load along +x
    reverse = jb.operating_point(load=W, speed=-1000.0)
    rotate = np.array([[0.0, -1.0], [1.0, 0.0]])  # +90 deg: -y -> +x
    np.testing.assert_allclose(sideways.position, rotate @ down.position, rtol=1e-12, atol=1e-12 * C)
    np.testing.assert_allclose(reverse.position, down.position * [-1, 1], rtol=1e-12, atol=1e-12 * C)
    assert down.position[0] > 0 and down.position[1] < 0  # below the centre, displaced in the rotation's sense


@pytest.mark.parametrize("speed", SPEEDS)
def test_eight_coefficients_match_the_closed_form(speed):
    op = bearing().operating_point(load=W, speed=speed)
    K, Cc = closed_form_coefficients(op.eccentricity_ratio, speed)
    np.testing.assert_allclose(op.stiffness, K, rtol=1e-9, atol=1e-10 * np.abs(K).max())
    np.testing.assert_allclose(op.damping, Cc, rtol=1e-9, atol=1e-10 * np.abs(Cc).max())


@pytest.mark.parametrize("speed", [300.0, 1000.0])
def test_model_jacobian_at_equilibrium_gives_the_same_coefficients(speed):
    """The generated analytic Jacobian of the equations of motion, at the static equilibrium."""
    s = system().with_parameters(R_speed=speed)
    q = static_equilibrium(s, tol=1e-12)
    A, _ = linearize(s, q, method="analytic")
    eps = math.hypot(*q) / C
    K, Cc = closed_form_coefficients(eps, speed)
    np.testing.assert_allclose(-M * A[2:, :2], K, rtol=1e-7, atol=1e-8 * np.abs(K).max())
    np.testing.assert_allclose(-M * A[2:, 2:], Cc, rtol=1e-7, atol=1e-8 * np.abs(Cc).max())


def test_full_film_equilibrium_is_perpendicular_to_the_load():
    s = system("full").with_parameters(R_speed=1000.0)
    x, y = static_equilibrium(s, tol=1e-12)
    eps = math.hypot(x, y) / C
    assert abs(y) <= 1e-8 * C  # attitude 90 degrees: straight beside the centre
    assert 2 * math.pi * modified_sommerfeld(1000.0) * eps / (1 - eps**2) ** 1.5 == pytest.approx(1.0, rel=1e-9)
    assert short_bearing_eccentricity(modified_sommerfeld(1000.0), "full") == pytest.approx((eps, math.pi / 2))


def test_static_deflection_reports_the_bearing_reaction():
    """The bearing grounds the journal: the static analysis finds it carrying the weight."""
    from rotorkit.analysis.static import static_deflection

    result = static_deflection(system().with_parameters(R_speed=1000.0))
    reaction = result.reactions["journal1"]
    assert reaction["y1"] == pytest.approx(W, rel=1e-9) and abs(reaction["x1"]) < 1e-9 * W


def test_speed_comes_from_the_model():
    """A bearing on a geared rotor (speed ratio) sees that rotor's speed."""
    direct = Model([Rotor(name="A", stations=(1,), speed=1000.0), LumpedMass(station=1, mass=M), bearing()])
    geared = Model([Rotor(name="A", stations=(0,), speed=500.0), LumpedMass(station=0, mass=M),
                    bearing(station=0),
                    Rotor(name="B", stations=(1,), speed_ratio=2.0, reference="A"), LumpedMass(station=1, mass=M),
                    bearing()])
    state = np.array([1e-5, -2e-5, 0.01, 0.003])
    a1 = direct.compile(backend="python").rhs(0.0, state)[2:]
    names = geared.coordinate_names
    s2 = geared.compile(backend="python")
    y = np.zeros(2 * len(names))
    y[names.index("x1")], y[names.index("y1")] = state[:2]
    y[len(names) + names.index("x1")], y[len(names) + names.index("y1")] = state[2:]
    a2 = s2.rhs(0.0, y)[len(names):]
    np.testing.assert_allclose([a2[names.index("x1")], a2[names.index("y1")]], a1, rtol=1e-13)


# -- oil whip -------------------------------------------------------------------------------------------------
def lund_threshold_ratio(eps):
    """``c Omega^2 / g`` at the stability threshold of a rigid rotor, and the whirl ratio (Lund's formula)."""
    K, D = closed_form_coefficients(eps, 1.0)
    k, d = K * C / W, D * C / W  # dimensionless: K = (W/c) k, C = (W/(c Omega)) d
    k_eq = (k[0, 0] * d[1, 1] + k[1, 1] * d[0, 0] - k[0, 1] * d[1, 0] - k[1, 0] * d[0, 1]) / (d[0, 0] + d[1, 1])
    gamma2 = ((k_eq - k[0, 0]) * (k_eq - k[1, 1]) - k[0, 1] * k[1, 0]) / (d[0, 0] * d[1, 1] - d[0, 1] * d[1, 0])
    return k_eq / gamma2, math.sqrt(gamma2)


def classical_whip_threshold():
    def excess(speed):
        eps = short_bearing_eccentricity(modified_sommerfeld(speed))[0]
        return C * speed**2 / G - lund_threshold_ratio(eps)[0]

    return brentq(excess, 800.0, 3200.0, xtol=1e-12)


def largest_growth_rate(speed):
    s = system().with_parameters(R_speed=speed)
    A, _ = linearize(s, static_equilibrium(s, tol=1e-12))
    eigenvalues = np.linalg.eigvals(A)
    return eigenvalues[np.argmax(eigenvalues.real)]


def test_whip_onset_from_the_linear_stability_analysis_is_the_classical_threshold():
    threshold = classical_whip_threshold()
    assert largest_growth_rate(0.95 * threshold).real < 0 < largest_growth_rate(1.05 * threshold).real
    onset = brentq(lambda w: largest_growth_rate(w).real, 0.95 * threshold, 1.05 * threshold, xtol=1e-9 * threshold)
    assert onset == pytest.approx(threshold, rel=1e-7)
    eps = short_bearing_eccentricity(modified_sommerfeld(threshold))[0]
    whirl_ratio = lund_threshold_ratio(eps)[1]
    assert abs(largest_growth_rate(onset).imag) == pytest.approx(whirl_ratio * threshold, rel=1e-6)
    assert 0.4 < whirl_ratio < 0.55  # the half-speed whirl


def test_campbell_stability_analysis_finds_the_whip_onset():
    """The analyses' own entry: campbell(..., relinearize=True) reports the onset at the classical threshold."""
    from rotorkit.analysis.modes import campbell

    threshold = classical_whip_threshold()
    result = campbell(system(), np.linspace(0.6, 1.4, 5) * threshold, n_modes=2, relinearize=True)
    (onset,) = result.onsets
    assert onset.becomes == "unstable" and onset.whirl == "forward"
    assert onset.speed == pytest.approx(threshold, rel=1e-6)


@pytest.mark.parametrize("factor, grows", [(0.85, False), (1.15, True)])
def test_time_run_on_both_sides_of_the_whip_threshold(factor, grows):
    """Nonlinear time runs from a nudged equilibrium: the whirl dies out below the threshold, grows above."""
    speed = factor * classical_whip_threshold()
    s = system().with_parameters(R_speed=speed)
    q = static_equilibrium(s, tol=1e-12)
    nudge = 0.02 * C
    result = simulate(s, (0.0, 0.25), y0=[q[0] + nudge, q[1], 0.0, 0.0], sample_rate=20000.0, rtol=1e-9,
                      atol=1e-14)
    deviation = np.hypot(result["x1"] - q[0], result["y1"] - q[1])
    start, end = deviation[result.t < 0.02].max(), deviation[result.t > 0.2].max()
    rate = largest_growth_rate(speed).real
    if grows:
        assert end > 20 * start and rate > 0
    else:
        assert end < start / 20 and rate < 0
    assert np.max(np.hypot(result["x1"], result["y1"])) < C


# -- bad input ------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("fields, match", [
    (dict(viscosity=-0.02), r"JournalBearing\.viscosity = -0\.02 must be > 0"),
    (dict(clearance=0.0), r"JournalBearing\.clearance = 0\.0 must be > 0"),
    (dict(radius=None), r"radius is required"),
    (dict(cavitation="gumbel"), r"cavitation = 'gumbel': expected 'pi'"),
    (dict(clearance=0.03), r"clearance = 0\.03 m is not smaller than radius"),
])
def test_bad_input_is_named(fields, match):
    with pytest.raises(ParameterError, match=match):
        bearing(**fields)


@pytest.mark.parametrize("load, speed, match", [
    (W, 0.0, r"speed = 0\.0: expected a nonzero spin speed"),
    (0.0, 100.0, r"load = 0\.0 must be > 0"),
    ((0.0, 0.0), 100.0, r"is zero: expected a static load"),
    ((1.0, 2.0, 3.0), 100.0, r"expected a magnitude \(N\) or a vector"),
])
def test_bad_operating_point_input_is_named(load, speed, match):
    with pytest.raises(ParameterError, match=match):
        bearing().operating_point(load=load, speed=speed)


def test_long_bearing_warns_with_its_ratio_and_units_are_read():
    with pytest.warns(ShortBearingWarning, match=r"L/D = length / \(2 radius\) = 1 > 0\.5"):
        bearing(length=0.05)
    jb = JournalBearing(station=1, radius="25 mm", length="20 mm", clearance="50 um", viscosity="20 mPa*s")
    assert (jb.radius, jb.length, jb.clearance, jb.viscosity) == pytest.approx((R, L, C, MU), rel=1e-12)
    op = jb.operating_point(load=f"{W} N", speed=f"{1000.0 * 60 / (2 * math.pi)} rpm")
    assert op.speed == pytest.approx(1000.0, rel=1e-12)
    assert jb.label() == "journal1" and jb.grounds() == ((1, "x"), (1, "y"))


@pytest.mark.slow
def test_journal_whip_example(tmp_path):
    """The example runs: the whirl dies out below the threshold and grows into whip near half speed above it."""
    import os
    import re
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")]),
           "MPLBACKEND": "Agg"}
    proc = subprocess.run([sys.executable, str(root / "examples" / "journal_whip.py"), "--plot",
                           str(tmp_path / "whip.png")], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                          env=env)
    assert proc.returncode == 0, proc.stderr
    threshold = float(re.search(r"analysis: ([\d.]+) rad/s", proc.stdout).group(1))
    assert threshold == pytest.approx(classical_whip_threshold(), rel=1e-3)
    swings = [float(v) for v in re.findall(r"x swings by \+-([\d.e+-]+) um", proc.stdout)]
    assert len(swings) == 4 and swings[-1] > 50 * swings[1] and swings[-1] > 30.0
    ratio = float(re.search(r"= ([\d.]+) x speed\n", proc.stdout.split("last")[1]).group(1))
    assert 0.4 < ratio < 0.55
    assert (tmp_path / "whip.png").stat().st_size > 10_000
