"""Tapered beam elements (TaperedBeamSegment) against independent solutions and closed forms.

- Equal end diameters: the tapered element's matrices are the uniform
  BeamSegment's (hollow Timoshenko, gyroscopic at speed, axial force).
- Truncated solid cone, Euler-Bernoulli cantilever: natural frequencies from
  an independent shooting solution of ``(E I(z) w'')'' = rho A(z) w^2 w``
  (clamped at the large end, free at the small one).
- Kirchhoff's complete cone cantilever: ``w_1 = 8.719 / L^2 sqrt(E I_0 / (rho A_0))``
  with the base section (Blevins, *Formulas for Natural Frequency and Mode
  Shape*, table 8-8); approached by a cone cut at 0.1 % of its base diameter (8.702 by shooting).
- A fine stepped discretisation into uniform BeamSegments converges to the
  tapered element's frequencies (Timoshenko, hollow).
- The mass matrix carries the segment's mass ``rho pi L (d0^2 + d0 d1 + d1^2) / 12``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg
import scipy.optimize

from rotorkit import ElasticSupport, Model, Rotor
from rotorkit.analysis.linear_matrices import linear_matrices
from rotorkit.elements import BeamSegment, Material, TaperedBeamSegment
from rotorkit.errors import ParameterError
from helpers import Clamp  # noqa: E402

STEEL = Material.steel()
E, RHO = STEEL.youngs_modulus, STEEL.density
PIN = 1e13


def frequencies(model, count=3, floor=1.0):
    """The first ``count`` distinct undamped natural frequencies (rad/s)."""
    M, _, K = linear_matrices(model)
    w = np.sort(np.sqrt(np.abs(scipy.linalg.eigh(K.toarray(), M.toarray(), eigvals_only=True))))
    out = []
    for v in w:
        if v > floor and (not out or v > out[-1] * (1 + 1e-4)):
            out.append(v)
    return np.array(out[:count])


def cantilever(segment):
    return Model([Rotor(name="R", stations=(1, 2), speed=0.0), segment, Clamp(station=1, stiffness=PIN)])


def cone_shooting(length, d0, d1, count):
    """Euler-Bernoulli clamped-free frequencies of a solid truncated cone, by shooting (independent of the FE)."""

    def d(z):
        return d0 + (d1 - d0) * z / length

    def residual(w):
        def rhs(z, y):  # y = (w, w', M = E I w'', V = M')
            dz = d(z)
            area, inertia = math.pi * dz**2 / 4, math.pi * dz**4 / 64
            return [y[1], y[2] / (E * inertia), y[3], RHO * area * w**2 * y[0]]

        ends = []
        for start in ([0, 0, 1, 0], [0, 0, 0, 1]):
            sol = scipy.integrate.solve_ivp(rhs, (0, length), start, rtol=1e-10, atol=1e-14, method="DOP853")
            ends.append(sol.y[2:, -1])
        return np.linalg.det(np.array(ends).T)

    grid = np.linspace(100.0, 6000.0, 60)
    values = [residual(w) for w in grid]
    roots = []
    for a, b, fa, fb in zip(grid, grid[1:], values, values[1:]):
        if fa * fb < 0:
            roots.append(scipy.optimize.brentq(residual, a, b, xtol=1e-10))
        if len(roots) == count:
            break
    return np.array(roots)


def test_equal_end_diameters_give_the_uniform_element():
    common = dict(start=1, end=2, length=0.4, outer_diameter=0.07, inner_diameter=0.03, material=STEEL, elements=2,
                  axial_force=-2e4)
    models = [Model([Rotor(name="R", stations=(1, 2), speed=300.0), segment,
                     ElasticSupport(station=1, stiffness=1e8), ElasticSupport(station=2, stiffness=1e8)])
              for segment in (BeamSegment(**common),
                              TaperedBeamSegment(outer_diameter_end=0.07, inner_diameter_end=0.03, **common))]
    uniform, tapered = (linear_matrices(m) for m in models)
    for a, b in zip(uniform, tapered):  # M, C (gyroscopic), K
        a, b = a.toarray(), b.toarray()
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.abs(a).max())


def test_truncated_cone_cantilever_matches_shooting_solution():
    L, d0, d1 = 1.0, 0.08, 0.04
    segment = TaperedBeamSegment(start=1, end=2, length=L, outer_diameter=d0, outer_diameter_end=d1, material=STEEL,
                                 theory="euler-bernoulli", rotary_inertia=False, elements=8)
    fe, exact = frequencies(cantilever(segment)), cone_shooting(L, d0, d1, 3)
    np.testing.assert_allclose(fe[:2], exact[:2], rtol=2e-4)
    assert fe[2] == pytest.approx(exact[2], rel=1e-3)  # 8 cubic elements: the third mode converges last


def test_complete_cone_cantilever_approaches_kirchhoff():
    L, d0 = 1.0, 0.1
    A0, I0 = math.pi * d0**2 / 4, math.pi * d0**4 / 64
    kirchhoff = 8.719 / L**2 * math.sqrt(E * I0 / (RHO * A0))
    segment = TaperedBeamSegment(start=1, end=2, length=L, outer_diameter=d0, outer_diameter_end=1e-3 * d0,
                                 material=STEEL, theory="euler-bernoulli", rotary_inertia=False, elements=8)
    assert frequencies(cantilever(segment), 1)[0] == pytest.approx(kirchhoff, rel=2e-3)


@pytest.mark.slow
def test_stepped_discretisation_converges_to_tapered_timoshenko():
    L, (a0, a1), (b0, b1) = 0.6, (0.12, 0.06), (0.05, 0.02)
    tapered = frequencies(cantilever(TaperedBeamSegment(
        start=1, end=2, length=L, outer_diameter=a0, outer_diameter_end=a1, inner_diameter=b0, inner_diameter_end=b1,
        material=STEEL, elements=16)), 2)
    stepped = []
    for n in (8, 16):
        elements = [Rotor(name="R", stations=tuple(range(n + 1)), speed=0.0), Clamp(station=0, stiffness=PIN)]
        for i in range(n):
            f = (i + 0.5) / n
            elements.append(BeamSegment(start=i, end=i + 1, length=L / n, outer_diameter=a0 + (a1 - a0) * f,
                                        inner_diameter=b0 + (b1 - b0) * f, material=STEEL))
        stepped.append(frequencies(Model(elements), 2))
    errors = np.abs(np.array(stepped) / tapered - 1)
    assert np.all(errors[1] < errors[0] / 2.5)  # the steps converge (O(h^2)) ...
    limit = (4 * stepped[1] - stepped[0]) / 3  # Richardson
    np.testing.assert_allclose(tapered, limit, rtol=2e-3)  # ... to the tapered element's frequencies


def test_mass_matrix_carries_the_cone_mass():
    segment = TaperedBeamSegment(start=1, end=2, length=0.5, outer_diameter=0.09, outer_diameter_end=0.05,
                                 inner_diameter=0.04, inner_diameter_end=0.02, material=STEEL, elements=3)
    model = Model([Rotor(name="R", stations=(1, 2), speed=0.0), segment, Clamp(station=1, stiffness=PIN)])
    M = linear_matrices(model)[0].toarray()
    ux = np.array([1.0 if name.startswith("x") else 0.0 for name in model.coordinate_names])
    exact = RHO * math.pi * 0.5 / 12 * ((0.09**2 + 0.09 * 0.05 + 0.05**2) - (0.04**2 + 0.04 * 0.02 + 0.02**2))
    assert ux @ M @ ux == pytest.approx(exact, rel=1e-12)
    assert segment.mass_value() == pytest.approx(exact, rel=1e-12)


@pytest.mark.parametrize("kwargs, match", [
    (dict(outer_diameter=0.05, outer_taper=-0.2), r"outer_taper = -0\.2 .* outer diameter of -0\.01 m"),
    (dict(outer_diameter=0.05, inner_diameter=0.01, inner_taper=-0.1), r"inner_taper = -0\.1 .* inner diameter"),
])
def test_taper_making_a_diameter_negative_is_a_named_error(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        TaperedBeamSegment.from_taper(start=1, end=2, length=0.3, material=STEEL, **kwargs)


@pytest.mark.parametrize("kwargs, match", [
    (dict(), r"outer_diameter_end is required"),
    (dict(outer_diameter_end=-0.02), r"outer_diameter_end"),
    (dict(outer_diameter_end=0.03, inner_diameter_end=0.03), r"inner_diameter_end = 0\.03 m must be smaller"),
])
def test_bad_tapered_segment_is_a_named_error(kwargs, match):
    with pytest.raises(ParameterError, match=match):
        TaperedBeamSegment(start=1, end=2, length=0.3, outer_diameter=0.05, inner_diameter=0.01, material=STEEL,
                           **kwargs)


def test_from_taper_gives_the_end_diameters():
    b = TaperedBeamSegment.from_taper(start=1, end=2, length=0.5, outer_diameter=0.06, outer_taper=-0.04,
                                      inner_diameter=0.02, inner_taper=0.01, material=STEEL)
    assert (b.outer_diameter_end, b.inner_diameter_end) == pytest.approx((0.04, 0.025))


def test_tapered_segment_model_file_round_trip():
    from rotorkit.modelfile import dumps_model, loads_model

    model = cantilever(TaperedBeamSegment(start=1, end=2, length=0.5, outer_diameter=0.09, outer_diameter_end=0.05,
                                          inner_diameter=0.02, material=STEEL, axial_force=-1e3))
    model = Model([e for e in model.elements if type(e).__name__ != "Clamp"]
                  + [ElasticSupport(station=1, stiffness=1e8), ElasticSupport(station=2, stiffness=1e8)])
    back, _ = loads_model(dumps_model(model))
    assert back.parameters == model.parameters and back.structure_key == model.structure_key


def test_equal_end_diameters_in_a_turning_base_and_gravity_give_the_uniform_equations():
    from rotorkit import Maneuver
    from rotorkit.elements import BaseRotation

    common = dict(start=1, end=2, length=0.4, outer_diameter=0.07, inner_diameter=0.03, material=STEEL)
    rhs = []
    for segment in (BeamSegment(**common), TaperedBeamSegment(outer_diameter_end=0.07, **common)):
        model = Model([Rotor(name="R", stations=(1, 2), speed=300.0), segment,
                       ElasticSupport(station=1, stiffness=1e8), ElasticSupport(station=2, stiffness=1e8),
                       BaseRotation(rate_y=0.5, rate_x=0.2, center_x=-3.0, axial_positions={1: 0.0}),
                       Maneuver(gravity=9.81)])
        system = model.compile(backend="python")
        y = np.random.default_rng(1).normal(size=system.n_states) * 1e-3
        rhs.append(system.rhs(0.3, y))
    np.testing.assert_allclose(rhs[1], rhs[0], rtol=1e-9, atol=1e-9 * np.abs(rhs[0]).max())


def test_tapered_torsion_integrates_the_polar_moment_along_the_taper():
    """torsion=True: the element's torsional mass ``rho l int I_p(s) N_i N_j ds`` and stiffness ``G int I_p ds / l``
    (linear shape functions ``N = (1 - s, s)``, ``I_p(s) = pi (d_o(s)^4 - d_i^4) / 32``), by quadrature here; for
    equal end diameters the uniform BeamSegment's torsion (``rho I_p l / 3``, ``/ 6``, ``G I_p / l``)."""
    from rotorkit import Disk, LumpedMass, ShaftSegment

    L, d0, d1, di = 0.4, 0.08, 0.05, 0.02

    def torsion_matrices(segment):
        model = Model([Rotor(name="R", stations=(1, 2, 3), speed=0.0), segment,
                       Disk(station=2, mass=5.0, radius=0.1, torsion=True),
                       ShaftSegment(start=2, end=3, bending_stiffness=5e4, torsional_stiffness=300.0),
                       LumpedMass(station=3, mass=1.0),
                       ElasticSupport(station=1, stiffness=1e6), ElasticSupport(station=3, stiffness=1e6)])
        M, _, K = (A.toarray() for A in linear_matrices(model))
        a = [model.coordinate_names.index(c) for c in ("alpha1", "alpha2")]
        return M[np.ix_(a, a)], K[np.ix_(a, a)]

    def polar(s, end):
        return math.pi / 32 * ((d0 + (end - d0) * s) ** 4 - di**4)

    for end in (d1, d0):
        M, K = torsion_matrices(TaperedBeamSegment(start=1, end=2, length=L, outer_diameter=d0,
                                                   outer_diameter_end=end, inner_diameter=di, material=STEEL,
                                                   torsion=True))
        shape = (lambda s: 1 - s, lambda s: s)

        def moment(i, j):
            return scipy.integrate.quad(lambda s: polar(s, end) * shape[i](s) * shape[j](s), 0, 1, epsabs=0,
                                        epsrel=1e-13)[0]

        expected = STEEL.density * L * np.array([[moment(i, j) for j in range(2)] for i in range(2)])
        assert M[0, 0] == pytest.approx(expected[0, 0], rel=1e-12)
        assert M[0, 1] == pytest.approx(expected[0, 1], rel=1e-12) and M[1, 0] == pytest.approx(M[0, 1], rel=1e-14)
        stiffness = STEEL.shear_modulus * scipy.integrate.quad(lambda s: polar(s, end), 0, 1, epsrel=1e-13)[0] / L
        assert K[0, 0] == pytest.approx(stiffness, rel=1e-12) and K[0, 1] == pytest.approx(-stiffness, rel=1e-12)
        if end == d0:
            M_u, K_u = torsion_matrices(BeamSegment(start=1, end=2, length=L, outer_diameter=d0, inner_diameter=di,
                                                    material=STEEL, torsion=True))
            assert np.allclose(M, M_u, rtol=1e-12, atol=0) and np.allclose(K, K_u, rtol=1e-12, atol=0)
            jl = STEEL.density * polar(0.0, d0) * L
            assert M[0, 0] == pytest.approx(jl / 3, rel=1e-12) and M[0, 1] == pytest.approx(jl / 6, rel=1e-12)
