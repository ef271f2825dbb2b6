"""Linearised modal analysis (rotorkit.analysis.modes) against closed-form results.

- Jeffcott rotor: a double natural frequency sqrt(k/m) (x and y), damping
  ratio c / (2 sqrt(k m)), gravity sag y = -m g / k.
- Two masses in a chain (support k1 at the first, shaft k2 between them):
  the roots of det(K - w^2 M) = 0,
  m1 m2 w^4 - (m1 k2 + m2 (k1 + k2)) w^2 + k1 k2 = 0.
- Two torsional disks tied to the drive (kt1) and to each other (kt2): the
  same quadratic with J and kt.
- Rub contact: always engaged (clearance 0) it adds k_r: sqrt((k + k_r)/m);
  with friction the stiffness matrix [[k+kr, -mu kr], [mu kr, k+kr]] gives
  lambda = +-i sqrt((k + kr +- i mu kr)/m), one growing mode; resting on the
  stator under gravity, y* = -(m g + kr delta)/(k + kr), radial stiffness
  k + kr and tangential k + kr (1 - delta/r*).
- AL-31F preset: the product's documented expectation (shared/MODEL_NOTES.md)
  is a lowest bending frequency near 336 rad/s; checked in a broad band.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import rotorkit
from rotorkit import Disk, ElasticSupport, LumpedMass, Maneuver, Model, Rotor, RubStator, ShaftSegment
from rotorkit.analysis.modes import (
    Campbell,
    Modes,
    campbell,
    linearize,
    natural_frequencies,
    static_equilibrium,
)
from rotorkit.errors import ParameterError

MASS, STIFFNESS, DAMPING = 2.0, 2.0e4, 4.0  # kg, N/m, N s/m
WN = math.sqrt(STIFFNESS / MASS)  # 100 rad/s
ZETA = DAMPING / (2.0 * math.sqrt(STIFFNESS * MASS))  # 0.01
G = 9.81


def jeffcott(*, speed=0.0, damping=DAMPING, gravity=None, rub=None, eccentricity=0.0):
    """Jeffcott rotor R, disk at station 1; ``rub`` = dict of RubStator fields."""
    elements = [
        Rotor(name="R", stations=(1,), speed=speed),
        Disk(station=1, mass=MASS, radius=0.1, eccentricity=eccentricity, torsion=False),
        ElasticSupport(station=1, stiffness=STIFFNESS, damping=damping),
    ]
    if gravity is not None:
        elements.append(Maneuver.steady(gravity=gravity))
    if rub is not None:
        elements.append(RubStator(station=1, **rub))
    return Model(elements, name="jeffcott").compile(backend="python")


def quadratic_roots(a11, a22, k1, k2):
    """sqrt of the roots of a11 a22 w^4 - (a11 k2 + a22 (k1 + k2)) w^2 + k1 k2 = 0, ascending."""
    b = a11 * k2 + a22 * (k1 + k2)
    disc = math.sqrt(b * b - 4.0 * a11 * a22 * k1 * k2)
    return sorted(math.sqrt((b + s * disc) / (2.0 * a11 * a22)) for s in (-1.0, 1.0))


@pytest.fixture(scope="module")
def al31f():
    return rotorkit.preset("al31f").compile(backend="python")


@pytest.fixture(scope="module")
def al31f_modes(al31f):
    return natural_frequencies(al31f)


# ---------------------------------------------------------------------------
# Jeffcott rotor
# ---------------------------------------------------------------------------


def test_jeffcott_frequency_and_damping_ratio():
    modes = natural_frequencies(jeffcott(speed=300.0))
    assert isinstance(modes, Modes)
    np.testing.assert_allclose(modes.frequencies, [WN, WN], rtol=1e-7)
    np.testing.assert_allclose(modes.damping_ratios, [ZETA, ZETA], rtol=1e-6)
    np.testing.assert_allclose(modes.damped_frequencies, WN * math.sqrt(1 - ZETA**2), rtol=1e-7)
    np.testing.assert_allclose(modes.eigenvalues.real, -ZETA * WN, rtol=1e-6)
    assert modes.sample_times.tolist() == [0.0]  # no bearing: one sample
    assert modes.rub_engaged is False


def test_jeffcott_static_sag_under_gravity():
    system = jeffcott(gravity=G)
    q = static_equilibrium(system)
    np.testing.assert_allclose(q, [0.0, -MASS * G / STIFFNESS], rtol=1e-9, atol=1e-15)
    modes = natural_frequencies(system)  # linear: the sag does not change the frequency
    np.testing.assert_allclose(modes.operating_point, q, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(modes.frequencies, [WN, WN], rtol=1e-7)


def test_static_equilibrium_ignores_unbalance_by_default():
    system = jeffcott(speed=50.0, gravity=G, eccentricity=1e-3)
    np.testing.assert_allclose(static_equilibrium(system), [0.0, -MASS * G / STIFFNESS], rtol=1e-9, atol=1e-15)
    # a frozen snapshot with the unbalance force m e w^2 (cos, sin)(0) = (m e w^2, 0)
    q = static_equilibrium(system, unbalance=True)
    np.testing.assert_allclose(q, [MASS * 1e-3 * 50.0**2 / STIFFNESS, -MASS * G / STIFFNESS], rtol=1e-8)


def test_linearize_jeffcott_is_the_exact_state_matrix():
    A, names = linearize(jeffcott(), [0.0, 0.0])
    assert names == ("x1", "y1", "x1_dot", "y1_dot")
    k, c = STIFFNESS / MASS, DAMPING / MASS
    exact = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-k, 0, -c, 0], [0, -k, 0, -c]], dtype=float)
    np.testing.assert_allclose(A, exact, rtol=1e-7, atol=1e-6)


# ---------------------------------------------------------------------------
# Two masses in a chain
# ---------------------------------------------------------------------------

M1, M2, K1, K2, C1 = 1.0, 3.0, 3.0e4, 1.0e4, 2.0


@pytest.fixture(scope="module")
def chain():
    return Model([
        Rotor(name="R", stations=(1, 2), speed=100.0),
        LumpedMass(station=1, mass=M1),
        LumpedMass(station=2, mass=M2),
        ShaftSegment(start=1, end=2, bending_stiffness=K2),
        ElasticSupport(station=1, stiffness=K1, damping=C1),
    ], name="chain").compile(backend="python")


def test_two_mass_chain_frequencies_from_the_closed_form(chain):
    low, high = quadratic_roots(M1, M2, K1, K2)
    # undamped: with non-proportional damping |lambda| differs from the undamped roots
    modes = natural_frequencies(chain.with_parameters(support1_damping=0.0))
    np.testing.assert_allclose(modes.frequencies, [low, low, high, high], rtol=1e-6)


def test_two_mass_chain_jacobian_blocks(chain):
    A, _ = linearize(chain, np.zeros(4))
    Minv = np.diag([1 / M1, 1 / M2])
    K = np.array([[K1 + K2, -K2], [-K2, K2]])
    C = np.array([[C1, 0.0], [0.0, 0.0]])
    # coordinates x1, x2, y1, y2: the x block and the y block are the same
    for block in (slice(0, 2), slice(2, 4)):
        vel = slice(block.start + 4, block.stop + 4)
        np.testing.assert_allclose(A[vel, block], -Minv @ K, rtol=1e-7)
        np.testing.assert_allclose(A[vel, vel], -Minv @ C, rtol=1e-7, atol=1e-7)
    np.testing.assert_array_equal(A[:4, 4:], np.eye(4))


def test_two_mass_chain_mode_shape_ratio(chain):
    low, _ = quadratic_roots(M1, M2, K1, K2)
    modes = natural_frequencies(chain.with_parameters(support1_damping=0.0))
    shape = modes.shape_of(1)
    # (K - w^2 M) v = 0, first row: x2 / x1 = (k1 + k2 - m1 w^2) / k2
    # (modes 1 and 2 are the backward/forward pair of one double frequency: pick the x or y part)
    axis = "x" if abs(shape["x1"]) > abs(shape["y1"]) else "y"
    ratio = shape[f"{axis}2"] / shape[f"{axis}1"]
    np.testing.assert_allclose(ratio.real, (K1 + K2 - M1 * low**2) / K2, rtol=1e-5)
    assert abs(max(abs(v) for v in shape.values()) - 1.0) < 1e-12


# ---------------------------------------------------------------------------
# Torsion
# ---------------------------------------------------------------------------

J2, J3, KT1, KT2, KB = 0.02, 0.01, 2.0e3, 1.0e3, 1.0e4


def test_torsional_two_disk_frequencies():
    system = Model([
        Rotor(name="R", stations=(1, 2, 3), speed=500.0),
        LumpedMass(station=1, mass=1.0),
        Disk(station=2, mass=1.0, polar_inertia=J2, eccentricity=0.0, torsion=True),
        Disk(station=3, mass=1.0, polar_inertia=J3, eccentricity=0.0, torsion=True),
        ShaftSegment(start=1, end=2, torsional_stiffness=KT1),
        ShaftSegment(start=2, end=3, torsional_stiffness=KT2),
        *[ElasticSupport(station=s, stiffness=KB) for s in (1, 2, 3)],
    ], name="torsion").compile(backend="python")
    modes = natural_frequencies(system)
    torsional = [i for i in range(len(modes)) if modes.dominant_coordinates(i + 1, 1)[0].startswith("alpha")]
    np.testing.assert_allclose(modes.frequencies[torsional], quadratic_roots(J2, J3, KT1, KT2), rtol=1e-6)
    bending = [i for i in range(len(modes)) if i not in torsional]
    np.testing.assert_allclose(modes.frequencies[bending], math.sqrt(KB / 1.0), rtol=1e-6)
    assert len(bending) == 6
    for i in torsional:  # pure torsion: no bending in the shape
        shape = modes.shape_of(i + 1)
        assert max(abs(v) for n, v in shape.items() if not n.startswith("alpha")) < 1e-6


# ---------------------------------------------------------------------------
# Rub contact
# ---------------------------------------------------------------------------

KR = 6.0e4  # N/m


def test_rub_with_zero_clearance_adds_its_stiffness():
    system = jeffcott(damping=0.0, rub=dict(clearance=0.0, contact_stiffness=KR))
    engaged = natural_frequencies(system, rub_engaged=True)
    np.testing.assert_allclose(engaged.frequencies, [math.sqrt((STIFFNESS + KR) / MASS)] * 2, rtol=1e-6)
    assert engaged.rub_engaged
    free = natural_frequencies(system, rub_engaged=False)
    np.testing.assert_allclose(free.frequencies, [WN, WN], rtol=1e-7)
    assert not free.rub_engaged
    default = natural_frequencies(system)  # clearance 0: always in contact
    np.testing.assert_allclose(default.frequencies, engaged.frequencies, rtol=1e-9)


def test_rub_friction_gives_the_follower_force_eigenvalues():
    mu = 0.1
    system = jeffcott(damping=0.0, rub=dict(clearance=0.0, contact_stiffness=KR, friction_coefficient=mu))
    modes = natural_frequencies(system, rub_engaged=True)
    expected = [1j * np.sqrt((STIFFNESS + KR + s * 1j * mu * KR) / MASS) for s in (1.0, -1.0)]
    expected = sorted(expected, key=abs)
    np.testing.assert_allclose(np.sort_complex(modes.eigenvalues), np.sort_complex(expected), rtol=1e-6)
    assert min(modes.damping_ratios) < -1e-3 < 1e-3 < max(modes.damping_ratios)  # one mode grows


def test_rub_resting_on_the_stator_under_gravity():
    delta = 5e-4  # below the free sag m g / k = 9.81e-4 m
    system = jeffcott(damping=0.0, gravity=G, rub=dict(clearance=delta, contact_stiffness=KR))
    q = static_equilibrium(system)
    y = -(MASS * G + KR * delta) / (STIFFNESS + KR)
    np.testing.assert_allclose(q, [0.0, y], rtol=1e-9, atol=1e-15)
    modes = natural_frequencies(system)  # engaged at the equilibrium
    tangential = math.sqrt((STIFFNESS + KR * (1.0 - delta / abs(y))) / MASS)
    radial = math.sqrt((STIFFNESS + KR) / MASS)
    np.testing.assert_allclose(modes.frequencies, [tangential, radial], rtol=1e-6)
    assert modes.rub_engaged
    free = natural_frequencies(system, rub_engaged=False)
    np.testing.assert_allclose(free.operating_point, [0.0, -MASS * G / STIFFNESS], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(free.frequencies, [WN, WN], rtol=1e-7)


def test_rub_engaged_pushes_a_grazing_contact_along_the_sag():
    # clearance larger than the sag: not engaged by default, engaged on request
    system = jeffcott(damping=0.0, gravity=G, rub=dict(clearance=2e-3, contact_stiffness=KR))
    np.testing.assert_allclose(natural_frequencies(system).frequencies, [WN, WN], rtol=1e-7)
    modes = natural_frequencies(system, rub_engaged=True)
    # radial (y, along the sag) gets k + kr, tangential (x) keeps k: a grazing contact
    np.testing.assert_allclose(modes.frequencies, [WN, math.sqrt((STIFFNESS + KR) / MASS)], rtol=1e-5)
    assert abs(modes.shape_of(2)["y1"]) == 1.0
    np.testing.assert_allclose(modes.operating_point, [0.0, -MASS * G / STIFFNESS], rtol=1e-9, atol=1e-15)


# ---------------------------------------------------------------------------
# AL-31F preset
# ---------------------------------------------------------------------------


def test_al31f_gravity_sag(al31f):
    q = dict(zip(al31f.coordinate_names, static_equilibrium(al31f)))
    assert -2e-4 < q["y2"] < -5e-5  # MODEL_NOTES: about 1e-4 m at disk 2
    assert max(abs(q[f"x{s}"]) for s in range(1, 8)) < 1e-12  # gravity acts in y only
    # the Hertzian bearing carries load: the HP station sags relative to LP station 4 past the clearance
    assert q["y4"] - q["y7"] < -al31f.parameters["bearing4_7_clearance"]


def test_al31f_lowest_bending_frequency(al31f_modes):
    # MODEL_NOTES.md (the product's documented expectation): near 336 rad/s, about 0.22 omega_low.
    # A broad band: this is a regression guard against gross errors, not a fit to the number.
    modes = al31f_modes
    assert 250.0 < modes.frequencies[0] < 450.0
    assert modes.dominant_coordinates(1, 1)[0][0] in "xy"
    assert modes.frequency_range.shape == (len(modes), 2)
    assert modes.sample_times.size == 16
    assert modes.frequency_range[0, 0] <= modes.frequency_range[0, 1]
    assert not modes.rub_engaged  # the sag (about 9e-5 m) is below the clearance 1.34e-4 m
    assert np.all(modes.damping_ratios > 0)


def test_al31f_rub_engaged_stiffens(al31f, al31f_modes):
    engaged = natural_frequencies(al31f, rub_engaged=True)
    assert engaged.rub_engaged
    assert engaged.frequencies[1] > 1.05 * al31f_modes.frequencies[1]
    # the contact at disk 2 acts along the sag (y): the x modes do not move
    np.testing.assert_allclose(engaged.frequencies[0], al31f_modes.frequencies[0], rtol=1e-3)


def test_al31f_finite_differences_agree_with_the_analytic_jacobian(al31f, al31f_modes):
    if not getattr(al31f, "has_jacobian", False):
        pytest.skip("this system has no analytic Jacobian")
    q = al31f_modes.operating_point  # bearing loaded, rub open: no kink
    fd, _ = linearize(al31f, q, 0.0)
    exact, _ = linearize(al31f, q, 0.0, method="analytic")
    n = len(q)
    scale = np.abs(exact[n:]).max(axis=1, keepdims=True)
    np.testing.assert_allclose(fd[n:] / scale, exact[n:] / scale, atol=1e-6)


def test_al31f_samples_stay_before_a_time_event(al31f):
    start = al31f.parameters["maneuver_roll_start"]
    modes = natural_frequencies(al31f, t=start - 1e-5, cage_samples=4)
    assert modes.sample_times.max() < start
    assert np.isclose(modes.sample_times.max(), start - 1e-5)


def test_al31f_table_lists_every_mode(al31f_modes):
    text = al31f_modes.table(n_modes=None)  # the default lists the 6 lowest (issue 24)
    assert len(text.splitlines()) == 2 + len(al31f_modes)
    assert "damping ratio" in text and "cage spread" in text  # ball bearings: several cage positions sampled
    assert len(al31f_modes.table().splitlines()) == 2 + min(6, len(al31f_modes)) + (len(al31f_modes) > 6)


# ---------------------------------------------------------------------------
# Campbell diagram
# ---------------------------------------------------------------------------


def test_jeffcott_campbell_is_flat_and_the_1x_line_is_the_speed():
    speeds = np.array([0.0, 50.0, 150.0, 300.0])
    diagram = campbell(jeffcott(), speeds, n_modes=2, speed_parameter="R_speed")
    assert isinstance(diagram, Campbell)
    wd = WN * math.sqrt(1.0 - ZETA**2)  # the diagram shows damped natural frequencies
    np.testing.assert_allclose(diagram.frequencies, wd, rtol=1e-7)
    np.testing.assert_allclose(diagram.natural_frequencies, WN, rtol=1e-7)
    np.testing.assert_allclose(diagram.log_decrements, 2 * math.pi * ZETA / math.sqrt(1 - ZETA**2), rtol=1e-6)
    np.testing.assert_array_equal(diagram.rotor_speeds["R"], speeds)
    crossings = diagram.critical_speeds()
    assert [(c.rotor, c.mode, c.whirl) for c in crossings] == [("R", 1, "backward"), ("R", 2, "forward")]
    np.testing.assert_allclose([c.speed for c in crossings], wd, rtol=1e-7)
    np.testing.assert_allclose([c.frequency for c in crossings], wd, rtol=1e-7)


def test_campbell_from_a_builder_follows_the_speed_ratio():
    def build():
        return rotorkit.preset("al31f", rub=False, maneuver=False, torsion=False)

    diagram = campbell(build, [1000.0, 1500.0], n_modes=3, cage_samples=2, backend="python")
    np.testing.assert_array_equal(diagram.rotor_speeds["LP"], [1000.0, 1500.0])
    np.testing.assert_allclose(diagram.rotor_speeds["HP"], [1800.0, 2700.0], rtol=1e-12)
    assert diagram.frequencies.shape == (2, 3)
    assert np.all((diagram.frequencies > 250.0) & (diagram.frequencies < 1000.0))


# ---------------------------------------------------------------------------
# Plotting
# ---------------------------------------------------------------------------


def test_plot_campbell_draws_modes_and_1x_lines():
    from matplotlib.axes import Axes

    from rotorkit.plotting.campbell import plot_campbell

    speeds = np.array([0.0, 100.0, 200.0])
    diagram = campbell(jeffcott(), speeds, n_modes=2, speed_parameter="R_speed")
    ax = plot_campbell(diagram, units="Hz")
    assert isinstance(ax, Axes)
    labels = [line.get_label() for line in ax.get_lines()]
    assert "1x R" in labels and "mode 1" in labels
    line = ax.get_lines()[labels.index("1x R")]
    np.testing.assert_allclose(line.get_ydata(), speeds / (2 * math.pi))
    assert any(text.get_text() == "1x R" for text in ax.texts)
    assert diagram.plot(units="rpm") is not None


def test_plot_mode_shape(chain):
    from rotorkit.plotting.campbell import plot_mode_shape

    modes = natural_frequencies(chain)
    ax = plot_mode_shape(modes, 3)
    lines = ax.get_lines()
    labels = [line.get_label() for line in lines]
    assert labels[:2] == ["semi-major axis", "semi-minor axis"]
    assert max(lines[0].get_ydata()) == pytest.approx(1.0)  # largest entry 1
    np.testing.assert_allclose(lines[1].get_ydata(), lines[0].get_ydata(), rtol=1e-9)  # circular whirl
    assert ax.get_xlabel() == "station" and "relative" in ax.get_ylabel()
    assert modes.plot_mode_shape(1) is not None
    assert modes.plot_orbits(2) is not None


# ---------------------------------------------------------------------------
# Bad input
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda s: linearize(s, [0.0]), r"shape \(1,\)"),
        (lambda s: linearize(s, [0.0, 0.0], eps=-1.0), "eps"),
        (lambda s: linearize(s, [0.0, float("nan")]), "NaN"),
        (lambda s: linearize(s, [0.0, 0.0], method="exact"), "method='exact'"),
        (lambda s: static_equilibrium(s, t=float("inf")), "t=inf"),
        (lambda s: static_equilibrium(s, q0=[1.0, 2.0, 3.0]), "q0"),
        (lambda s: natural_frequencies(s, rub_engaged="yes"), "rub_engaged"),
        (lambda s: natural_frequencies(s, cage_samples=0), "cage_samples"),
        (lambda s: natural_frequencies(s, equilibrium="sag"), "equilibrium"),
        (lambda s: campbell(s, [0.0, 1.0], speed_parameter="LP_speed"), "speed_parameter='LP_speed'"),
        (lambda s: campbell(s, [1.0, 0.0], speed_parameter="R_speed"), "increase"),
        (lambda s: campbell(s, [1.0], orders=(0,), speed_parameter="R_speed"), "orders"),
        (lambda s: campbell(s, [], speed_parameter="R_speed"), "speeds"),
        (lambda s: campbell(s, [1.0], n_modes=0, speed_parameter="R_speed"), "n_modes"),
        (lambda s: natural_frequencies(s).shape_of(5), "mode 5"),
        (lambda s: natural_frequencies(s).shape_of(0), "mode 0 .*from 1"),
        (lambda s: natural_frequencies(s).table(units="kHz"), "units"),
    ],
)
def test_bad_input_raises(call, match):
    with pytest.raises(ParameterError, match=match):
        call(jeffcott(gravity=G))


def test_model_instead_of_system_is_a_type_error():
    model = Model([Rotor(name="R", stations=(1,), speed=0.0), Disk(station=1, mass=1.0, radius=0.1),
                   ElasticSupport(station=1, stiffness=1e4)])
    with pytest.raises(TypeError, match="model.compile"):
        natural_frequencies(model)


def test_non_convergence_names_the_residual(al31f):
    with pytest.raises(ParameterError, match=r"did not converge.*residual acceleration is d2\(\w+\)/dt2"):
        static_equilibrium(al31f, max_evaluations=1)
