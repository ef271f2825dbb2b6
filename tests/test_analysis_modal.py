"""Modes, whirl, log decrement and Campbell/stability diagrams against closed forms.

- Jeffcott rotor (m, k, c): damped frequency wn sqrt(1 - zeta^2), log
  decrement 2 pi zeta / sqrt(1 - zeta^2), and the free-decay rate of a
  simulated run.
- Cross-coupled stiffness q (loads Qx = -q y, Qy = +q x) on isotropic
  supports: m s^2 + c s + k - i q = 0 has a root on the imaginary axis
  exactly at q = c wn; unstable above, in forward whirl. With q = q1 W the
  onset speed is c wn / q1.
- Anisotropic supports kx != ky: frequencies sqrt(kx/m), sqrt(ky/m).
- Overhung disk on a massless cantilever (mass m, transverse and polar
  inertia Id, Ip, stiffness EI/L^3 [[12, -6L], [-6L, 4L^2]]): a mode whirling
  at w (forward w > 0, backward w < 0) satisfies
  (k11 - m w^2)(k22 - Id w^2 + Ip W w) = k12^2; its critical speeds (w = +-W)
  solve the same with Id -+ Ip.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorkit import Disk, ElasticSupport, Model, Rotor
from rotorkit.analysis.campbell import campbell, mac
from rotorkit.analysis.linear_model import LinearModel, linear_model
from rotorkit.analysis.modes import natural_frequencies
from rotorkit.analysis.whirl import orbit
from rotorkit.elements.base import Element, Terms
from rotorkit.errors import ParameterError

M_, K_, C_ = 2.0, 2.0e4, 4.0
WN = math.sqrt(K_ / M_)
ZETA = C_ / (2.0 * math.sqrt(K_ * M_))
NAMES = ("x1", "y1")


def jeffcott_linear(kx=K_, ky=K_, c=C_, q=0.0, q_per_speed=0.0):
    skew = np.array([[0.0, 1.0], [-1.0, 0.0]])  # Qx = -q y, Qy = +q x  ->  K gets [[0, q], [-q, 0]]
    return LinearModel(mass=M_ * np.eye(2), damping=c * np.eye(2), stiffness=np.diag([kx, ky]) + q * skew,
                       circulatory=q_per_speed * skew, coordinate_names=NAMES, rotor_speeds={"R": (0.0, 1.0)})


def test_jeffcott_damped_frequency_and_log_decrement():
    modes = jeffcott_linear().modes(0.0)
    np.testing.assert_allclose(modes.frequencies, WN, rtol=1e-12)
    np.testing.assert_allclose(modes.damped_frequencies, WN * math.sqrt(1 - ZETA**2), rtol=1e-12)
    np.testing.assert_allclose(modes.log_decrements, 2 * math.pi * ZETA / math.sqrt(1 - ZETA**2), rtol=1e-10)
    assert modes.whirl == ("backward", "forward")  # the double root split into its circular whirls
    assert modes.stations == ("1",)


def test_log_decrement_matches_free_decay_of_a_simulated_run():
    from rotorkit.simulate import simulate

    system = Model([Rotor(name="R", stations=(1,), speed=0.0), Disk(station=1, mass=M_, radius=0.1),
                    ElasticSupport(station=1, stiffness=K_, damping=10 * C_)]).compile(backend="python")
    modes = natural_frequencies(system)
    y0 = np.zeros(4)
    y0[0] = 1e-4
    run = simulate(system, (0.0, 0.5), y0=y0, rtol=1e-10, atol=1e-14, sample_rate=20000.0)
    x = run["x1"]
    peaks = [i for i in range(1, x.size - 1) if x[i] > x[i - 1] and x[i] >= x[i + 1] and x[i] > 0]
    measured = np.mean(np.log(x[peaks[:-1]] / x[peaks[1:]]))
    np.testing.assert_allclose(measured, modes.log_decrements[0], rtol=2e-3)


def test_left_eigenvectors_of_a_cross_coupled_rotor():
    model = jeffcott_linear(q=50.0)
    modes = model.modes(0.0)
    M, C, K = model.matrices(0.0)
    for i, lam in enumerate(modes.eigenvalues):
        x, y = modes.shapes[:, i], modes.left_shapes[:, i]
        Q = lam**2 * M + lam * C + K
        assert np.linalg.norm(Q @ x) < 1e-9 * np.linalg.norm(Q)
        assert np.linalg.norm(y.conj() @ Q) < 1e-9 * np.linalg.norm(Q) * np.linalg.norm(y)
        assert abs(y.conj() @ (2 * lam * M + C) @ x - 1.0) < 1e-9


@pytest.mark.parametrize("factor, stable", [(0.99, True), (1.01, False)])
def test_cross_coupled_jeffcott_is_unstable_exactly_above_c_wn(factor, stable):
    modes = jeffcott_linear(q=factor * C_ * WN).modes(0.0)
    assert modes.stable is stable
    assert sorted(modes.whirl) == ["backward", "forward"]
    forward = modes.whirl.index("forward")
    assert bool(modes.log_decrements[forward] > 0) is stable  # the forward mode is the one driven
    assert modes.log_decrements[1 - forward] > 0


def _cross_coupling_element():
    from dataclasses import dataclass

    @dataclass(frozen=True, slots=True, kw_only=True)
    class Coupling(Element):
        station: int = 1
        coupling: float = 0.0
        _units = {"coupling": ("N/m", "nonnegative")}

        def attached_stations(self):
            return (self.station,)

        def _default_label(self):
            return f"coupling{self.station}"

        def contribute(self, ctx):
            (x, _), (y, _) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
            q = ctx.p["coupling"]
            return Terms(loads={x: -q * y, y: q * x})

    return Coupling


@pytest.mark.parametrize("factor, stable", [(0.98, True), (1.02, False)])
def test_custom_cross_coupling_element_in_a_compiled_model(factor, stable):
    Coupling = _cross_coupling_element()
    system = Model([Rotor(name="R", stations=(1,), speed=100.0), Disk(station=1, mass=M_, radius=0.1),
                    ElasticSupport(station=1, stiffness=K_, damping=C_),
                    Coupling(station=1, coupling=factor * C_ * WN)]).compile(backend="python")
    modes = natural_frequencies(system)
    assert modes.stable is stable
    lm = linear_model(system)
    np.testing.assert_allclose(lm.stiffness, [[K_, factor * C_ * WN], [-factor * C_ * WN, K_]], rtol=1e-9)
    np.testing.assert_allclose(lm.mass, M_ * np.eye(2), rtol=1e-12)


def test_instability_onset_where_the_cross_coupling_grows_with_speed():
    q1 = 0.1  # N/m per rad/s
    diagram = campbell(jeffcott_linear(q_per_speed=q1), np.linspace(0.0, 8000.0, 17), n_modes=2)
    expected = C_ * WN / q1  # 4000 rad/s
    assert diagram.instability_onset == pytest.approx(expected, rel=1e-9)
    (onset,) = diagram.onsets
    assert onset.mode == 2 and onset.whirl == "forward" and onset.becomes == "unstable"
    assert onset.frequency == pytest.approx(WN, rel=1e-9)
    assert np.all(diagram.log_decrements[:, 0] > 0)  # the backward mode is damped further


def test_anisotropic_supports_split_the_frequencies():
    kx, ky = 1.5e4, 2.5e4
    modes = jeffcott_linear(kx=kx, ky=ky, c=0.0).modes(0.0)
    np.testing.assert_allclose(modes.frequencies, [math.sqrt(kx / M_), math.sqrt(ky / M_)], rtol=1e-12)
    assert modes.whirl == ("linear", "linear")  # planar modes, no gyroscopic coupling


# ---------------------------------------------------------------------------
# Overhung gyroscopic disk
# ---------------------------------------------------------------------------

EI, L = 2.0e4, 0.5
MD, ID, IP = 5.0, 0.05, 0.08  # Ip > Id: the forward line never meets 1x
K11, K12, K22 = 12 * EI / L**3, -6 * EI / L**2, 4 * EI / L


def overhung(ip=IP):
    # coordinates x, y, theta_x, theta_y; dx/dz = theta_y, dy/dz = -theta_x
    K = np.zeros((4, 4))
    K[np.ix_([0, 3], [0, 3])] = [[K11, K12], [K12, K22]]
    K[np.ix_([1, 2], [1, 2])] = [[K11, -K12], [-K12, K22]]
    G = np.zeros((4, 4))
    G[2, 3], G[3, 2] = ip, -ip
    return LinearModel(mass=np.diag([MD, MD, ID, ID]), damping=np.zeros((4, 4)), stiffness=K, gyroscopic=G,
                       coordinate_names=("x1", "y1", "tx1", "ty1"), rotor_speeds={"R": (0.0, 1.0)})


def whirl_frequencies(speed, ip=IP):
    """Roots w of (K11 - m w^2)(K22 - Id w^2 + Ip W w) - K12^2 (forward w > 0, backward w < 0)."""
    a = np.polynomial.Polynomial([K11, 0.0, -MD])
    b = np.polynomial.Polynomial([K22, ip * speed, -ID])
    roots = (a * b - K12**2).roots()
    return np.sort(roots.real[np.abs(roots.imag) < 1e-9])


def critical(inertia):
    """Critical speeds W with (K11 - m W^2)(K22 - inertia W^2) = K12^2 (real positive roots)."""
    roots = np.roots([MD * inertia, -(K11 * inertia + MD * K22), K11 * K22 - K12**2])
    return np.sort(np.sqrt(roots[(roots.real > 0) & (np.abs(roots.imag) < 1e-9)].real))


def test_overhung_disk_campbell_lines_and_whirl():
    model = overhung()
    for speed in (0.0, 300.0, 1000.0):
        modes = model.modes(speed)
        w = whirl_frequencies(speed)
        forward, backward = np.sort(w[w > 0]), np.sort(-w[w < 0])
        kinds = np.array(modes.whirl)
        if speed > 0:
            np.testing.assert_allclose(np.sort(modes.frequencies[kinds == "forward"]), forward, rtol=1e-9)
            np.testing.assert_allclose(np.sort(modes.frequencies[kinds == "backward"]), backward, rtol=1e-9)
        else:
            np.testing.assert_allclose(modes.frequencies, np.sort(np.repeat(forward, 2)), rtol=1e-9)


def test_overhung_disk_critical_speeds_forward_and_backward():
    ip = 0.02  # Ip < Id: both critical speeds of the lower pair exist
    diagram = campbell(overhung(ip), np.linspace(0.0, 2000.0, 41), n_modes=4)
    fwd = [c.speed for c in diagram.critical_speeds() if c.whirl == "forward"]
    bwd = [c.speed for c in diagram.critical_speeds() if c.whirl == "backward"]
    np.testing.assert_allclose(sorted(fwd), critical(ID - ip)[: len(fwd)], rtol=1e-8)
    np.testing.assert_allclose(sorted(bwd), critical(ID + ip)[: len(bwd)], rtol=1e-8)
    assert len(fwd) >= 1 and len(bwd) >= 2
    # tracked lines keep their whirl along the speed (no swap at crossings)
    for k in range(diagram.n_modes):
        assert len(set(diagram.whirl[1:, k])) == 1


def test_tracking_keeps_identity_through_a_crossing():
    # translation (flat) and the backward tilt line (falling) cross: sorting would swap them
    model = overhung(0.3)
    diagram = campbell(model, np.linspace(0.0, 3000.0, 31), n_modes=4)
    for k in range(diagram.n_modes):
        kinds = set(diagram.whirl[1:, k])
        assert len(kinds) == 1
    for i, speed in enumerate(diagram.speeds[1:], start=1):
        w = whirl_frequencies(speed, 0.3)
        for k in range(diagram.n_modes):
            assert np.min(np.abs(np.abs(w) - diagram.frequencies[i, k])) < 1e-6 * np.max(np.abs(w))


def test_mac_of_forward_and_backward_circles_is_zero():
    f = np.array([1.0, -1j])
    b = np.array([1.0, 1j])
    np.testing.assert_allclose(mac(np.column_stack([f, b]), np.column_stack([f, b])), np.eye(2), atol=1e-15)


def test_orbit_ellipse_of_two_amplitudes():
    o = orbit(1.0, 0.5j)  # x = cos, y = -0.5 sin: backward ellipse, axes 1 and 0.5 along x
    assert o.direction == "backward"
    assert (float(o.major), float(o.minor), float(o.inclination)) == pytest.approx((1.0, 0.5, 0.0), abs=1e-12)
    o = orbit(1.0, 1.0)  # x = y: a straight line at 45 degrees
    assert o.direction == "linear"
    assert float(o.inclination) == pytest.approx(math.pi / 4)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(mass=np.eye(2), stiffness=np.eye(3)), r"stiffness has shape \(3, 3\)"),
        (dict(mass=np.zeros((2, 2)), stiffness=np.eye(2)), "mass is singular"),
        (dict(mass=np.eye(2), stiffness=[[1.0, np.nan], [0.0, 1.0]]), "NaN"),
        (dict(mass=np.eye(2), stiffness=np.eye(2), coordinate_names=("a", "a")), "distinct"),
        (dict(mass=np.eye(2), stiffness=np.eye(2), rotor_speeds={"R": 3.0}), "rotor_speeds"),
    ],
)
def test_bad_linear_model_raises(kwargs, match):
    kwargs.setdefault("damping", None)
    with pytest.raises(ParameterError, match=match):
        LinearModel(**kwargs)


def test_bad_speed_raises():
    with pytest.raises(ParameterError, match="speed=nan"):
        jeffcott_linear().modes(float("nan"))


def test_sparse_lowest_modes_agree_with_the_dense_solution():
    from test_analysis_unbalance import chain

    model = chain(80)
    dense = model.modes(300.0)
    sparse = model.modes(300.0, n_modes=6)
    k = 6
    np.testing.assert_allclose(sparse.eigenvalues[:k], dense.eigenvalues[:k], rtol=1e-9)
    assert sparse.whirl[:k] == dense.whirl[:k]
    M, C, K = model.matrices(300.0)
    for i in range(k):
        lam, x, y = sparse.eigenvalues[i], sparse.shapes[:, i], sparse.left_shapes[:, i]
        Q = lam**2 * M + lam * C + K
        assert np.linalg.norm(y.conj() @ Q) < 1e-8 * np.linalg.norm(Q) * np.linalg.norm(y)
        assert abs(y.conj() @ (2 * lam * M + C) @ x - 1.0) < 1e-8
