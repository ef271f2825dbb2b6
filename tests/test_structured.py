"""Structured code generation (matrices for the linear part, scalar code for local terms) against the unrolled path.

The unrolled path is checked against sympy and finite differences elsewhere
(test_codegen, test_jacobian); here both paths must give the same right-hand
side and Jacobian to 1e-12 relative (max-norm over the vector or matrix) for
the AL-31F preset (state-dependent mass, bearings, rubs, manoeuvres), a
random beam rotor with a rub, an eccentric torsional disk and a run-up.
"""

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.codegen.generate import STRUCTURED_FROM, codegen_mode
from rotorkit.elements import BeamSegment, Disk, Material, SpeedProfile

RTOL = 1e-12


def both(model, backend="python"):
    return (model.compile(backend=backend, codegen="unrolled"), model.compile(backend=backend, codegen="structured"))


def assert_same(unrolled, structured, states, times):
    assert unrolled._module.CODEGEN == "unrolled" and structured._module.CODEGEN == "structured"
    for t in times:
        for y in states:
            a, b = unrolled.rhs(t, y), structured.rhs(t, y)
            np.testing.assert_allclose(b, a, rtol=0, atol=RTOL * np.abs(a).max())
            Ja, Jb = unrolled.jacobian(t, y), structured.jacobian(t, y)
            np.testing.assert_allclose(Jb, Ja, rtol=0, atol=RTOL * np.abs(Ja).max())
            assert np.array_equal(unrolled.switch_values(t, y), structured.switch_values(t, y))


def random_states(n, scale_q, scale_u, count, seed):
    rng = np.random.default_rng(seed)
    return [rng.normal(size=2 * n) * np.r_[np.full(n, scale_q), np.full(n, scale_u)] for _ in range(count)]


def test_preset_structured_equals_unrolled():
    model = rk.preset("al31f")
    unrolled, structured = both(model)
    assert structured._module.MASS_STATE_DEPENDENT  # the eccentric torsional disks: the Woodbury path
    assert_same(unrolled, structured, random_states(16, 2e-4, 1e-2, 4, 11), (0.1, 0.5, 2.5))


def random_beam_rotor(seed, nodes=5, speed=300.0, clearance=2e-5):
    """Beam elements of random length and diameter, two disks, two bearings, unbalance, a rub at one disk."""
    rng = np.random.default_rng(seed)
    steel = Material.steel()
    stations = tuple(range(1, nodes + 1))
    elements = [rk.Rotor(name="R", stations=stations, speed=speed)]
    elements += [BeamSegment(start=s, end=s + 1, length=float(rng.uniform(0.1, 0.4)),
                             outer_diameter=float(rng.uniform(0.04, 0.07)), material=steel) for s in stations[:-1]]
    disks = (stations[1], stations[-2])
    elements += [Disk.from_geometry(station=s, width=0.05, inner_diameter=0.05, outer_diameter=float(rng.uniform(0.2, 0.3)),
                                    material=steel, eccentricity=1e-5) for s in disks]
    elements += [rk.ElasticSupport(station=s, stiffness=float(rng.uniform(5e5, 2e6)), damping=50.0)
                 for s in (stations[0], stations[-1])]
    elements.append(rk.RubStator(station=disks[0], clearance=clearance, contact_stiffness=1e7, friction_coefficient=0.2))
    return rk.Model(elements, name=f"random_beam_{seed}")


@pytest.mark.parametrize("seed", [1, 2])
def test_random_beam_rotor_with_rub(seed):
    model = random_beam_rotor(seed)
    unrolled, structured = both(model)
    n = len(model.coordinate_names)
    rub = model.coordinate_names.index(f"x{model.elements[-1].station}")
    assert rub in structured._module.LOCAL_ROWS and len(structured._module.LOCAL_ROWS) < n // 4
    states = random_states(n, 3e-5, 1e-2, 3, seed)  # the rub station in and out of contact
    states[0][rub], states[1][rub] = 0.0, 1e-4
    assert_same(unrolled, structured, states, (0.0, 0.37))


def eccentric_disk_on_beams(elements, length=0.3):
    """An eccentric torsional disk (state-dependent mass) between beam elements, with a rub."""
    steel = Material.steel()
    return rk.Model([
        rk.Rotor(name="R", stations=(1, 2, 3, 4), speed=200.0),
        BeamSegment(start=1, end=2, length=length, outer_diameter=0.05, material=steel, elements=elements),
        BeamSegment(start=2, end=3, length=length, outer_diameter=0.05, material=steel, elements=elements),
        rk.Disk(station=2, mass=8.0, radius=0.12, eccentricity=0.01, torsion=True),
        rk.LumpedMass(station=4, mass=1.0),
        rk.ShaftSegment(start=2, end=4, bending_stiffness=5e4, torsional_stiffness=300.0, torsional_damping=0.2),
        rk.ElasticSupport(station=1, stiffness=1e6),
        rk.ElasticSupport(station=3, stiffness=1e6),
        rk.ElasticSupport(station=4, stiffness=1e4),
        rk.RubStator(station=2, clearance=1e-5, contact_stiffness=1e7, friction_coefficient=0.1),
    ])


def test_eccentric_torsional_disk_on_beams():
    """State-dependent mass coupled to the consistent beam mass: the Woodbury correction on a banded M0."""
    model = eccentric_disk_on_beams(elements=2)
    unrolled, structured = both(model)
    assert structured._module.MASS_STATE_DEPENDENT
    n = len(model.coordinate_names)
    alpha = model.coordinate_names.index("alpha2")
    states = random_states(n, 3e-5, 1e-2, 3, 5)
    for y in states:
        y[alpha] = 0.7  # far from alpha = 0, where M = M0
    assert_same(unrolled, structured, states, (0.0, 0.2))


def structured_with(model, solve):
    """The structured module with ``M0^-1`` applied as ``solve`` says ('dense' product or 'band' solve)."""
    from rotorkit.codegen import cache
    from rotorkit.codegen.structured import generate_structured
    from rotorkit.system import System

    key = f"{model.structure_key}_test_{solve}"
    module = cache.store(key, generate_structured(model.equations(), key, solve=solve).source)
    assert module.MASS_SOLVE == solve
    return System(model, module, "python", module.rhs)


@pytest.mark.parametrize("solve", ["band", "dense"])
def test_band_and_dense_mass_solves_equal_unrolled(solve):
    """Both ways of applying M0^-1, with the rub in and out of contact and a run-up's speed-scaled matrix."""
    model = random_beam_rotor(5, nodes=7, speed=SpeedProfile.table(times=[0.0, 1.0], speeds=[0.0, 400.0]))
    unrolled = model.compile(backend="python", codegen="unrolled")
    n = len(model.coordinate_names)
    rub = model.coordinate_names.index(f"x{model.elements[-1].station}")
    states = random_states(n, 3e-5, 1e-2, 2, 8)
    states[0][rub], states[1][rub] = 0.0, 1e-4
    assert_same(unrolled, structured_with(model, solve), states, (0.0, 0.4))


def test_band_solve_with_state_dependent_mass():
    """The Woodbury correction around the band solve."""
    model = eccentric_disk_on_beams(elements=4, length=0.4)
    unrolled, band = model.compile(backend="python", codegen="unrolled"), structured_with(model, "band")
    assert band._module.MASS_STATE_DEPENDENT
    alpha = model.coordinate_names.index("alpha2")
    states = random_states(len(model.coordinate_names), 3e-5, 1e-2, 3, 6)
    for y in states:
        y[alpha] = 0.7
    assert_same(unrolled, band, states, (0.0, 0.2))


def test_band_factor_against_numpy():
    from rotorkit.codegen.structured import BLOCK_INVERSE

    scope = {"np": np}
    exec(BLOCK_INVERSE, scope)
    rng = np.random.default_rng(3)
    n, b = 30, 4
    a = np.zeros((n, n))
    for d in range(b + 1):
        v = rng.normal(size=n - d)
        a += np.diag(v, d) + (np.diag(v, -d) if d else 0)
    a += np.eye(n) * (np.abs(a).sum(axis=1).max() + 1.0)  # diagonally dominant: SPD
    lb = scope["_band_factor"](a, b)
    L = np.diag(1.0 / lb[:, 0]) + sum(np.diag(lb[d:, d], -d) for d in range(1, b + 1))
    np.testing.assert_allclose(L, np.linalg.cholesky(a), rtol=0, atol=1e-13 * np.abs(L).max())
    a[5, 5] = -1.0
    assert np.isnan(scope["_band_factor"](a, b)).all()


def test_run_up_keeps_gyroscopics_in_matrices():
    """Speed profile: the gyroscopic terms are a matrix times the speed, not scalar code per coordinate."""
    model = random_beam_rotor(3, speed=SpeedProfile.table(times=[0.0, 1.0], speeds=[0.0, 400.0]))
    unrolled, structured = both(model)
    assert len(structured._module.LOCAL_ROWS) < len(model.coordinate_names) // 4
    assert hasattr(structured._module, "PTR1")  # a second matrix, scaled by the speed
    assert_same(unrolled, structured, random_states(len(model.coordinate_names), 3e-5, 1e-2, 2, 3), (0.3, 0.8))


@pytest.mark.slow
@pytest.mark.skipif("numba" not in rk.available_backends(), reason="numba not installed")
def test_structured_numba_run_equals_unrolled_run():
    """The compiled engine runs structured code; the runs agree to the integration tolerance (their step
    sequences differ by rounding)."""
    model = random_beam_rotor(4, nodes=5)
    runs = []
    for system in both(model, backend="numba"):
        y0 = system.initial_state(**{"x2": 3e-5})
        runs.append(rk.simulate(system, (0.0, 0.02), y0=y0, rtol=1e-8, atol=1e-12, sample_rate=2000.0))
    a, b = (np.asarray(r.y) for r in runs)
    for rows in (slice(0, a.shape[0] // 2), slice(a.shape[0] // 2, None)):  # displacements, velocities
        np.testing.assert_allclose(b[rows], a[rows], rtol=0, atol=1e-5 * np.abs(a[rows]).max())


def test_codegen_mode_by_size_and_override(monkeypatch):
    monkeypatch.delenv("ROTORKIT_CODEGEN", raising=False)
    assert codegen_mode(16) == "unrolled" and codegen_mode(STRUCTURED_FROM) == "structured"
    assert codegen_mode(400, "unrolled") == "unrolled"
    monkeypatch.setenv("ROTORKIT_CODEGEN", "structured")
    assert codegen_mode(16) == "structured"
    with pytest.raises(rk.ParameterError, match="codegen='banded' is unknown"):
        codegen_mode(16, "banded")


def test_beam_torsion_inertia_from_the_shared_template():
    """Beam element matrices come from a template shared by elements; torsion keeps rho Ip l / 3 and / 6."""
    import math

    import sympy as sp

    steel = Material.steel()
    model = rk.Model([rk.Rotor(name="R", stations=(1, 2, 3), speed=100.0),
                      BeamSegment(start=1, end=2, length=0.3, outer_diameter=0.05, material=steel, torsion=True),
                      rk.Disk(station=2, mass=5.0, radius=0.1, torsion=True),
                      rk.ShaftSegment(start=2, end=3, bending_stiffness=5e4, torsional_stiffness=300.0),
                      rk.LumpedMass(station=3, mass=1.0),
                      rk.ElasticSupport(station=1, stiffness=1e6), rk.ElasticSupport(station=3, stiffness=1e6)])
    M = model.equations().mass_matrix
    values = {sp.Symbol(k, real=True): v for k, v in model.parameters.items()}
    a1, a2 = (model.coordinate_names.index(c) for c in ("alpha1", "alpha2"))
    jl = steel.density * math.pi * 0.05**4 / 32 * 0.3
    assert float(M[a1, a1].xreplace(values)) == pytest.approx(jl / 3, rel=1e-12)
    assert float(M[a1, a2].xreplace(values)) == pytest.approx(jl / 6, rel=1e-12)
