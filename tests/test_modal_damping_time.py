"""``Rotor(damping=ModalDamping(...))`` in time simulation: the force ``-C q'`` in the compiled equations.

The model: a two-mass chain in each plane (disk ``m1`` on a support ``k1``,
disk ``m2`` tied to it by a shaft ``k2``), so that the modes couple both
coordinates. Closed forms used:

- undamped frequencies from ``m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0``
  and mode shapes ``phi = (1, k2 / (k2 - m2 w^2))``;
- modal damping keeps each mode's shape, so a free decay started in mode
  ``k`` stays in it and its peaks fall by the log decrement
  ``delta = 2 pi zeta / sqrt(1 - zeta^2)`` per damped period ``2 pi / (w sqrt(1 - zeta^2))``;
- on two modes per plane, modal damping with ratios ``z1``, ``z2`` is
  *exactly* Rayleigh damping ``alpha M + beta K`` with
  ``z_k = alpha / (2 w_k) + beta w_k / 2``: the same model with
  ``Rotor(damping=Rayleigh(alpha, beta))`` (``alpha M + beta K_shaft``) and a
  support damper ``beta k1`` has the same equations, so the same response.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rotorkit as rk
from rotorkit import Disk, ElasticSupport, ModalDamping, Model, Rotor, ShaftSegment
from rotorkit.elements import Rayleigh
from rotorkit.errors import ParameterError
from rotorkit.linear.modes import natural_frequencies

M1, M2, K1, K2 = 2.0, 1.0, 4e4, 2e4  # kg, N/m
Z1, Z2 = 0.02, 0.03


def frequencies(k1=K1):
    """The chain's two undamped frequencies (rad/s), ascending, from the characteristic quadratic."""
    a, b, c = M1 * M2, M1 * K2 + M2 * (k1 + K2), k1 * K2
    root = math.sqrt(b * b - 4 * a * c)
    return math.sqrt((b - root) / (2 * a)), math.sqrt((b + root) / (2 * a))


def shape(w):
    return np.array([1.0, K2 / (K2 - M2 * w * w)])


def chain(damping, support_damping=0.0, speed=0.0, eccentricity=0.0):
    return Model([Rotor(name="R", stations=(1, 2), speed=speed, damping=damping),
                  Disk(station=1, mass=M1, radius=0.1, eccentricity=eccentricity),
                  Disk(station=2, mass=M2, radius=0.1),
                  ElasticSupport(station=1, stiffness=K1, damping=support_damping),
                  ShaftSegment(start=1, end=2, bending_stiffness=K2)])


MODAL = ModalDamping(ratios=(Z1, Z1, Z2, Z2))  # the x and y modes of each pair have the same frequency


def decay(result, row):
    """(damping ratio, damped period s) from the peaks of ``result.y[row]`` (parabolic peak refinement)."""
    y, t = result.y[row], result.t
    k = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]) & (y[1:-1] > 0)) + 1
    a, b, c = y[k - 1], y[k], y[k + 1]
    shift = 0.5 * (a - c) / (a - 2 * b + c)
    peaks = b - 0.25 * (a - c) * shift
    times = t[k] + shift * (t[1] - t[0])
    n = len(peaks) - 1
    delta = math.log(peaks[0] / peaks[-1]) / n
    return delta / math.sqrt(4 * math.pi**2 + delta**2), (times[-1] - times[0]) / n


def free_decay(system, mode, periods=6, **options):
    w = frequencies()[mode]
    phi = shape(w)
    y0 = system.initial_state(x1=1e-3 * phi[0], x2=1e-3 * phi[1])
    span = periods * 2 * math.pi / w
    return rk.simulate(system, (0.0, span), y0=y0, sample_rate=4000 * w / (2 * math.pi), rtol=1e-10, atol=1e-15,
                       **options)


@pytest.mark.parametrize("mode, zeta", [(0, Z1), (1, Z2)])
def test_free_decay_of_each_mode_has_its_ratio(mode, zeta):
    system = chain(MODAL).compile(backend="python")
    assert system.modal_damping
    w = frequencies()[mode]
    linear = rk.linear_model(chain(MODAL)).modes(0.0)
    np.testing.assert_allclose(linear.frequencies, np.repeat(frequencies(), 2), rtol=1e-9)
    eigenvalue = linear.eigenvalues[2 * mode]
    result = free_decay(system, mode, engine="scipy")
    measured, period = decay(result, system.state_index("x1"))
    assert measured == pytest.approx(zeta, rel=1e-3)
    assert period == pytest.approx(2 * math.pi / (w * math.sqrt(1 - zeta**2)), rel=1e-4)
    # the linear analysis' eigenvalue: decay rate and damped frequency
    assert measured * 2 * math.pi / (period * math.sqrt(1 - measured**2)) == pytest.approx(-eigenvalue.real,
                                                                                             rel=1e-3)
    assert 2 * math.pi / period == pytest.approx(abs(eigenvalue.imag), rel=1e-4)
    # the mode keeps its shape: x2 / x1 stays phi
    i1, i2 = system.state_index("x1"), system.state_index("x2")
    big = np.abs(result.y[i1]) > 0.2 * np.abs(result.y[i1]).max()
    np.testing.assert_allclose(result.y[i2, big] / result.y[i1, big], shape(w)[1], rtol=1e-5)


def compiled_backends():
    return [b for b in ("c", "numba") if b in rk.available_backends()]


@pytest.mark.parametrize("backend", [pytest.param(b, marks=pytest.mark.slow) if b == "numba" else b
                                     for b in compiled_backends()])
def test_compiled_engine_gives_the_same_decay(backend):
    """The compiled integration loop takes the modal damping's entries in the prepared parameters."""
    system = chain(MODAL).compile(backend=backend)
    reference = free_decay(chain(MODAL).compile(backend="python"), 1, method="DOP853", engine="scipy")
    result = free_decay(system, 1, method="DOP853", engine="compiled")
    assert result.stats["engine"] == "compiled"
    np.testing.assert_allclose(result.y, reference.y, atol=1e-10, rtol=0)
    assert decay(result, system.state_index("x1"))[0] == pytest.approx(Z2, rel=1e-3)


def equivalent_rayleigh():
    w1, w2 = frequencies()
    return Rayleigh.from_damping_ratios((Z1, w1), (Z2, w2))


@pytest.mark.parametrize("method", ["DOP853", "Radau"])
def test_time_response_equals_the_equivalent_rayleigh_model(method):
    """Unbalance run-up from rest at 150 rad/s: the same equations, so the same response to integration tolerance."""
    rayleigh = equivalent_rayleigh()
    damped = chain(MODAL, speed=150.0, eccentricity=1e-4).compile(backend="python")
    explicit = chain(rayleigh, support_damping=rayleigh.beta * K1, speed=150.0,
                     eccentricity=1e-4).compile(backend="python")
    options = dict(method=method, engine="scipy", rtol=1e-10, atol=1e-14, sample_rate=2000.0)
    span = (0.0, 0.3 if method == "DOP853" else 0.05)  # Radau (analytic Jacobian) in Python is slow
    a, b = rk.simulate(damped, span, **options), rk.simulate(explicit, span, **options)
    assert a.state_names == b.state_names
    scale = np.abs(b.y).max(axis=1, keepdims=True)
    np.testing.assert_allclose(a.y / scale, b.y / scale, atol=1e-6, rtol=0)
    assert np.abs(b.y[0]).max() > 1e-5  # a response, not zeros


def test_structured_code_generation_carries_it():
    rayleigh = equivalent_rayleigh()
    structured = chain(MODAL).compile(backend="python", codegen="structured")
    explicit = chain(rayleigh, support_damping=rayleigh.beta * K1).compile(backend="python")
    y = explicit.initial_state(x1=1e-3, x2_dot=0.3, y2=-2e-4, y1_dot=0.05)
    np.testing.assert_allclose(structured.rhs(0.0, y), explicit.rhs(0.0, y), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(structured.jacobian(0.0, y), explicit.jacobian(0.0, y), rtol=1e-9, atol=1e-9)


def test_jacobian_holds_minus_m_inverse_c():
    system = chain(MODAL).compile(backend="python")
    rayleigh = equivalent_rayleigh()
    explicit = chain(rayleigh, support_damping=rayleigh.beta * K1).compile(backend="python")
    y = np.zeros(system.n_states)
    np.testing.assert_allclose(system.jacobian(0.0, y), explicit.jacobian(0.0, y), rtol=1e-9, atol=1e-9)


def test_new_parameter_values_recompute_the_damping_without_rederiving():
    """A stiffer support moves the modes: with_parameters (as a sweep point) rebuilds C, not the code."""
    system = chain(MODAL).compile(backend="python")
    stiffer = system.with_parameters(support1_stiffness=3 * K1)
    assert stiffer.core is system.core  # same generated module: no derivation, no compilation
    M = np.diag([M1, M2])
    K = np.array([[3 * K1 + K2, -K2], [-K2, K2]])
    w2, Phi = np.linalg.eigh(np.linalg.solve(np.sqrt(M), np.linalg.solve(np.sqrt(M), K).T))  # M^-1/2 K M^-1/2
    Phi = np.linalg.solve(np.sqrt(M), Phi)  # mass-normalised shapes
    C = M @ Phi @ np.diag(2 * np.array([Z1, Z2]) * np.sqrt(w2)) @ Phi.T @ M
    x = [stiffer.coordinate_names.index(n) for n in ("x1", "x2")]
    y = stiffer.initial_state(x1_dot=0.3, x2_dot=-0.1)
    expected = -np.linalg.solve(M, C @ np.array([0.3, -0.1]))
    np.testing.assert_allclose(stiffer.rhs(0.0, y)[[stiffer.n_states // 2 + i for i in x]], expected, rtol=1e-9)
    assert not np.allclose(system.rhs(0.0, y), stiffer.rhs(0.0, y))
    # the damping ratios are those set, at the new frequencies
    result = rk.simulate(stiffer, (0.0, 6 * 2 * math.pi / frequencies(3 * K1)[0]),
                         y0=stiffer.initial_state(x1=1e-3, x2=1e-3 * K2 / (K2 - M2 * frequencies(3 * K1)[0]**2)),
                         sample_rate=4000 * frequencies(3 * K1)[0] / (2 * math.pi), rtol=1e-10, atol=1e-15,
                         engine="scipy")
    assert decay(result, stiffer.state_index("x1"))[0] == pytest.approx(Z1, rel=1e-3)


def test_natural_frequencies_of_the_compiled_system_count_it_once():
    system = chain(MODAL).compile(backend="python")
    modes = natural_frequencies(system, equilibrium=False)
    np.testing.assert_allclose(modes.damping_ratios, [Z1, Z1, Z2, Z2], rtol=1e-6)


def test_a_model_without_it_generates_the_code_it_did():
    """No ModalDamping: no run-time parameters, the module is generate()'s own, byte for byte."""
    from rotorkit.codegen.generate import generate

    for damping in (None, equivalent_rayleigh()):
        model = chain(damping)
        system = model.compile(backend="python")
        assert not system.modal_damping
        assert system.parameter_names == tuple(model.parameters)
        source = generate(model.equations(), model.structure_key, jacobian=False, mode="unrolled").source
        assert system._module.__rotorkit_source__ == source
        assert "_modal" not in source and "N_MODAL_DAMPING" not in source


def test_its_code_is_cached_apart_from_a_model_without_it():
    modal, plain = chain(MODAL).compile(backend="python"), chain(None).compile(backend="python")
    assert modal.core is not plain.core
    assert sum(name.startswith("_modal_c") for name in modal.parameter_names) == 10  # 4 coordinates: 4 * 5 / 2
    assert set(modal.parameters) == set(chain(MODAL).parameters)  # no run-time name among the user's parameters


def test_reduced_system_refuses_by_name():
    model = Model([Rotor(name="R", stations=(1, 2, 3), speed=100.0, damping=ModalDamping(ratios=(0.01,))),
                   Disk(station=2, mass=2.0, radius=0.1)]
                  + [rk.LumpedMass(station=s, mass=1.0) for s in (1, 3)]
                  + [ShaftSegment(start=s, end=s + 1, bending_stiffness=1e6) for s in (1, 2)]
                  + [ElasticSupport(station=s, stiffness=1e5, damping=10.0) for s in (1, 3)])
    reduced = rk.reduce(model, 1, backend="python")
    with pytest.raises(ParameterError, match=r"simulate: .*ModalDamping.*leaves out.*model.compile\(\)"):
        rk.simulate(reduced, (0.0, 0.01))


def test_nonlinear_model_refuses_at_compile():
    model = Model([Rotor(name="R", stations=(1,), speed=100.0, damping=ModalDamping(ratios=(0.01,))),
                   Disk(station=1, mass=2.0, radius=0.1), ElasticSupport(station=1, stiffness=1e5),
                   rk.RubStator(station=1, clearance=1e-4, contact_stiffness=1e7, friction_coefficient=0.1)])
    with pytest.raises(ParameterError, match=r"ModalDamping: .*not linear"):
        model.compile(backend="python")


def test_a_driven_rotor_spin_angle_is_not_damped():
    """A Drive's spin angle is no coordinate of the linear analyses: C couples the lateral coordinates only."""
    model = Model([Rotor(name="R", stations=(1,), speed=rk.Drive.constant(torque=0.0, initial_speed=50.0),
                         damping=ModalDamping(ratios=(0.05, 0.05))),
                   Disk(station=1, mass=M1, radius=0.1), ElasticSupport(station=1, stiffness=K1)])
    system = model.compile(backend="python")
    assert system.coordinate_names == ("x1", "y1", "spin1")
    assert [n for n in system.parameter_names if n.startswith("_modal_c")] == ["_modal_c0_0", "_modal_c0_1",
                                                                               "_modal_c1_1"]
    y = system.initial_state(x1_dot=0.2, spin1_dot=50.0)
    w = math.sqrt(K1 / M1)
    assert system.rhs(0.0, y)[3] == pytest.approx(-2 * 0.05 * w * 0.2, rel=1e-9)  # -c x' / m, c = 2 zeta m w
    assert system.rhs(0.0, y)[5] == pytest.approx(0.0, abs=1e-12)  # no torque, no damping on the spin


def test_energy_balance_holds_the_modal_damping():
    """The energy balance takes the power -q' . C q' of the modal damping into its "damping" channel: the free
    decay's energy loss equals the dissipated work (residual at the solver's error), and that work equals the
    same run's with the equivalent Rayleigh damping (the same equations on this chain)."""
    from rotorkit.analysis.energy import energy_balance

    model = chain(MODAL)
    result = free_decay(model.compile(), 0, periods=4)
    balance = energy_balance(model, result)
    lost = balance.h[0] - balance.h[-1]
    assert lost > 0.1 * balance.h[0]  # a real decay: ~40 % of the energy over 4 periods at zeta = 0.02
    assert balance.relative_residual < 1e-6
    assert balance.work["damping"][-1] == pytest.approx(-lost, rel=1e-6)
