"""Speed as a degree of freedom (rotorkit.elements.drive) against closed forms and balance laws.

The reference rotor is a Jeffcott rotor (disk of mass m, polar inertia
``J = m R^2 / 2``, eccentricity e, on an isotropic support k, c). With the
spin a coordinate, ``phi = Omega_0 t + spin`` and ``Omega = Omega_0 + spin'``:

- a very large polar inertia and a constant torque equal to the losses at
  ``Omega_0`` keep the speed at ``Omega_0``: the lateral motion is the
  constant-speed rotor's (symbolically, and in a simulation);
- without unbalance the spin equation is linear and has closed forms: a
  motor curve ``T = T_0 (1 - Omega / Omega_s)`` with drag ``b`` gives
  ``Omega(t) = Omega_inf (1 - exp(-t / tau))``,
  ``Omega_inf = T_0 / (T_0 / Omega_s + b)``, ``tau = J / (T_0 / Omega_s + b)``;
  a PI controller drives the speed to its target and holds the integral
  state at ``b Omega_ref / k_i`` (integral action against a drag);
- the physical energy ``E = m |v_G|^2 / 2 + J Omega^2 / 2 + k r^2 / 2`` changes
  by the drive's work ``int T Omega dt`` less the dissipated
  ``int c |r'|^2 + b Omega^2 + w |Omega|^3 dt``, computed here by hand on the samples;
- the Sommerfeld effect: a drive of limited torque on an unbalanced rotor
  stays captured just below the critical speed (although its torque would
  carry the unloaded rotor to twice it); a larger torque passes it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import cumulative_trapezoid

import rotorkit as rk
from rotorkit.analysis.energy import energy_balance

MASS, RADIUS, STIFFNESS, DAMPING = 2.0, 0.1, 2.0e4, 8.0  # wn = 100 rad/s, zeta = 0.02
J_DISK = MASS * RADIUS**2 / 2
WN = math.sqrt(STIFFNESS / MASS)


def jeffcott(speed, *, eccentricity=1e-4, phase=0.3):
    return rk.Model([
        rk.Rotor(name="R", stations=(1,), speed=speed),
        rk.Disk(station=1, mass=MASS, radius=RADIUS, eccentricity=eccentricity, phase=phase),
        rk.ElasticSupport(station=1, stiffness=STIFFNESS, damping=DAMPING),
    ])


def P(name):
    return sp.Symbol(name, real=True)


# ---------------------------------------------------------------------------
# the limit of a very large inertia: a constant-speed rotor
# ---------------------------------------------------------------------------

OMEGA0, DRAG, WINDAGE = 150.0, 2e-3, 1e-5
BALANCE = DRAG * OMEGA0 + WINDAGE * OMEGA0**2  # the loss torque at OMEGA0


def heavy_drive():
    return rk.Drive.constant(torque=BALANCE, initial_speed=OMEGA0, polar_inertia=1e7, drag=DRAG, windage=WINDAGE)


def test_spin_coordinate_and_parameters():
    model = jeffcott(heavy_drive())
    assert model.coordinate_names == ("x1", "y1", "spin1")
    assert set(model.parameters) >= {"R_speed_initial", "R_speed_inertia", "R_speed_drag", "R_speed_windage",
                                     "R_speed_torque"}
    assert model.parameter_units["R_speed_torque"] == "N*m"
    changed = model.with_values(R_speed_torque="3 N*m")
    assert changed.parameters["R_speed_torque"] == 3.0 and changed.structure_key == model.structure_key


def test_large_inertia_balanced_torque_gives_the_constant_speed_equations():
    ref = jeffcott(OMEGA0).equations()
    eom = jeffcott(heavy_drive()).equations()
    x, y, spin = eom.coordinates
    at_rest = {spin: 0, eom.speeds[2]: 0, P("R_speed_initial"): P("R_speed")}
    for i in range(2):
        assert sp.simplify(eom.forcing[i].xreplace(at_rest) - ref.forcing[i]) == 0
        assert eom.mass_matrix[i, i] == ref.mass_matrix[i, i]
    # the spin equation: inertia J + J_disk + m e^2, torque minus losses
    m, e = P("disk1_mass"), P("disk1_eccentricity")
    assert sp.simplify(eom.mass_matrix[2, 2] - (P("R_speed_inertia") + m * P("disk1_radius") ** 2 / 2 + m * e**2)) == 0


def test_large_inertia_balanced_torque_runs_like_the_constant_speed_rotor():
    t_span, y0 = (0.0, 0.4), dict(x1=1e-4)
    ref_sys = jeffcott(OMEGA0).compile()
    ref = rk.simulate(ref_sys, t_span, y0=ref_sys.initial_state(**y0), rtol=1e-10, atol=1e-14, sample_rate=2000)
    sys = jeffcott(heavy_drive()).compile()
    run = rk.simulate(sys, t_span, y0=sys.initial_state(**y0), rtol=1e-10, atol=1e-14, sample_rate=2000)
    assert np.max(np.abs(run["spin1_dot"])) < 1e-8  # the speed holds at OMEGA0
    for name in ("x1", "y1"):
        assert np.max(np.abs(run[name] - ref[name])) < 1e-6 * np.max(np.abs(ref[name]))


def test_geared_rotor_adds_ratio_squared_inertia_and_rub_torque_reaches_the_spin():
    gamma, j_hp, mu, r_rub = 2.0, 0.03, 0.2, 0.05
    model = rk.Model([
        rk.Rotor(name="LP", stations=(1,), speed=rk.Drive.constant(torque=1.0, initial_speed=10.0, polar_inertia=0.1)),
        rk.Rotor(name="HP", stations=(2,), speed_ratio=gamma, reference="LP"),
        rk.Disk(station=1, mass=MASS, radius=RADIUS),
        rk.Disk(station=2, mass=1.0, polar_inertia=j_hp),
        rk.ElasticSupport(station=1, stiffness=STIFFNESS), rk.ElasticSupport(station=2, stiffness=STIFFNESS),
        rk.RubStator(station=2, clearance=1e-4, contact_stiffness=1e6, friction_coefficient=mu, contact_radius=r_rub),
    ])
    eom = model.equations()
    values = {P(n): v for n, v in model.parameters.items()}
    spin = eom.coordinates.index(P("spin1"))
    # J = drive + LP disk + gamma^2 HP disk (no unbalance)
    assert float(eom.mass_matrix[spin, spin].xreplace(values)) == pytest.approx(0.1 + J_DISK + gamma**2 * j_hp)
    # the HP rub's friction torque -mu N R, geared: gamma times it on the LP spin (x2 = 3e-4: N = k_r 2e-4)
    load = eom.forces["rub2"][spin].xreplace(values).xreplace({P("x2"): 3e-4, P("y2"): 0.0})
    from rotorkit.symbolic.functions import ramp

    load = load.replace(ramp, lambda x: sp.Max(x, 0))
    assert float(load) == pytest.approx(-gamma * mu * r_rub * 1e6 * 2e-4)


def test_driven_beam_rotor_equals_whole_system_lagranges_method():
    """Gyroscopic beam sections and a tilting disk on a driven rotor: every spin coupling of T, derived in full."""
    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

    steel = rk.elements.Material.steel()
    model = rk.Model([
        rk.Rotor(name="R", stations=(1, 2), speed=rk.Drive.constant(torque=0.0, initial_speed=100.0,
                                                                    polar_inertia=0.01)),
        rk.elements.BeamSegment(start=1, end=2, length=0.6, outer_diameter=0.04, material=steel, elements=1),
        rk.Disk.from_geometry(station=2, width=0.02, outer_diameter=0.2, material=steel, eccentricity=1e-4),
        rk.ElasticSupport(station=1, stiffness=1e6), rk.ElasticSupport(station=2, stiffness=8e5),
    ])
    eom = model.equations()
    assert eom.n == 9 and P("spin1") in eom.coordinates
    # numbers (exact rationals) for everything; the drive's torque and losses are 0, so the loads vanish
    numbers = {p: sp.nsimplify(model.parameters[str(p)], rational=True) for p in eom.parameters}
    assert all(v.xreplace(numbers) == 0 for v in eom.loads)
    qt = [dynamicsymbols(str(q)) for q in eom.coordinates]
    to_t = {**dict(zip(eom.coordinates, qt)), **{u: sp.diff(q, dynamicsymbols._t) for u, q in zip(eom.speeds, qt)}}
    lagrangian = (eom.kinetic - eom.potential).xreplace(numbers).subs(eom.t, dynamicsymbols._t).subs(to_t)
    lm = LagrangesMethod(lagrangian, qt)
    lm.form_lagranges_equations()
    back = {v: k for k, v in to_t.items()}
    mass = lm.mass_matrix.subs(back).subs(dynamicsymbols._t, eom.t)
    forcing = lm.forcing.subs(back).subs(dynamicsymbols._t, eom.t)
    spin = eom.coordinates.index(P("spin1"))
    assert any(mass[spin, j] != 0 for j in range(eom.n) if j != spin)  # the spin couples to the motion
    same = lambda a, b: sp.trigsimp(sp.expand(a - b)) == 0  # noqa: E731  (sin^2 + cos^2 of the unbalance)
    assert all(same(mass[i, j], eom.mass_matrix[i, j].xreplace(numbers)) for i in range(eom.n) for j in range(eom.n))
    assert all(same(forcing[i], eom.forcing[i].xreplace(numbers)) for i in range(eom.n))


# ---------------------------------------------------------------------------
# closed forms of the spin equation (no unbalance)
# ---------------------------------------------------------------------------

T0, OMEGA_S, B = 2.0, 400.0, 2e-3


@pytest.mark.parametrize("drive", [
    rk.Drive.motor(speeds=[0.0, OMEGA_S], torques=[T0, 0.0], initial_speed=0.0, drag=B),
    rk.Drive.expression(lambda w, t0, ws: t0 * (1 - w / ws), parameters={"t0": T0, "ws": OMEGA_S},
                        initial_speed=0.0, drag=B),
], ids=["table", "expression"])
def test_motor_curve_run_up_is_the_first_order_closed_form(drive):
    system = jeffcott(drive, eccentricity=0.0).compile()
    result = rk.simulate(system, (0.0, 0.1), rtol=1e-10, atol=1e-12, sample_rate=1000)
    rate = T0 / OMEGA_S + B
    expected = T0 / rate * (1 - np.exp(-result.t * rate / J_DISK))
    assert np.max(np.abs(result["spin1_dot"] - expected)) < 1e-6 * expected[-1]


def test_pi_controller_follows_the_second_order_closed_form_and_holds_the_drag_with_the_integral():
    target, w0, kp, ki = 120.0, 100.0, 0.1, 2.0
    drive = rk.Drive.controller(target=target, proportional=kp, integral=ki, initial_speed=w0, drag=B)
    system = jeffcott(drive, eccentricity=0.0).compile()
    result = rk.simulate(system, (0.0, 3.0), rtol=1e-10, atol=1e-12, sample_rate=200)
    speed = w0 + result["spin1_dot"]
    integral = (target - w0) * result.t - result["spin1"]  # the integral of the speed error
    # E = Omega - Omega_ref: J E'' + (k_p + b) E' + k_i E = b ... differentiated: J E'' + (k_p + b) E' + k_i E = 0,
    # E(0) = w0 - target, J E'(0) = -k_p E(0) - b w0 (z(0) = 0)
    a, wd = (kp + B) / (2 * J_DISK), math.sqrt(ki / J_DISK - ((kp + B) / (2 * J_DISK)) ** 2)
    e0, de0 = w0 - target, (-kp * (w0 - target) - B * w0) / J_DISK
    t = result.t
    expected = target + np.exp(-a * t) * (e0 * np.cos(wd * t) + (de0 + a * e0) / wd * np.sin(wd * t))
    assert np.max(np.abs(speed - expected)) < 1e-6 * target
    assert speed[-1] == pytest.approx(target, rel=1e-5)
    assert integral[-1] == pytest.approx(B * target / ki, rel=1e-4)  # the integral holds the drag torque


# ---------------------------------------------------------------------------
# energy: drive in, dissipation out, with unbalance coupling
# ---------------------------------------------------------------------------


def test_energy_of_drive_unbalance_and_dissipation_balances():
    ecc, phase, w0, torque, drag, windage = 2e-3, 0.3, 60.0, 0.5, 1e-3, 2e-6
    drive = rk.Drive.constant(torque=torque, initial_speed=w0, drag=drag, windage=windage, polar_inertia=0.005)
    model = jeffcott(drive, eccentricity=ecc, phase=phase)
    system = model.compile()
    result = rk.simulate(system, (0.0, 1.0), y0=system.initial_state(x1=1e-3), rtol=1e-11, atol=1e-14,
                         sample_rate=20_000)
    t, x, y, xd, yd = result.t, result["x1"], result["y1"], result["x1_dot"], result["y1_dot"]
    omega = w0 + result["spin1_dot"]
    phi = w0 * t + result["spin1"] + phase
    vx, vy = xd - ecc * omega * np.sin(phi), yd + ecc * omega * np.cos(phi)
    energy = MASS * (vx**2 + vy**2) / 2 + (J_DISK + 0.005) * omega**2 / 2 + STIFFNESS * (x**2 + y**2) / 2
    drive_in = cumulative_trapezoid(torque * omega, t, initial=0.0)
    lost = cumulative_trapezoid(DAMPING * (xd**2 + yd**2) + drag * omega**2 + windage * np.abs(omega) ** 3, t,
                                initial=0.0)
    assert omega[-1] > 1.3 * w0  # the rotor ran up, towards the critical speed
    assert np.max(np.abs(energy - energy[0] - (drive_in - lost))) < 1e-5 * np.max(drive_in)
    assert energy_balance(model, result).relative_residual < 1e-6


# ---------------------------------------------------------------------------
# the Sommerfeld effect
# ---------------------------------------------------------------------------


def test_sommerfeld_effect_capture_below_the_critical_speed_and_passage_with_more_torque():
    drag = 2e-3  # free speeds T / drag: 200 rad/s (2 wn) and 400 rad/s
    model = jeffcott(rk.Drive.constant(torque=0.4, initial_speed=0.0, drag=drag), eccentricity=1e-3)
    system = model.compile()
    captured = rk.simulate(system, (0.0, 6.0), rtol=1e-8, atol=1e-11, sample_rate=100)
    passed = rk.simulate(system.with_parameters(R_speed_torque=0.8), (0.0, 6.0), rtol=1e-8, atol=1e-11,
                         sample_rate=100)
    late = captured.t > 4.0
    assert np.all(captured["spin1_dot"][late] < WN)  # held below the critical speed
    assert np.all(captured["spin1_dot"][late] > 0.9 * WN)  # ... at it: the resonance takes the torque
    assert passed["spin1_dot"][-1] > 2.5 * WN


# ---------------------------------------------------------------------------
# linear analyses: at the frozen initial speed
# ---------------------------------------------------------------------------


def test_linear_analyses_freeze_a_driven_rotor_at_its_initial_speed():
    from rotorkit.analysis.campbell import campbell
    from rotorkit.analysis.linear_matrices import frozen_speed_model
    from rotorkit.analysis.modes import natural_frequencies

    model = jeffcott(rk.Drive.constant(torque=0.4, initial_speed=50.0, drag=B))
    frozen = frozen_speed_model(model)
    assert frozen.coordinate_names == ("x1", "y1") and frozen.parameters["R_speed"] == 50.0
    table = campbell(model, speeds=[0.0, 100.0], n_modes=2)
    # Jeffcott: the damped frequency sqrt(wn^2 - (c / 2m)^2) at every speed
    assert np.allclose(table.frequencies, math.sqrt(WN**2 - (DAMPING / (2 * MASS)) ** 2), rtol=1e-9)
    with pytest.raises(rk.ParameterError, match="degree of freedom.*frozen_speed_model"):
        natural_frequencies(model.compile())


# ---------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("make, match", [
    (lambda: rk.Drive.motor(speeds=[0.0, 300.0, 200.0], torques=[1.0, 0.5, 0.0]), "not strictly increasing"),
    (lambda: rk.Drive.motor(speeds=[0.0, 300.0], torques=[1.0]), "one value per speeds entry"),
    (lambda: rk.Drive.constant(torque=None), "torque is required"),
    (lambda: rk.Drive.constant(torque=1.0, polar_inertia=-1.0), "polar_inertia"),
    (lambda: rk.Drive.constant(torque=1.0, drag="1 m"), "drag"),
    (lambda: rk.Drive.constant(torque="2 N"), "torque"),
    (lambda: rk.Drive.controller(target=None, proportional=1.0), "target is required"),
    (lambda: rk.Drive.controller(target=100.0, proportional=-1.0), "proportional"),
    (lambda: rk.Drive.expression(lambda w: w * q), "failed"),  # noqa: F821
    (lambda: rk.Drive.expression(lambda w, a: a * w, parameters={"initial": 1.0}), "parameter name"),
    (lambda: rk.Drive(kind="turbine"), "expected one of"),
])
def test_bad_drive_input_is_a_named_error(make, match):
    with pytest.raises((rk.ParameterError, rk.UnitError), match=match):
        make()


def test_a_driven_rotor_without_polar_inertia_is_a_named_error():
    with pytest.raises(rk.TopologyError, match="nothing gives it polar inertia"):
        rk.Model([rk.Rotor(name="R", stations=(1,), speed=rk.Drive.constant(torque=1.0)),
                  rk.LumpedMass(station=1, mass=1.0), rk.ElasticSupport(station=1, stiffness=1e4)])


def test_drive_round_trips_through_a_model_file(tmp_path):
    model = jeffcott(rk.Drive.motor(speeds=[0.0, 300.0], torques=[2.0, 0.5], initial_speed=10.0, drag=1e-3))
    back = rk.load_model(model.save(tmp_path / "driven.toml"))
    assert back.parameters == model.parameters and back.structure_key == model.structure_key
