"""The analytic Jacobian is generated only when something asks for it (issue 14, fast starts).

An explicit run must not generate it (its start-state stiffness check uses
finite differences of the right-hand side); an implicit run, ``jacobian()``
and the analyses generate it once, in a module of its own, and get the same
numbers as a module generated with the Jacobian (the way it was before).
"""

import numpy as np
import pytest

import rotorkit as rk
from rotorkit import system as system_module
from rotorkit.analysis.stiffness import fastest_rate, finite_difference_jacobian
from rotorkit.codegen import cache
from rotorkit.codegen import generate as generate_module
from rotorkit.elements import BeamSegment, Disk, Material
from rotorkit.symbolic import lagrange
from rotorkit.system import System


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch):
    """An empty disk cache, nothing in memory, and a record of every module generated (its Jacobian flag)."""
    monkeypatch.setenv("ROTORKIT_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(system_module, "_MODULES", {})
    monkeypatch.setattr(lagrange, "_CACHE", {})
    generated = []
    original = generate_module.generate

    def recording(eom, structure_key="", jacobian=True, mode="auto"):
        generated.append((structure_key, jacobian))
        return original(eom, structure_key, jacobian=jacobian, mode=mode)

    monkeypatch.setattr(generate_module, "generate", recording)
    return tmp_path / "cache", generated


def eager(model, codegen):
    """A System on one module holding rhs and jac, as compile_model built it before the Jacobian was lazy."""
    key = f"{model.structure_key}_eager_{codegen}"
    module = cache.store(key, generate_module.generate(model.equations(), key, jacobian=True, mode=codegen).source)
    assert module.HAS_JACOBIAN
    return System(model, module, "python", module.rhs)


def beam_rotor(nodes=8):
    """A beam rotor (compiled with the structured code: matrices for the linear part), a rub at an unbalanced disk."""
    steel = Material.steel()
    stations = tuple(range(1, nodes + 1))
    elements = [rk.Rotor(name="R", stations=stations, speed=300.0)]
    elements += [BeamSegment(start=s, end=s + 1, length=0.05, outer_diameter=0.05, material=steel)
                 for s in stations[:-1]]
    elements += [Disk.from_geometry(station=nodes // 2, width=0.05, inner_diameter=0.05, outer_diameter=0.3,
                                    material=steel, eccentricity=1e-5),
                 rk.RubStator(station=nodes // 2, clearance=2e-5, contact_stiffness=1e7, friction_coefficient=0.2)]
    elements += [rk.ElasticSupport(station=s, stiffness=1e6, damping=50.0) for s in (stations[0], stations[-1])]
    return rk.Model(elements, name="beam")


def states(n, count, seed):
    rng = np.random.default_rng(seed)
    return [rng.normal(size=2 * n) * np.r_[np.full(n, 3e-5), np.full(n, 1e-2)] for _ in range(count)]


def assert_same_jacobians(lazy, reference, ys, times):
    for t in times:
        for y in ys:
            J, J_ref = lazy.jacobian(t, y), reference.jacobian(t, y)
            np.testing.assert_allclose(J, J_ref, rtol=0, atol=1e-12 * np.abs(J_ref).max())


def test_lazy_jacobian_equals_the_eager_one_on_the_preset(fresh_cache):
    folder, generated = fresh_cache
    model = rk.preset("al31f")
    lazy = model.compile(backend="python")
    assert generated == [(model.structure_key, False)]  # the right-hand side alone
    reference = eager(model, "unrolled")
    ys = states(16, 3, 1)
    assert_same_jacobians(lazy, reference, ys, (0.1, 2.7))
    # the Jacobian module's own prepared vector follows the time window and the parameters
    inside = lazy.within(2.5, 3.0)
    assert not np.array_equal(inside.jacobian(0.1, ys[0]), lazy.jacobian(0.1, ys[0]))  # clamped into the roll
    assert_same_jacobians(inside, reference.within(2.5, 3.0), ys, (0.1,))
    changed = inside.with_parameters(LP_speed=900.0, rub2_contact_stiffness=3e7)
    assert_same_jacobians(changed, reference.with_parameters(LP_speed=900.0, rub2_contact_stiffness=3e7).within(
        2.5, 3.0), ys, (0.1, 2.7))
    assert sorted(p.name for p in (folder / "models").iterdir()) == sorted(
        [model.structure_key, model.structure_key + "_jac", model.structure_key + "_eager_unrolled"])
    assert generated.count((model.structure_key + "_jac", True)) == 1  # generated once, for every copy


def test_lazy_jacobian_equals_the_eager_one_on_a_structured_beam_rotor(fresh_cache):
    folder, _ = fresh_cache
    model = beam_rotor()
    lazy = model.compile(backend="python", codegen="structured")
    assert lazy._module.CODEGEN == "structured" and not lazy._module.HAS_JACOBIAN
    ys = states(len(model.coordinate_names), 2, 2)
    rub = model.coordinate_names.index(f"x{model.elements[-3].station}")
    ys[1][rub] = 1e-4  # in contact
    assert_same_jacobians(lazy, eager(model, "structured"), ys, (0.0, 0.3))
    assert (folder / "models" / (model.structure_key + "_structured_jac")).is_dir()


def jeffcott_with_rub():
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=50.0),
                     rk.Disk(station=1, mass=1.0, radius=0.1, eccentricity=1e-4),
                     rk.ElasticSupport(station=1, stiffness=1e4, damping=2.0),
                     rk.RubStator(station=1, clearance=5e-5, contact_stiffness=1e6, friction_coefficient=0.1)])


def test_an_explicit_run_does_not_generate_the_jacobian_an_implicit_one_does(fresh_cache):
    folder, generated = fresh_cache
    model = jeffcott_with_rub()
    system = model.compile(backend="python")
    explicit = rk.simulate(system, (0.0, 0.2), engine="scipy")
    assert explicit.stats["success"]
    assert generated == [(model.structure_key, False)]
    assert [p.name for p in (folder / "models").iterdir()] == [model.structure_key]
    implicit = rk.simulate(system, (0.0, 0.2), method="Radau", engine="scipy")
    assert generated[-1] == (model.structure_key + "_jac", True)
    assert (folder / "models" / (model.structure_key + "_jac")).is_dir()
    assert implicit.stats["njev"] > 0
    before = rk.simulate(eager(model, "unrolled"), (0.0, 0.2), method="Radau", engine="scipy")  # one module
    np.testing.assert_allclose(implicit.y, before.y, rtol=0, atol=1e-9 * np.abs(before.y).max())
    np.testing.assert_allclose(implicit.y, explicit.y, rtol=0, atol=1e-2 * np.abs(explicit.y).max())


@pytest.mark.parametrize("case", ["preset at rest", "preset in contact", "beam rotor"])
def test_finite_difference_spectral_radius_equals_the_analytic_one(case):
    if case == "beam rotor":
        system = beam_rotor().compile(backend="python", codegen="structured").within(0.0, 1.0)
        y = states(len(system.coordinate_names), 1, 3)[0]
        t = 0.2
    else:
        system = rk.preset("al31f").compile(backend="python").within(2.0, 3.0)
        y, t = np.zeros(32), 2.0
        if case == "preset in contact":
            y = states(16, 1, 4)[0]
            y[1], y[8] = 2.0 * 1.34e-4, 0.5 * 1.34e-4  # the rub engaged
    J = finite_difference_jacobian(system, t, y)
    exact = fastest_rate(system.jacobian(t, y, compiled=False))
    assert abs(fastest_rate(J) / exact - 1) < 1e-4
    assert exact > 1e3  # a stiff enough rate to mean something (1/s)
