"""Inter-shaft rub (rotorkit.elements.intershaft_rub) against a rub stator and the balance laws.

- With the outer station not spinning and held still, the loads on the inner
  station are a :class:`RubStator`'s (symbolically, after renaming the
  parameters and putting the outer station at the origin) and a simulation
  with a very stiff outer station follows the stator run.
- Momentum: the contact forces on the two stations are equal and opposite
  at every sample (evaluated from the derived loads on the simulated states).
- Energy: with both spins free (speed degrees of freedom, no drive torque)
  the total energy falls by exactly the friction's ``mu N |sliding speed|``
  plus the damping, computed by hand on the samples; the energy balance of
  :mod:`rotorkit.analysis.energy` closes, and
  the work of the rub's loads equals, independently, the loss of the contact
  spring energy ``k_r max(r - delta, 0)^2 / 2`` minus the friction power
  ``mu N s (t . d' + R alpha_i' - (R + delta) alpha_o')`` on the sampled
  motion (the lever arms of the two torques and the tangent of the force).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

import rotorkit as rk
from rotorkit.analysis.energy import energy_balance
from rotorkit.context import Context
from rotorkit.symbolic.functions import contact_ratio, hypot, ramp, step
from rotorkit.symbolic.lagrange import Symbols

RADIUS, CLEARANCE, KR, MU = 0.05, 1e-4, 5e6, 0.15
SPEED = 300.0


def inner_rotor(rub=None, *, speed=SPEED, torsion=True):
    """Rotor R: drive station 0 and a disk at 1 (torsion, unbalance) on a flexible shaft."""
    return [
        rk.Rotor(name="R", stations=(0, 1), speed=speed),
        rk.LumpedMass(station=0, mass=1.0),
        rk.ElasticSupport(station=0, stiffness=1e7, damping=50.0),
        rk.Disk(station=1, mass=4.0, radius=RADIUS, eccentricity=2e-4, torsion=torsion),
        rk.ShaftSegment(start=0, end=1, length=0.3, bending_stiffness=2e5, bending_damping=5.0,
                        **(dict(torsional_stiffness=2e3, torsional_damping=0.05) if torsion else {})),
    ]


def outer_rotor(*, speed=0.0, stiffness=4e5, mass=3.0, torsion=False):
    """Rotor S: one station 9 on its own support (a disk with torsion if asked)."""
    parts = [rk.Rotor(name="S", stations=(8, 9) if torsion else (9,), speed=speed),
             rk.ElasticSupport(station=9, stiffness=stiffness, damping=20.0)]
    if torsion:
        parts += [rk.LumpedMass(station=8, mass=1.0), rk.ElasticSupport(station=8, stiffness=1e7),
                  rk.Disk(station=9, mass=mass, radius=0.08, torsion=True),
                  rk.ShaftSegment(start=8, end=9, length=0.2, bending_stiffness=1e6, torsional_stiffness=3e3,
                                  torsional_damping=0.05)]
    else:
        parts.append(rk.LumpedMass(station=9, mass=mass))
    return parts


def rub(**kw):
    values = dict(inner_station=1, outer_station=9, clearance=CLEARANCE, contact_stiffness=KR,
                  friction_coefficient=MU, contact_radius=RADIUS)
    values.update(kw)
    return rk.IntershaftRub(**values)


def stator():
    return rk.RubStator(station=1, clearance=CLEARANCE, contact_stiffness=KR, friction_coefficient=MU,
                        contact_radius=RADIUS)


def element_loads(model, label):
    ctx = Context(model, Symbols(model))
    element = next(e for e in model.elements if e.label() == label)
    return ctx, {q: sp.sympify(v) for q, v in element.contribute(ctx.bind(element)).loads.items()}


def numeric(expr, symbols):
    """A numpy function of ``symbols`` from an expression with rotorkit's piecewise functions."""
    expr = expr.replace(contact_ratio, lambda r, d: sp.Max(r - d, 0) / r)
    expr = expr.replace(ramp, lambda x: sp.Max(x, 0)).replace(hypot, lambda a, b: sp.sqrt(a**2 + b**2))
    expr = expr.replace(step, lambda x: sp.Piecewise((1, x > 0), (0, True)))
    return sp.lambdify(symbols, expr, "numpy")


# ---------------------------------------------------------------------------
# the outer station held still: a rub stator
# ---------------------------------------------------------------------------


def test_loads_equal_a_rub_stators_symbolically_when_the_outer_station_is_still():
    _, ref = element_loads(rk.Model(inner_rotor() + [stator()]), "rub1")
    ctx, mine = element_loads(rk.Model(inner_rotor() + outer_rotor() + [rub()]), "intershaftrub1_9")
    x1, y1, a1 = (ctx.coord(1, ax)[0] for ax in ("x", "y", "alpha"))
    x9, y9 = ctx.coord(9, "x")[0], ctx.coord(9, "y")[0]
    P = lambda n: sp.Symbol(n, real=True)  # noqa: E731
    rename = {P(f"intershaftrub1_9_{f}"): P(f"rub1_{f}") for f in
              ("clearance", "contact_stiffness", "friction_coefficient", "contact_radius")}
    still = {x9: 0, y9: 0, P("S_speed"): 0}
    assert set(mine) == {x1, y1, a1, x9, y9} and set(ref) == {x1, y1, a1}
    for q in (x1, y1, a1):
        got = mine[q].xreplace(still).xreplace(rename)
        (s,) = got.atoms(step)  # the friction sign: step(R Omega) = 1 for Omega > 0
        assert s.args[0] == P("rub1_contact_radius") * P("R_speed")
        assert sp.simplify(got.xreplace({s: 1}) - ref[q]) == 0


def test_friction_follows_the_sliding_speed_of_co_and_counter_rotating_spools():
    ctx, loads = element_loads(rk.Model(inner_rotor() + outer_rotor(speed=100.0) + [rub()]), "intershaftrub1_9")
    x1, y1, x9, y9 = ctx.coord(1, "x")[0], ctx.coord(1, "y")[0], ctx.coord(9, "x")[0], ctx.coord(9, "y")[0]
    a1 = ctx.coord(1, "alpha")[0]
    params = ctx.model.parameters
    syms = [x1, y1, x9, y9, sp.Symbol("S_speed", real=True)]
    rest = {sp.Symbol(n, real=True): v for n, v in params.items() if n != "S_speed"}
    fy1 = numeric(loads[y1].xreplace(rest), syms)
    m1 = numeric(loads[a1].xreplace(rest), syms)
    # inner disk pushed 2e-4 along +x past the outer centre: penetration 1e-4, N = k_r 1e-4
    N = KR * 1e-4
    # sliding v = 300 R - Omega_o (R + delta): positive below Omega_o = 300 R / (R + delta), negative above
    for omega_o, sign in ((0.0, 1), (100.0, 1), (-300.0, 1), (400.0, -1)):
        assert fy1(2e-4, 0.0, 0.0, 0.0, omega_o) == pytest.approx(-sign * MU * N, rel=1e-12)
        assert m1(2e-4, 0.0, 0.0, 0.0, omega_o) == pytest.approx(-sign * MU * N * RADIUS, rel=1e-12)
    # out of contact: nothing
    assert fy1(5e-5, 0.0, 0.0, 0.0, 0.0) == 0.0


def test_simulation_equals_a_rub_stator_run_with_a_stiff_still_outer_station():
    t_span, y0 = (0.0, 0.05), dict(x1=3e-4, y1_dot=0.05)
    ref_sys = rk.Model(inner_rotor() + [stator()]).compile()
    ref = rk.simulate(ref_sys, t_span, y0=ref_sys.initial_state(**y0), rtol=1e-9, atol=1e-13, sample_rate=4000)
    # a 1e6 kg outer station on 1e14 N/m: moves ~1e-10 m under the contact force
    sys = rk.Model(inner_rotor() + outer_rotor(stiffness=1e14, mass=1e6) + [rub()]).compile()
    run = rk.simulate(sys, t_span, y0=sys.initial_state(**y0), rtol=1e-9, atol=1e-13, sample_rate=4000)
    assert np.max(np.hypot(ref["x1"], ref["y1"])) > CLEARANCE * 1.5  # it does rub
    assert np.max(np.abs(run["x9"])) < 1e-3 * CLEARANCE
    for name in ("x1", "y1", "alpha1"):
        scale = np.max(np.abs(ref[name]))
        assert np.max(np.abs(run[name] - ref[name])) < 1e-4 * scale, name


# ---------------------------------------------------------------------------
# momentum and energy
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def two_spool_run():
    """Counter-rotating spools, both with torsion, rubbing: inner whirl started into the contact."""
    model = rk.Model(inner_rotor(speed=SPEED) + outer_rotor(speed=-150.0, stiffness=6e5, mass=3.0, torsion=True)
                     + [rub()])
    system = model.compile()
    result = rk.simulate(system, (0.0, 0.08), y0=system.initial_state(x1=2.5e-4, y1_dot=0.06), rtol=1e-10,
                         atol=1e-14, sample_rate=40_000)
    return model, result


def test_contact_forces_are_equal_and_opposite_at_every_sample(two_spool_run):
    model, result = two_spool_run
    ctx, loads = element_loads(model, "intershaftrub1_9")
    coords = [ctx.coord(s, a)[0] for s, a in ((1, "x"), (1, "y"), (9, "x"), (9, "y"))]
    rest = {sp.Symbol(n, real=True): v for n, v in model.parameters.items()}
    states = [result[str(q)] for q in coords]
    f = {q: numeric(loads[q].xreplace(rest), coords)(*states) for q in coords}
    fx1, fy1, fx9, fy9 = (np.broadcast_to(f[q], result.t.shape) for q in coords)
    assert np.max(np.hypot(fx1, fy1)) > 10.0  # in contact for a part of the run
    assert np.max(np.abs(fx1 + fx9)) == 0.0 and np.max(np.abs(fy1 + fy9)) == 0.0


def test_energy_balance_closes_and_rub_work_is_contact_energy_less_friction_loss(two_spool_run):
    model, result = two_spool_run
    balance = energy_balance(model, result)
    assert balance.relative_residual < 1e-6
    t = result.t
    dx, dy = result["x1"] - result["x9"], result["y1"] - result["y9"]
    vx, vy = result["x1_dot"] - result["x9_dot"], result["y1_dot"] - result["y9_dot"]
    r = np.hypot(dx, dy)
    pen = np.maximum(r - CLEARANCE, 0.0)
    N = KR * pen
    spring = KR * pen**2 / 2
    v_spin = SPEED * RADIUS - (-150.0) * (RADIUS + CLEARANCE)  # > 0: s = +1
    tangential = (-dy * vx + dx * vy) / np.where(r > 0, r, 1.0)  # t . d'
    friction = MU * N * (tangential + RADIUS * result["alpha1_dot"] - (RADIUS + CLEARANCE) * result["alpha9_dot"])
    assert v_spin > 0
    from scipy.integrate import cumulative_trapezoid

    loss = cumulative_trapezoid(friction, t, initial=0.0)
    expected = -(spring - spring[0]) - loss
    work = balance.work["intershaftrub1_9"]
    assert np.max(spring) > 1e-5  # the contact stores energy at times
    assert np.max(np.abs(work - expected)) < 2e-3 * np.max(np.abs(expected))


def test_friction_work_is_dissipated_between_two_free_spinning_spools():
    """Both spins free (Drive with no torque): the energy lost is the friction's mu N |sliding| and the damping."""
    j_in, j_out, w_in, w_out = 0.5, 1.0, 300.0, -200.0  # counter-rotating; inertias that keep them sliding
    model = rk.Model([
        rk.Rotor(name="R", stations=(1,), speed=rk.Drive.constant(torque=0.0, initial_speed=w_in, polar_inertia=j_in)),
        rk.Rotor(name="S", stations=(9,), speed=rk.Drive.constant(torque=0.0, initial_speed=w_out,
                                                                  polar_inertia=j_out)),
        rk.LumpedMass(station=1, mass=4.0), rk.ElasticSupport(station=1, stiffness=2e5, damping=5.0),
        rk.LumpedMass(station=9, mass=3.0), rk.ElasticSupport(station=9, stiffness=4e5, damping=5.0),
        rub(),
    ])
    system = model.compile()
    # 15 ms: later the friction drives a backward whirl that grows (dry-friction whip)
    result = rk.simulate(system, (0.0, 0.015), y0=system.initial_state(x1=3e-4, y1_dot=0.05), rtol=1e-11,
                         atol=1e-14, sample_rate=200_000)
    t = result.t
    om_in, om_out = w_in + result["spin1_dot"], w_out + result["spin9_dot"]
    dx, dy = result["x1"] - result["x9"], result["y1"] - result["y9"]
    vx, vy = result["x1_dot"] - result["x9_dot"], result["y1_dot"] - result["y9_dot"]
    r = np.hypot(dx, dy)
    pen = np.maximum(r - CLEARANCE, 0.0)
    energy = (4.0 * (result["x1_dot"] ** 2 + result["y1_dot"] ** 2)
              + 3.0 * (result["x9_dot"] ** 2 + result["y9_dot"] ** 2)
              + j_in * om_in**2 + j_out * om_out**2 + 2e5 * (result["x1"] ** 2 + result["y1"] ** 2)
              + 4e5 * (result["x9"] ** 2 + result["y9"] ** 2) + KR * pen**2) / 2
    sliding = om_in * RADIUS - om_out * (RADIUS + CLEARANCE)  # > 0 throughout: s = +1
    tangential = (-dy * vx + dx * vy) / np.where(r > 0, r, 1.0)
    friction = MU * KR * pen * (sliding + tangential)  # mu N times the sliding speed of the material points
    damping = 5.0 * (result["x1_dot"] ** 2 + result["y1_dot"] ** 2 + result["x9_dot"] ** 2 + result["y9_dot"] ** 2)
    from scipy.integrate import cumulative_trapezoid

    lost = cumulative_trapezoid(friction + damping, t, initial=0.0)
    assert np.all(sliding > 0) and np.max(pen) > 0
    assert lost[-1] > 1.0  # J: the friction worked
    assert np.max(np.abs(energy - energy[0] + lost)) < 1e-5 * lost[-1]
    # the friction torques slow both spools (the outer one turns the other way: its speed rises towards 0)
    assert om_in[-1] < w_in and om_out[-1] > w_out


# ---------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("kw, match", [
    (dict(outer_station=1), "both 1"),
    (dict(clearance=-1e-4), "clearance"),
    (dict(contact_stiffness=None), "contact_stiffness"),
    (dict(contact_radius=None), "contact_radius is required"),
    (dict(contact_radius="2 kg"), "contact_radius"),
    (dict(friction_coefficient=-0.1), "friction_coefficient"),
])
def test_bad_parameters_are_named(kw, match):
    with pytest.raises((rk.ParameterError, rk.UnitError), match=match):
        rub(**kw)


def test_two_stations_of_one_rotor_is_a_named_error():
    with pytest.raises(rk.TopologyError, match="both on rotor 'R'.*two\\s+different rotors"):
        rk.Model(inner_rotor() + [rub(outer_station=0)])
