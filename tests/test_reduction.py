"""Model reduction (rotorkit.reduction): Craig-Bampton with the contact coordinates physical.

Checked against the full model: with every interior mode kept the reduced
system is the full one in other coordinates (right-hand side, runs, natural
frequencies); with fewer modes the low natural frequencies and a rub run
converge to the full model's as modes are added.
"""

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.analysis.modes import natural_frequencies
from rotorkit.elements import BeamSegment, Disk, Material, SpeedProfile
from rotorkit.errors import ParameterError, TopologyError

NUMBA = "numba" in rk.available_backends()


def beam_rotor(nodes=5, speed=300.0, rub=True, seed=0):
    """A steel shaft of ``nodes`` beam nodes, two unbalanced disks, two bearings, a rub stator at the first disk."""
    rng = np.random.default_rng(seed)
    steel = Material.steel()
    stations = tuple(range(1, nodes + 1))
    elements = [rk.Rotor(name="R", stations=stations, speed=speed)]
    elements += [BeamSegment(start=s, end=s + 1, length=float(rng.uniform(0.1, 0.3)), outer_diameter=0.05,
                             material=steel) for s in stations[:-1]]
    disks = (stations[1], stations[-2])
    elements += [Disk.from_geometry(station=s, width=0.05, inner_diameter=0.05, outer_diameter=0.25, material=steel,
                                    eccentricity=2e-5, phase=float(k)) for k, s in enumerate(disks)]
    elements += [rk.ElasticSupport(station=s, stiffness=1e6, damping=100.0) for s in (stations[0], stations[-1])]
    if rub:
        elements.append(rk.RubStator(station=disks[0], clearance=1e-5, contact_stiffness=2e6,
                                     friction_coefficient=0.1))
    return rk.Model(elements, name=f"reduction_beam_{nodes}_{seed}")


@pytest.fixture(scope="module")
def small():
    return beam_rotor(5).compile(backend="python")


def mapped_difference(full, reduced, states, times):
    """Largest relative difference of T z'' (reduced) against the full right-hand side at y = T z."""
    worst = 0.0
    for z in states:
        y = reduced.physical_state(z)
        for t in times:
            ref = full.rhs(t, y)
            got = reduced.physical_state(reduced.rhs(t, z))
            worst = max(worst, float(np.abs(got - ref).max() / np.abs(ref).max()))
    return worst


def random_reduced_states(reduced, count, seed):
    rng = np.random.default_rng(seed)
    R = reduced.n_states // 2
    return [np.concatenate([rng.normal(size=R) * 3e-5, rng.normal(size=R) * 1e-2]) for _ in range(count)]


def test_all_modes_right_hand_side_equals_full(small):
    n_interior = len(small.coordinate_names) - len(small._module.LOCAL_ROWS if hasattr(small._module, "LOCAL_ROWS")
                                                      else ())
    reduced = rk.reduce(small, modes=len(small.coordinate_names) - 4)
    assert reduced.boundary == ("x2", "x4", "y2", "y4")  # rub and unbalance stations, physical
    assert reduced.basis.shape == (20, 20) and n_interior >= 16
    states = random_reduced_states(reduced, 3, 1)
    states[0][0] = 0.0  # the rub disk centred (out of contact) in one state, far in contact in another
    states[1][0] = 1e-4
    assert mapped_difference(small, reduced, states, (0.0, 0.37)) < 1e-10


def test_all_modes_with_a_speed_profile():
    """The time-factor matrices (gyroscopic terms times the run-up speed) are reduced too."""
    model = beam_rotor(4, speed=SpeedProfile.table(times=[0.0, 1.0], speeds=[0.0, 400.0]), seed=3)
    full = model.compile(backend="python")
    reduced = rk.reduce(full, modes=len(model.coordinate_names) - 4)
    assert reduced._module.N_GROUPS >= 2  # constant matrices and the speed-scaled ones
    assert mapped_difference(full, reduced, random_reduced_states(reduced, 2, 2), (0.3, 0.8)) < 1e-10


def test_truncated_basis_is_exact_on_its_own_span(small):
    """Fewer modes: the reduced right-hand side is the Galerkin projection; on states where the interior
    carries no inertia or damping load (z' = 0, no interior mode deflected) the boundary rows are statically
    exact: T^T f(T z) = f_r(z)."""
    reduced = rk.reduce(small, modes=3)
    assert reduced.n_states == 2 * (4 + 3)
    z = np.zeros(reduced.n_states)
    z[0], z[2] = 2e-5, -1e-5
    y = reduced.physical_state(z)
    force_full = reduced._m0 @ small.rhs(0.1, y)[20:]
    force_reduced = reduced._mr @ reduced.rhs(0.1, z)[reduced.n_states // 2:]
    np.testing.assert_allclose(reduced.basis.T @ force_full, force_reduced, rtol=0,
                               atol=1e-10 * np.abs(force_reduced).max())


def test_natural_frequencies_all_modes_equal_full(small):
    reduced = rk.reduce(small, modes=16)
    a = natural_frequencies(small, equilibrium=False, rub_engaged=False)
    b = natural_frequencies(reduced, equilibrium=False, rub_engaged=False)
    np.testing.assert_allclose(b.frequencies, a.frequencies, rtol=1e-6)
    np.testing.assert_allclose(b.damping_ratios, a.damping_ratios, rtol=1e-4, atol=1e-9)


@pytest.fixture(scope="module")
def ten():
    return beam_rotor(10, seed=7).compile(backend="numba" if NUMBA else "python")


def test_low_frequencies_of_a_truncated_model(ten):
    """Craig-Bampton is exact at 0 Hz and accurate far below the first dropped fixed-interface frequency."""
    full = natural_frequencies(ten, equilibrium=False, rub_engaged=False)
    worst = []
    for modes in (8, 16):
        reduced = rk.reduce(ten, modes=modes)
        cut = reduced.error_estimate(points=2).first_dropped_frequency
        red = natural_frequencies(reduced, equilibrium=False, rub_engaged=False)
        low = full.frequencies < cut / 4
        assert low.sum() >= 4
        rel = np.abs(red.frequencies[: low.sum()] - full.frequencies[low]) / full.frequencies[low]
        assert rel.max() < 1e-3, (modes, rel)
        worst.append(rel[:4].max())
    assert worst[1] < worst[0] / 10 and worst[1] < 1e-5, worst  # the lowest four: converging with the modes


def test_error_estimate_falls_with_modes(ten):
    est = [rk.reduce(ten, modes=m).error_estimate(band=(0.0, 3000.0), points=200) for m in (2, 6, 12)]
    errors = [e.frf_error for e in est]
    assert errors[0] > errors[1] > errors[2]
    assert est[0].first_dropped_frequency < est[1].first_dropped_frequency < est[2].first_dropped_frequency
    n_interior = len(ten.coordinate_names) - 4
    assert rk.reduce(ten, modes=n_interior).error_estimate(points=50).frf_error < 1e-9
    with pytest.raises(ParameterError, match="band"):
        est[0].frf_error and rk.reduce(ten, modes=2).error_estimate(band=(5.0, 1.0))


@pytest.mark.skipif(not NUMBA, reason="numba not installed")
def test_all_modes_simulation_equals_full():
    model = beam_rotor(5)
    full = model.compile(backend="numba")
    reduced = rk.reduce(full, modes=16)
    options = dict(rtol=1e-9, atol=1e-13, sample_rate=5000.0)
    for engine in ("compiled", "scipy"):
        ref = rk.simulate(full, (0.0, 0.03), engine=engine, **options)
        run = rk.simulate(reduced, (0.0, 0.03), engine=engine, **options)
        assert run.state_names == reduced.state_names
        got = reduced.expand(run)
        assert got.state_names == ref.state_names
        assert np.abs(ref["x2"]).max() > 3e-5  # the disk rubs (clearance 1e-5 m)
        assert np.abs(got.y - ref.y).max() < 1e-5 * np.abs(ref.y).max()


@pytest.mark.slow
@pytest.mark.skipif(not NUMBA, reason="numba not installed")
def test_rub_run_converges_as_modes_are_added(ten):
    t_span, options = (0.0, 0.05), dict(rtol=1e-9, atol=1e-13, sample_rate=4000.0)
    ref = rk.simulate(ten, t_span, **options)
    x = ref["x2"]
    assert np.abs(x).max() > 3e-5  # in contact
    errors = []
    for modes in (4, 8, 16, 32):
        reduced = rk.reduce(ten, modes=modes)
        run = reduced.expand(rk.simulate(reduced, t_span, **options))
        errors.append(float(np.abs(run["x2"] - x).max() / np.abs(x).max()))
    assert all(a > b for a, b in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-6, errors


def test_with_parameters_rebuilds_the_basis(small):
    reduced = rk.reduce(small, modes=16)
    faster = reduced.with_parameters(R_speed=600.0)
    assert isinstance(faster, rk.ReducedSystem) and faster.parameters["R_speed"] == 600.0
    full = small.with_parameters(R_speed=600.0)
    assert mapped_difference(full, faster, random_reduced_states(faster, 2, 4), (0.2,)) < 1e-10
    window = reduced.within(0.1, 0.2).with_parameters(R_speed=500.0)
    assert window.prepared_parameters[-2] >= 0.1 and window.prepared_parameters[-1] <= 0.2


def test_keep_makes_a_coordinate_physical(small):
    reduced = rk.reduce(small, modes=4, keep=["x3", 5])
    assert reduced.boundary == ("x2", "x4", "y2", "y4", "x3", "x5", "y5", "thx5", "thy5")
    z = random_reduced_states(reduced, 1, 9)[0]
    y = reduced.physical_state(z)
    names = small.coordinate_names
    for k, name in enumerate(reduced.boundary):
        assert y[names.index(name)] == z[k]


def test_reduced_state_inverts_physical_state(small):
    reduced = rk.reduce(small, modes=5)
    z = random_reduced_states(reduced, 1, 3)[0]
    np.testing.assert_allclose(reduced.reduced_state(reduced.physical_state(z)), z, rtol=1e-10, atol=1e-16)


@pytest.mark.parametrize("modes, message", [(-1, "modes=-1"), (17, "modes=17: expected an integer from 0 to 16"),
                                            (2.5, "modes=2.5"), (True, "modes=True")])
def test_bad_modes(small, modes, message):
    with pytest.raises(ParameterError, match=message):
        rk.reduce(small, modes=modes)


@pytest.mark.parametrize("keep, message", [(["x33"], "unknown coordinate 'x33'; did you mean"),
                                           ([42], "no coordinates at station 42"),
                                           ([None], "None is not a coordinate name")])
def test_bad_keep(small, keep, message):
    with pytest.raises(ParameterError, match=message):
        rk.reduce(small, modes=2, keep=keep)


def test_no_interior_to_reduce():
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=100.0), rk.Disk(station=1, mass=2.0, radius=0.1),
                      rk.ElasticSupport(station=1, stiffness=2e4, damping=4.0),
                      rk.RubStator(station=1, clearance=1e-4, contact_stiffness=1e6)], name="one_disk_rub")
    with pytest.raises(ParameterError, match="no interior coordinates"):
        rk.reduce(model.compile(backend="python"), modes=0)


def test_free_interior_is_named():
    """A rotor held only at its rub station: with that station fixed, the shaft still tilts freely about it
    (a rigid rotation of the interior), so the constraint modes do not exist."""
    steel = Material.steel()
    model = rk.Model([rk.Rotor(name="R", stations=(1, 2, 3), speed=0.0),
                      BeamSegment(start=1, end=2, length=0.2, outer_diameter=0.05, material=steel),
                      BeamSegment(start=2, end=3, length=0.2, outer_diameter=0.05, material=steel),
                      rk.Disk(station=2, mass=3.0, radius=0.1), rk.ElasticSupport(station=2, stiffness=1e6),
                      rk.RubStator(station=2, clearance=1e-4, contact_stiffness=1e6)], name="free_beam")
    with pytest.raises(ParameterError, match="not held by a stiffness"):
        rk.reduce(model, modes=2, backend="python")


def test_state_dependent_mass_is_refused():
    model = rk.Model([rk.Rotor(name="R", stations=(1, 2), speed=200.0),
                      BeamSegment(start=1, end=2, length=0.3, outer_diameter=0.05, material=Material.steel()),
                      rk.Disk(station=2, mass=8.0, radius=0.12, eccentricity=0.01, torsion=True),
                      rk.ShaftSegment(start=1, end=2, bending_stiffness=5e4, torsional_stiffness=300.0),
                      rk.ElasticSupport(station=1, stiffness=1e6)], name="eccentric_torsion")
    with pytest.raises(TopologyError, match="state-dependent mass"):
        rk.reduce(model, modes=1, backend="python")


def test_expand_checks_the_result(small):
    reduced = rk.reduce(small, modes=2)
    other = rk.reduce(small, modes=3)
    run = rk.simulate(other, (0.0, 1e-3), sample_rate=2000.0, engine="scipy")
    with pytest.raises(ParameterError, match="not this reduced system's"):
        reduced.expand(run)
    with pytest.raises(TypeError, match="expected a rotorkit System or Model"):
        rk.reduce("al31f", modes=2)


def test_gravity_sag_is_exact_with_few_modes():
    """A constant interior load (gravity on the whole shaft) gets its static vector: the sag is exact."""
    from rotorkit.analysis.linearize import static_equilibrium

    model = rk.Model(list(beam_rotor(5, rub=False).elements) + [rk.Maneuver.steady()], name="reduction_gravity")
    full = model.compile(backend="python")
    q_full = static_equilibrium(full)
    assert np.abs(q_full).max() > 1e-6  # it sags
    for modes in (0, 2):
        reduced = rk.reduce(full, modes=modes)
        assert reduced.coordinate_names[-1] == "eta_static"
        q = reduced.basis @ static_equilibrium(reduced)
        np.testing.assert_allclose(q, q_full, rtol=0, atol=1e-9 * np.abs(q_full).max())


def build_beam(contact_stiffness=2e6):
    """Sweep scene: the 5-node beam rotor with its rub stator's contact stiffness as the swept parameter."""
    elements = [e for e in beam_rotor(5).elements if not isinstance(e, rk.RubStator)]
    station = elements[-3].station  # the first disk's
    elements.append(rk.RubStator(station=station, clearance=1e-5, contact_stiffness=contact_stiffness,
                                 friction_coefficient=0.1))
    return rk.Model(elements, name="reduction_sweep_beam")


build_beam.OUTPUTS = {"t_end": 0.04, "bending": "x2"}


@pytest.mark.skipif(not NUMBA, reason="numba not installed")
def test_sweep_runs_reduced_points(tmp_path):
    """simulate_options={'reduce': m}: every point runs the reduced system; with all modes the stored spectra equal
    the full sweep's; bad values fail before any point runs."""
    from rotorkit.sweep import run_sweep

    options = dict(rtol=1e-10, atol=1e-14, sample_rate=4000.0)
    # a run-away limit of 1 m: simulate's bound also applies to the full model's beam rotations (thx, thy), which the
    # reduced one holds in its modal coordinates
    kwargs = dict(window=(0.01, 0.04), workers=1, signals=["x2", "x3"], orders=["1"], runaway_limit=1.0)
    full = run_sweep(build_beam, "contact_stiffness", [1e6, 3e6], out_dir=tmp_path / "full",
                     simulate_options=options, **kwargs)
    reduced = run_sweep(build_beam, "contact_stiffness", [1e6, 3e6], out_dir=tmp_path / "reduced",
                        simulate_options=dict(options, reduce={"modes": 16}), **kwargs)
    a, b = full["amplitude"].values, reduced["amplitude"].values
    assert a.shape == b.shape and np.isfinite(a).sum() > 100  # NaN: padding beyond a point's spectrum
    np.testing.assert_array_equal(np.isnan(b), np.isnan(a))
    np.testing.assert_allclose(b, a, rtol=0, atol=1e-6 * np.nanmax(np.abs(a)))  # x3: interior, expanded
    truncated = run_sweep(build_beam, "contact_stiffness", [1e6], out_dir=tmp_path / "truncated",
                          simulate_options=dict(options, reduce=4), **kwargs)
    assert np.isfinite(truncated["amplitude"].values).sum() > 50
    with pytest.raises(ParameterError, match="modes=99"):
        run_sweep(build_beam, "contact_stiffness", [1e6], out_dir=tmp_path / "bad", simulate_options={"reduce": 99},
                  **kwargs)
    with pytest.raises(ParameterError, match="expected a number of modes"):
        run_sweep(build_beam, "contact_stiffness", [1e6], out_dir=tmp_path / "bad2",
                  simulate_options={"reduce": {"mode": 3}}, **kwargs)


def test_every_subpackage_is_shipped():
    """pyproject's explicit package list holds rotorkit.reduction (and every other subpackage): an installed
    rotorkit would otherwise lack it while tests from the source tree pass."""
    import pathlib
    import tomllib

    root = pathlib.Path(__file__).resolve().parents[1]
    listed = set(tomllib.loads((root / "pyproject.toml").read_text())["tool"]["setuptools"]["packages"])
    found = {".".join(p.parent.relative_to(root).parts) for p in (root / "rotorkit").rglob("__init__.py")}
    assert "rotorkit.reduction" in found and found <= listed, sorted(found - listed)


def test_docstring_examples():
    import doctest

    import rotorkit.reduction.system as module

    failures, tried = doctest.testmod(module, verbose=False)
    assert tried >= 5 and failures == 0


def test_analytic_jacobian_against_finite_differences(small):
    """The generated reduced Jacobian (linear blocks + the local terms' derivatives) against central differences of
    the reduced right-hand side, in and out of contact; with all modes it maps to the full Jacobian."""
    reduced = rk.reduce(small, modes=5)
    assert reduced.has_jacobian
    states = random_reduced_states(reduced, 2, 12)
    states[0][0] = 0.0  # the rub disk out of contact, then far in contact
    states[1][0] = 1e-4
    for z in states:
        for compiled in (False, True) if NUMBA else (False,):  # plain Python and numba-compiled jac
            J = reduced.jacobian(0.21, z, compiled=compiled)
            fd = np.empty_like(J)
            for j in range(z.size):
                h = 1e-7 * max(abs(z[j]), 1e-6)
                e = np.zeros(z.size)
                e[j] = h
                fd[:, j] = (reduced.rhs(0.21, z + e) - reduced.rhs(0.21, z - e)) / (2 * h)
            np.testing.assert_allclose(J, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())
    full = rk.reduce(small, modes=16)
    z = random_reduced_states(full, 1, 13)[0]
    T = np.kron(np.eye(2), full.basis)
    np.testing.assert_allclose(T @ full.jacobian(0.3, z) @ np.linalg.inv(T), small.jacobian(0.3, T @ z),
                               rtol=1e-8, atol=1e-8 * np.abs(small.jacobian(0.3, T @ z)).max())
