"""The linear matrices kept in the model cache, and speed-dependent coefficients evaluated exactly at every speed.

References: the matrices derived symbolically in this process
(``symbolic_linear_evaluator``: the derived equations with the numbers
substituted), a linear model built at each speed on its own (exact there,
whatever the speed dependence), and a Jeffcott rotor on a tabulated
bearing whose response has a closed form.
"""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from rotorkit import Disk, Model, Rotor
from rotorkit.analysis.campbell import campbell
from rotorkit.analysis.linear_matrices import linear_evaluator, symbolic_linear_evaluator
from rotorkit.analysis.linear_model import LinearModel, SpeedTerms, linear_model
from rotorkit.analysis.unbalance import Unbalance, unbalance_response
from rotorkit.elements import BeamSegment, LinearBearing, Material
from rotorkit.errors import ParameterError

ROOT = Path(__file__).resolve().parents[1]
SPEEDS = [0.0, 300.0, 700.0, 1200.0]


def beam_rotor(cross=True):
    """Three beam elements, two disks, a tabulated anisotropic bearing (cross-coupled) and a constant one."""
    steel = Material(density=7850.0, youngs_modulus=2.1e11, shear_modulus=8.1e10)
    elements = [Rotor(name="R", stations=(1, 2, 3, 4), speed=500.0)]
    elements += [BeamSegment(start=s, end=s + 1, length=0.2, outer_diameter=0.05, material=steel) for s in (1, 2, 3)]
    elements += [Disk(station=2, mass=8.0, polar_inertia=0.08, diametral_inertia=0.04),
                 Disk(station=3, mass=5.0, polar_inertia=0.05, diametral_inertia=0.025)]
    cross_terms = dict(kxy=[0.0, 2e6, 5e6], kyx=[0.0, -2e6, -5e6]) if cross else {}
    elements.append(LinearBearing.tabulated(station=1, speeds=[0.0, 400.0, 1000.0], kxx=[1e7, 2e7, 3e7],
                                            kyy=[8e6, 1.2e7, 2.5e7], cxx=[2e3, 1.5e3, 1e3], cyy=[2e3, 1.6e3, 1.2e3],
                                            **cross_terms))
    elements.append(LinearBearing(station=4, kxx=1.5e7, kyy=1e7, cxx=800.0, cyy=800.0))
    return Model(elements, name="beam_rotor")


def test_cached_matrices_equal_the_symbolic_ones():
    model = beam_rotor()
    cached = linear_evaluator(model, free=("R_speed",))
    symbolic = symbolic_linear_evaluator(model, free=("R_speed",))
    for w in SPEEDS:
        for A, B in zip(cached(R_speed=w), symbolic(R_speed=w)):
            A, B = A.toarray(), B.toarray()
            assert np.any(B != 0)
            np.testing.assert_allclose(A, B, rtol=1e-13, atol=1e-13 * np.abs(B).max())
    # the tabulated entries (kxx, kyy, cxx, cyy, kxy, kyx of the bearing) are the ones not affine in the speed
    assert cached.nonaffine.sum() == 6


def test_other_parameter_values_and_free_parameters_come_from_the_same_cached_templates():
    model = beam_rotor(cross=False)
    values = dict(model.parameters, beam1_2_outer_diameter=0.06, disk2_mass=11.0, linearbearing4_kxx=3e7)
    cached = linear_evaluator(model, values=values, free=("disk3_mass",))
    symbolic = symbolic_linear_evaluator(model, values=values, free=("disk3_mass",))
    for mass in (1.0, 7.0):
        for A, B in zip(cached(disk3_mass=mass), symbolic(disk3_mass=mass)):
            np.testing.assert_allclose(A.toarray(), B.toarray(), rtol=1e-13, atol=1e-13 * abs(B).max())


def test_unbalance_response_with_speed_dependent_bearings_equals_one_linear_model_per_speed():
    model = beam_rotor()
    speeds = np.linspace(50.0, 1200.0, 12)
    unbalance = [Unbalance(station=2, magnitude=1e-4, angle=0.3), Unbalance(station=3, magnitude=5e-5)]
    swept = unbalance_response(model, unbalance, speeds)
    first_order = unbalance_response(model, unbalance, speeds, speed_dependence="first-order")
    worst = 0.0
    for k, w in enumerate(speeds):
        # a linear model built at w (first order about w is exact at w itself)
        at_w = linear_model(model, speed=w, speed_dependence="first-order")
        Q = unbalance_response(at_w, unbalance, [w]).components["R"][0]
        np.testing.assert_allclose(swept.components["R"][k], Q, rtol=0, atol=1e-10 * np.abs(Q).max())
        worst = max(worst, np.abs(first_order.components["R"][k] - Q).max() / np.abs(Q).max())
    assert worst > 1e-2  # the expansion about one speed is not exact elsewhere: the check above can fail


def test_jeffcott_on_a_tabulated_bearing_against_the_closed_form():
    """x'' m + c(W) x' + k(W) x = U W^2 cos(W t): |X| = U W^2 / |k(W) - m W^2 + i W c(W)|, tables interpolated."""
    m, u = 4.0, 2e-5
    table = dict(kxx=[1e5, 4e5, 6e5], kyy=[1e5, 4e5, 6e5], cxx=[60.0, 20.0, 10.0], cyy=[60.0, 20.0, 10.0])
    model = Model([Rotor(name="R", stations=(1,), speed=100.0), Disk(station=1, mass=m, radius=0.1),
                   LinearBearing.tabulated(station=1, speeds=[0.0, 300.0, 500.0], **table)], name="jeffcott_table")
    speeds = np.array([50.0, 150.0, 290.0, 310.0, 420.0, 600.0])
    response = unbalance_response(model, [Unbalance(station=1, magnitude=u)], speeds)
    k = np.interp(speeds, [0.0, 300.0, 500.0], table["kxx"])
    c = np.interp(speeds, [0.0, 300.0, 500.0], table["cxx"])
    expected = u * speeds**2 / np.abs(k - m * speeds**2 + 1j * speeds * c)
    np.testing.assert_allclose(response.amplitude("x1"), expected, rtol=1e-12)


def test_linear_model_matrices_modes_and_campbell_are_exact_at_each_speed():
    model = beam_rotor()
    linear = linear_model(model, speed=600.0)
    assert linear.speed_terms is not None
    evaluator = linear_evaluator(model, free=("R_speed",))
    for w in SPEEDS:
        M, C, K = (A.toarray() for A in evaluator(R_speed=w))
        _, C2, K2 = linear.matrices(w)
        np.testing.assert_allclose(C2, C, rtol=0, atol=1e-9 * np.abs(C).max())
        np.testing.assert_allclose(K2, K, rtol=0, atol=1e-9 * np.abs(K).max())
        A = linear.state_matrix(w)
        n = linear.n
        np.testing.assert_allclose(M @ A[n:, :n], -K, rtol=0, atol=1e-8 * np.abs(K).max())
    grid = np.linspace(0.0, 1200.0, 9)
    from_model = campbell(model, grid, n_modes=4, refine=False)
    from_linear = campbell(linear, grid, n_modes=4, refine=False)
    np.testing.assert_allclose(from_linear.frequencies, from_model.frequencies, rtol=1e-9)


def test_first_order_is_asked_for_by_name():
    model = beam_rotor()
    assert linear_model(model, speed_dependence="first-order").speed_terms is None
    with pytest.raises(ParameterError, match=r"speed_dependence='second-order' is unknown.*'exact' or 'first-order'"):
        linear_model(model, speed_dependence="second-order")


def test_a_constant_bearing_model_has_no_speed_terms():
    model = beam_rotor(cross=False)
    model = Model([e for e in model.elements if not (isinstance(e, LinearBearing) and e.speeds is not None)]
                  + [LinearBearing(station=1, kxx=1e7, kyy=1e7)], name="constant_bearings")
    assert linear_model(model).speed_terms is None


@pytest.mark.parametrize("bad, message", [
    ("terms", r"speed_terms='terms' is invalid: expected a SpeedTerms of 2 coordinates"),
    (SpeedTerms(n=3, matrix=np.array([2]), rows=np.array([0]), cols=np.array([0]), values=lambda w: [w]),
     r"speed_terms=SpeedTerms\(n=3.*is invalid: expected a SpeedTerms of 2 coordinates"),
])
def test_bad_speed_terms_are_refused(bad, message):
    with pytest.raises(ParameterError, match=message):
        LinearModel(mass=np.eye(2), damping=None, stiffness=np.eye(2), speed_terms=bad)


_WARM = """
import numpy as np
import rotorkit.symbolic.lagrange as lagrange
calls = []
for name in ("derive", "_derive", "element_matrices"):
    original = getattr(lagrange, name)
    def counted(*args, _original=original, _name=name, **kwargs):
        calls.append(_name)
        return _original(*args, **kwargs)
    setattr(lagrange, name, counted)
import rotorkit as rk
from rotorkit.analysis.campbell import campbell
from rotorkit.analysis.unbalance import unbalance_response
from rotorkit.codegen.linear_cache import equations_text
model = rk.load_model({path!r})
campbell(model, np.linspace(0.0, 1000.0, 5), n_modes=4)
unbalance_response(model, [(2, 1e-4, 0.0)], np.linspace(10.0, 1000.0, 7))
equations_text(model)
print("CALLS", len(calls))
"""


def test_a_warm_process_does_not_derive(tmp_path):
    path = beam_rotor().save(tmp_path / "rotor.toml")
    env = dict(os.environ, ROTORKIT_CACHE_DIR=str(tmp_path / "cache"), PYTHONPATH=str(ROOT))
    script = textwrap.dedent(_WARM).format(path=str(path))
    counts = []
    for _ in range(2):
        out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, cwd=ROOT,
                             timeout=600)
        assert out.returncode == 0, out.stderr
        counts.append(int(out.stdout.split("CALLS")[-1]))
    assert counts[0] >= 1  # the cold process derives (the count sees it)
    assert counts[1] == 0  # the warm one reads the cache


def test_static_deflection_of_a_linear_model_is_solved_from_the_cached_matrices():
    """K q = F without compiling: equals the compiled system's equilibrium, and the reactions carry the weight."""
    from rotorkit import Maneuver
    from rotorkit.analysis.static import static_deflection

    model = Model(list(beam_rotor().elements) + [Maneuver.steady(gravity=9.81)], name="beam_rotor_gravity")
    direct = static_deflection(model)
    compiled = static_deflection(model.compile(backend="python"))
    names = model.coordinate_names
    scale = max(abs(v) for v in compiled.deflection.values())
    for name in names:
        assert direct.deflection[name] == pytest.approx(compiled.deflection[name], abs=1e-7 * scale)
    weight = 9.81 * (8.0 + 5.0 + 7850.0 * np.pi * 0.05**2 / 4 * 0.6)
    lift = sum(f for forces in direct.reactions.values() for c, f in forces.items() if c.startswith("y"))
    assert lift == pytest.approx(weight, rel=1e-9)
    assert set(direct.reactions) == set(compiled.reactions) == {"linearbearing1", "linearbearing4"}
    for label, forces in compiled.reactions.items():
        for c, f in forces.items():
            assert direct.reactions[label].get(c, 0.0) == pytest.approx(f, rel=1e-6, abs=1e-9 * weight)


def test_frequency_response_with_speed_dependent_bearings_is_exact_at_its_speed():
    from rotorkit.analysis.frf import frequency_response

    model = beam_rotor()
    linear = linear_model(model, speed=200.0)  # built far from the speed of the FRF
    frequencies = np.linspace(10.0, 2000.0, 7)
    for method in ("banded", "dense"):
        frf = frequency_response(linear, frequencies, speed=900.0, inputs=["x2"], outputs=["x2", "y3"], method=method)
        at_900 = linear_model(model, speed=900.0, speed_dependence="first-order")  # exact at 900 itself
        ref = frequency_response(at_900, frequencies, speed=900.0, inputs=["x2"], outputs=["x2", "y3"], method=method)
        np.testing.assert_allclose(frf.values, ref.values, rtol=0, atol=1e-10 * np.abs(ref.values).max())


def test_the_compressor_example_is_the_rotor_of_the_benchmark():
    import rotorkit as rk

    model = rk.load_model(ROOT / "examples" / "compressor.toml")
    assert len(model.coordinate_names) == 80
    kinds = [type(e).__name__ for e in model.elements]
    assert kinds.count("BeamSegment") == 19 and kinds.count("Disk") == 4 and kinds.count("LinearBearing") == 2
    bearings = [e for e in model.elements if isinstance(e, LinearBearing)]
    assert all(b.speeds is not None and b.kxx != b.kyy for b in bearings)  # tabulated, anisotropic
    assert sum(b.kxy is not None for b in bearings) == 1  # one cross-coupled
    assert model.parameters["R_speed"] == pytest.approx(10000 * 2 * np.pi / 60)
