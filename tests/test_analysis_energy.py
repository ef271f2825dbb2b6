"""The energy balance (rotorkit.analysis.energy) against closed-form results.

A Jeffcott rotor (disk of mass m on an isotropic support k, c) has exact
answers: the Jacobi integral of a free oscillation is ``m v^2/2 + k x^2/2``
and stays constant without damping; with damping it follows the analytic
free decay and the dissipated work is exactly the energy lost; in the steady
unbalance whirl of radius ``r`` the drive puts in ``c Omega^2 r^2`` at every
instant. A frictionless rub stator is a conservative spring ``k_r
max(r - delta, 0)^2 / 2``; with friction the tangential force ``-mu N``
takes energy out of a forward whirl. The AL-31F preset checks that the
residual follows the solver tolerance.
"""

from __future__ import annotations

import doctest
import math

import numpy as np
import pytest
import sympy as sp

import rotorkit as rk
from rotorkit.analysis import energy
from rotorkit.analysis.energy import EnergyBalance, energy_balance, energy_terms

MASS, STIFFNESS = 2.0, 2.0e4  # kg, N/m
WN = math.sqrt(STIFFNESS / MASS)  # 100 rad/s


def jeffcott(*, speed=0.0, eccentricity=0.0, damping=0.0, rub=None, maneuver=None):
    """Jeffcott rotor at station 1 (no torsion), optionally with a rub stator and a manoeuvre."""
    elements = [
        rk.Rotor(name="R", stations=(1,), speed=speed),
        rk.Disk(station=1, mass=MASS, radius=0.1, eccentricity=eccentricity),
        rk.ElasticSupport(station=1, stiffness=STIFFNESS, damping=damping),
    ]
    if rub is not None:
        elements.append(rk.RubStator(station=1, **rub))
    if maneuver is not None:
        elements.append(maneuver)
    return rk.Model(elements, name="jeffcott")


def run(model, t_span, *, rtol, y0=None, sample_rate=20_000.0, atol_scale=1e-6):
    system = model.compile()
    y0 = None if y0 is None else system.initial_state(**y0)
    return rk.simulate(system, t_span, y0=y0, rtol=rtol, atol=atol_scale * rtol, sample_rate=sample_rate)


# ---------------------------------------------------------------------------
# symbolic terms
# ---------------------------------------------------------------------------


def test_terms_of_a_jeffcott_with_unbalance_are_the_textbook_ones():
    terms = energy_terms(jeffcott(speed=150.0, eccentricity=1e-4, damping=8.0))
    m, k, c, e, w, phase = (sp.Symbol(n, real=True) for n in (
        "disk1_mass", "support1_stiffness", "support1_damping", "disk1_eccentricity", "R_speed", "disk1_phase"))
    x, y = terms.coordinates
    xd, yd = terms.speeds
    phi = w * terms.t + phase
    # h = m v^2/2 + k x^2/2 up to a constant (the unbalance's own m e^2 Omega^2 / 2)
    rest = sp.simplify(terms.jacobi - (m * (xd**2 + yd**2) / 2 + k * (x**2 + y**2) / 2))
    assert not rest.free_symbols & {x, y, xd, yd, terms.t}
    # the drive's power is the unbalance force m e Omega^2 (cos, sin)(phi) times the velocity
    assert sp.simplify(terms.power["drive"] - m * e * w**2 * (xd * sp.cos(phi) + yd * sp.sin(phi))) == 0
    assert sp.simplify(terms.power["damping"] + c * (xd**2 + yd**2)) == 0
    assert terms.names == ("drive", "damping")
    assert sp.simplify(terms.motion - m * (xd**2 + yd**2) / 2) == 0


def test_load_channels_add_up_to_the_equations_loads():
    """One channel per element with loads; together they are eom.loads . q'."""
    model = rk.preset("al31f")
    terms, eom = energy_terms(model), model.equations()
    assert set(terms.names) == {"drive", "damping", "bearing4_7", "rub2", "maneuver"}
    loads = [terms.power[n] for n in terms.names if n not in ("drive", "damping")]
    total = sum((eom.loads[i] * u for i, u in enumerate(eom.speeds)), sp.S.Zero)
    args = [eom.t, *eom.coordinates, *eom.speeds, *eom.parameters]
    f = sp.lambdify(args, [sum(loads, sp.S.Zero), total],
                    modules=[{"ramp": lambda a: max(a, 0.0), "window": lambda t, a, b: float(a <= t < b),
                              "hypot": math.hypot,
                              "contact_ratio": lambda r, d: max(r - d, 0.0) / r if r > 0 else float(d == 0)},
                             "math"])
    rng = np.random.default_rng(1)
    values = model.parameters
    p = [values[str(s)] for s in eom.parameters]
    for _ in range(20):
        q = rng.normal(scale=2e-4, size=eom.n)
        u = rng.normal(scale=0.3, size=eom.n)
        a, b = f(rng.uniform(0, 6), *q, *u, *p)
        assert a == pytest.approx(b, rel=1e-12, abs=1e-12)


def test_numeric_powers_match_the_generated_equations():
    """The numpy translation of the contact functions agrees with the compiled right-hand side,
    including r = 0, r = clearance and permanent contact (clearance 0)."""
    for clearance in (0.0, 1e-4):
        model = jeffcott(rub=dict(clearance=clearance, contact_stiffness=1e6, friction_coefficient=0.3))
        system = model.compile()
        states = [(0.0, 0.0, 0.3, -0.2), (1e-4, 0.0, 0.1, 0.2), (0.6e-4, 0.8e-4, -0.1, 0.3),
                  (2e-4, -1e-4, 0.05, 0.0), (-3e-5, 1e-5, 0.2, 0.1)]
        y = np.array(states, dtype=float).T
        result = rk.Result(t=np.array([0.0, 0.1, 0.2, 0.3, 0.4]), y=y, state_names=system.state_names,
                           parameters=system.parameters)
        balance = energy_balance(model, result)
        for k, state in enumerate(states):
            acc = system.rhs(0.0, np.array(state))[2:]
            force = MASS * acc + STIFFNESS * np.array(state[:2])  # what is left is the rub force
            assert balance.power_in["rub1"][k] == pytest.approx(force @ np.array(state[2:]), rel=1e-12, abs=1e-15)


# ---------------------------------------------------------------------------
# free oscillation
# ---------------------------------------------------------------------------


def test_undamped_free_oscillation_conserves_h():
    x0, v0 = 1e-3, 0.05
    h_exact = STIFFNESS * x0**2 / 2 + MASS * v0**2 / 2
    residuals = {}
    for rtol in (1e-6, 1e-10):
        model = jeffcott()
        result = run(model, (0.0, 1.0), rtol=rtol, y0=dict(x1=x0, y1_dot=v0))
        balance = energy_balance(model, result)
        np.testing.assert_allclose(balance.h, h_exact, rtol=30 * rtol)
        assert set(balance.power_in) == {"drive", "damping"}
        assert not np.any(balance.power_in["drive"]) and not np.any(balance.power_in["damping"])
        # nothing flows, so the scale is the largest energy in motion: x and y oscillate in
        # quadrature, so max m v^2 / 2 = max(k x0^2 / 2, m v0^2 / 2)
        assert balance.scale == pytest.approx(max(STIFFNESS * x0**2, MASS * v0**2) / 2, rel=1e-6)
        assert balance.relative_residual < 30 * rtol
        residuals[rtol] = balance.relative_residual
    assert residuals[1e-10] < residuals[1e-6] / 1000


@pytest.mark.parametrize("zeta", [0.02, 0.1])
def test_damped_free_decay_dissipates_exactly_the_energy_lost(zeta):
    c = 2 * zeta * math.sqrt(STIFFNESS * MASS)
    model = jeffcott(damping=c)
    x0 = 1e-3
    result = run(model, (0.0, 1.0), rtol=1e-10, y0=dict(x1=x0))
    balance = energy_balance(model, result)
    # analytic free decay: x = x0 exp(-s t) (cos wd t + s/wd sin wd t)
    s, wd, t = zeta * WN, WN * math.sqrt(1 - zeta**2), balance.t
    x = x0 * np.exp(-s * t) * (np.cos(wd * t) + s / wd * np.sin(wd * t))
    v = -x0 * np.exp(-s * t) * (WN**2 / wd) * np.sin(wd * t)
    h_exact = STIFFNESS * x**2 / 2 + MASS * v**2 / 2
    np.testing.assert_allclose(balance.h, h_exact, rtol=1e-7, atol=1e-9 * h_exact[0])
    assert np.all(balance.dissipated >= 0.0)
    np.testing.assert_allclose(balance.dissipated, c * v**2, rtol=1e-6, atol=1e-9 * c * v.max() ** 2)
    lost = balance.h[0] - balance.h
    np.testing.assert_allclose(-balance.work["damping"], lost, rtol=0, atol=1e-9 * balance.h[0])
    assert lost[-1] > 0.5 * balance.h[0]  # most of the energy is gone by 1 s
    assert balance.relative_residual < 1e-9


# ---------------------------------------------------------------------------
# forced: unbalance at constant speed
# ---------------------------------------------------------------------------


def test_steady_unbalance_whirl_drive_power_is_c_omega2_r2():
    zeta, speed, e = 0.05, 150.0, 1e-4
    c = 2 * zeta * math.sqrt(STIFFNESS * MASS)
    ratio = speed / WN
    radius = e * ratio**2 / math.hypot(1 - ratio**2, 2 * zeta * ratio)
    lag = math.atan2(2 * zeta * ratio, 1 - ratio**2)
    model = jeffcott(speed=speed, eccentricity=e, damping=c)
    # start on the steady orbit x + i y = r exp(i (Omega t - lag)): no transient
    y0 = dict(x1=radius * math.cos(-lag), y1=radius * math.sin(-lag),
              x1_dot=-radius * speed * math.sin(-lag), y1_dot=radius * speed * math.cos(-lag))
    result = run(model, (0.0, 0.5), rtol=1e-10, y0=y0)
    balance = energy_balance(model, result)
    steady = c * speed**2 * radius**2  # W
    np.testing.assert_allclose(balance.power_in["drive"], steady, rtol=1e-6)
    np.testing.assert_allclose(balance.dissipated, steady, rtol=1e-6)
    np.testing.assert_allclose(balance.work["drive"], steady * balance.t, rtol=1e-6, atol=1e-9 * steady)
    np.testing.assert_allclose(balance.h - balance.h[0], 0.0, atol=1e-8 * steady * 0.5)
    assert balance.relative_residual < 1e-9


def test_unbalance_from_rest_the_balance_closes_with_drive_work():
    model = jeffcott(speed=150.0, eccentricity=1e-4, damping=8.0)
    out = {}
    for rtol in (1e-6, 1e-9):
        balance = energy_balance(model, run(model, (0.0, 1.0), rtol=rtol))
        assert balance.work["drive"][-1] > 0.0  # the drive has fed the whirl
        assert balance.work["damping"][-1] < 0.0
        assert balance.relative_residual < 10 * rtol
        assert balance.relative_quadrature_error < rtol
        out[rtol] = balance
    # the works agree between tolerances to the coarse one's accuracy
    assert out[1e-6].work["drive"][-1] == pytest.approx(out[1e-9].work["drive"][-1], rel=1e-4)
    assert out[1e-9].relative_residual < out[1e-6].relative_residual / 10


# ---------------------------------------------------------------------------
# rub stator
# ---------------------------------------------------------------------------

RUB = dict(clearance=1.5e-4, contact_stiffness=2e5)


def contact_energy(result, stiffness=RUB["contact_stiffness"], clearance=RUB["clearance"]):
    r = np.hypot(result["x1"], result["y1"])
    return 0.5 * stiffness * np.maximum(r - clearance, 0.0) ** 2


def test_frictionless_rub_is_a_conservative_spring():
    model = jeffcott(speed=150.0, eccentricity=1e-4, damping=40.0, rub=dict(RUB, friction_coefficient=0.0))
    result = run(model, (0.0, 1.0), rtol=1e-9, sample_rate=50_000.0)
    balance = energy_balance(model, result)
    u = contact_energy(result)
    assert u.max() > 1e-4 * balance.scale  # it does touch
    # the rub's work is minus the change of its contact energy, at every sample
    np.testing.assert_allclose(balance.work["rub1"], -(u - u[0]), rtol=0, atol=1e-7 * u.max())
    assert balance.relative_residual < 1e-8


@pytest.mark.parametrize("t_end", [2.0, 10.0])
def test_the_residual_of_a_bouncing_contact_is_its_true_energy_error_at_any_run_length(t_end):
    # undamped, frictionless, no spin: m v^2/2 + k r^2/2 + the contact energy is exactly constant, so its
    # drift is the true energy error of the run; the relative residual must report it, not divide it by the
    # energy that kept flowing in and out of the contact (which grows with run length)
    model = jeffcott(rub=dict(RUB, friction_coefficient=0.0))
    result = run(model, (0.0, t_end), rtol=1e-5, y0={"x1": 3 * RUB["clearance"], "y1_dot": 0.02},
                 sample_rate=50_000.0)
    balance = energy_balance(model, result)
    energy = 0.5 * MASS * (result["x1_dot"] ** 2 + result["y1_dot"] ** 2) \
        + 0.5 * STIFFNESS * (result["x1"] ** 2 + result["y1"] ** 2) + contact_energy(result)
    true_error = np.max(np.abs(energy - energy[0])) / energy[0]
    assert contact_energy(result).max() > 0.1 * energy[0]  # it bounces hard
    assert true_error > 1e-6  # a loose tolerance: an error worth reporting
    assert 0.5 * true_error < balance.relative_residual < 2.0 * true_error
    assert balance.flow > 10 * balance.scale  # the energy that flowed would have hidden it


def test_friction_takes_energy_out_of_a_forward_whirl():
    mu = 0.1
    model = jeffcott(speed=150.0, eccentricity=1e-4, damping=40.0, rub=dict(RUB, friction_coefficient=mu))
    result = run(model, (0.0, 1.0), rtol=1e-9, sample_rate=50_000.0)
    balance = energy_balance(model, result)
    x, y, xd, yd = (result[n] for n in ("x1", "y1", "x1_dot", "y1_dot"))
    r = np.hypot(x, y)
    assert np.all(x * yd - y * xd >= 0.0)  # forward (counter-clockwise) whirl throughout
    friction_work = balance.work["rub1"] + contact_energy(result) - contact_energy(result)[0]
    # the tangential force is -mu N along the whirl direction: its power -mu N (x y' - y x') / r <= 0
    normal = RUB["contact_stiffness"] * np.maximum(r - RUB["clearance"], 0.0)
    power = -mu * normal * np.divide(x * yd - y * xd, r, out=np.zeros_like(r), where=r > 0)
    assert np.all(power <= 0.0)
    expected = np.concatenate(([0.0], np.cumsum(0.5 * (power[1:] + power[:-1]) * np.diff(result.t))))
    assert friction_work[-1] < -1e-3 * balance.scale
    np.testing.assert_allclose(friction_work, expected, rtol=0, atol=1e-3 * abs(expected[-1]))
    assert np.all(np.diff(friction_work) <= 1e-9 * abs(friction_work[-1]))
    assert balance.relative_residual < 3e-8  # 30 rtol: a second of whirl against the energy of the motion


# ---------------------------------------------------------------------------
# AL-31F: the residual follows the solver tolerance
# ---------------------------------------------------------------------------


def test_al31f_balance_closes_to_a_tolerance_that_follows_rtol():
    """rtol 1e-6 and 1e-9 (atol = 1e-6 rtol): the residual stays below 10 rtol per energy scale
    carried through the channels (as in the hard-case matrix) and shrinks by more than 10. At 400 kHz the quadrature part (its bound |W - W_2h|, dominated by the onsets
    of the Hertzian ball contacts, which are only C1) stays below half the allowed residual."""
    model = rk.preset("al31f")
    system = model.compile()
    out = {}
    for rtol in (1e-6, 1e-9):
        result = rk.simulate(system, (0.0, 0.1), rtol=rtol, atol=1e-6 * rtol, sample_rate=400_000.0)
        balance = energy_balance(model, result)
        allowed = 10 * rtol * max(1.0, balance.flow / balance.scale)  # 10 rtol per energy scale carried through
        assert balance.relative_quadrature_error < 0.5 * allowed  # the samples resolve the power
        assert balance.relative_residual < allowed
        assert balance.work["drive"][-1] > 0 > balance.work["damping"][-1]
        assert balance.work["rub2"][-1] < 0  # rubbing with mu = 0.1 takes energy out
        out[rtol] = balance.relative_residual
    assert out[1e-9] < out[1e-6] / 10


def test_al31f_across_the_roll_start_between_samples():
    """The roll's start (a jump of the loads) between two samples: each side integrated on its own."""
    model = rk.preset("al31f", roll_start=0.0500037, roll_end=2.0)
    system = model.compile()
    result = rk.simulate(system, (0.0, 0.1), rtol=1e-9, atol=1e-15, sample_rate=200_000.0)
    balance = energy_balance(model, result)
    assert balance.events == (0.0500037,)
    assert balance.relative_residual < 10 * 1e-9 * max(1.0, balance.flow / balance.scale)
    jump = np.abs(np.diff(balance.power_in["maneuver"])).max()
    assert jump > 10 * np.abs(np.diff(balance.power_in["maneuver"][:1000])).max()  # the loads do jump


# ---------------------------------------------------------------------------
# the object and bad input
# ---------------------------------------------------------------------------


def test_balance_is_immutable_data_with_a_summary_and_a_plot():
    import matplotlib

    matplotlib.use("Agg")
    model = jeffcott(damping=8.0)
    balance = energy_balance(model, run(model, (0.0, 0.2), rtol=1e-8, y0=dict(x1=1e-3)))
    assert isinstance(balance, EnergyBalance)
    with pytest.raises(AttributeError):
        balance.h = None
    with pytest.raises(ValueError):
        balance.h[0] = 1.0
    with pytest.raises(TypeError):
        balance.work["drive"] = None
    with pytest.raises(ValueError):
        balance.power_in["damping"][0] = 1.0
    assert "relative residual" in balance.summary()
    ax = balance.plot()
    assert ax.get_ylabel() == "energy (J)"
    total = balance.total_work
    np.testing.assert_allclose(balance.residual, balance.h - balance.h[0] - total)
    assert balance.loads == {}


def test_bad_input():
    model = jeffcott(damping=8.0)
    result = run(model, (0.0, 0.1), rtol=1e-6, y0=dict(x1=1e-3))
    other = jeffcott(damping=8.0, rub=dict(RUB, friction_coefficient=0.1))
    with pytest.raises(rk.ParameterError, match="parameters lacks rub1_"):
        energy_balance(other, result)
    renamed = rk.Result(t=result.t, y=result.y, state_names=("a", "b", "c", "d"), parameters=result.parameters)
    with pytest.raises(rk.ParameterError, match="no states x1"):
        energy_balance(model, renamed)
    with pytest.raises(rk.ParameterError, match="at least 2"):
        energy_balance(model, result.window(0.0, 0.0))
    with pytest.raises(rk.ParameterError, match="Model or System"):
        energy_balance("jeffcott", result)
    y = result.y.copy()
    y[0, 3] = np.nan
    with pytest.raises(rk.ParameterError, match="non-finite"):
        energy_balance(model, rk.Result(t=result.t, y=y, state_names=result.state_names,
                                        parameters=result.parameters))


def test_a_system_works_like_its_model():
    model = jeffcott(damping=8.0)
    result = run(model, (0.0, 0.1), rtol=1e-8, y0=dict(x1=1e-3))
    a, b = energy_balance(model, result), energy_balance(model.compile(), result)
    np.testing.assert_array_equal(a.residual, b.residual)


def test_functions_without_a_numpy_translation_use_the_generated_scalar_code():
    class clipped(sp.Function):  # a stand-in for a future rotorkit contact function
        nargs = 1

        def _pythoncode(self, printer):
            return f"min(max({printer._print(self.args[0])}, -1.0), 1.0)"

    clipped.__module__ = "rotorkit.symbolic.functions"
    x = sp.Symbol("x", real=True)
    from rotorkit.analysis.energy_numeric import scalar_fallbacks

    namespace = scalar_fallbacks([2 * clipped(x)])
    np.testing.assert_array_equal(namespace["clipped"](np.array([-3.0, 0.5, 7.0])), [-1.0, 0.5, 1.0])


def test_module_examples_run():
    failures, tried = doctest.testmod(energy, verbose=False)
    assert tried > 0 and failures == 0
