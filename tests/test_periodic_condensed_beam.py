"""Condensed harmonic balance on a stiff beam rotor: the branch passes where its corrector used to stall.

A 13-node beam rotor (52 coordinates, bench/bench_fe.py's rotor) with a rub stator at one
disk, in full annular rub over the range. Its condensed residual was formed as the inverse of the
receptance ``G_cc``; with beam stiffnesses ~1e8 N/m that left a round-off floor near the Newton
tolerance and the branch from 290 rad/s stopped at 301.8 rad/s. The reference is the full (uncondensed)
harmonic balance at the end of the range, an independent solve of the same equations.
"""

from __future__ import annotations

import numpy as np
import pytest

from helpers import load_bench

from rotorkit.analysis.periodic import periodic_response, periodic_solution


def beam_rub_rotor(nodes=13):
    """bench/bench_fe.py's rotor with ``nodes`` beam nodes, its rub stator at the first disk."""
    return load_bench("bench_fe").fe_rotor(nodes, name=f"beamrub{nodes}")


@pytest.mark.slow
def test_condensed_branch_passes_the_former_stall_and_equals_full_harmonic_balance():
    system = beam_rub_rotor().compile()
    station = 13 // 3 + 1
    branch = periodic_response(system, speeds=(290.0, 310.0), harmonics=3, condense=True, stability="none",
                               step=0.03, max_step=0.03)
    assert branch.reason.startswith("parameter bound"), branch.reason
    assert branch.parameter[-1] == pytest.approx(310.0)
    assert np.all(np.diff(branch.parameter) > 0)  # no fold here: the speed grows along the branch
    assert np.all(branch.max_radius(station) > 1e-5)  # full annular rub all along
    full = periodic_solution(system, harmonics=3, condense=False, stability="none", R_speed=310.0,
                             start=branch.coefficients[-1] * 1.01)
    scale = np.max(np.abs(full.coefficients))
    assert np.max(np.abs(branch.coefficients[-1] - full.coefficients[0])) < 1e-8 * scale
    assert branch.max_radius(station)[-1] == pytest.approx(full.max_radius(station)[0], rel=1e-8)


@pytest.mark.parametrize("speed", [123.0, 310.0, 777.0])
def test_prepared_parameters_at_a_new_speed_equal_prepare(speed):
    """The prepared vector at a new speed from the per-branch quadratic in the speed equals ``prepare``."""
    from rotorkit.periodic.evaluate import Evaluator

    system = beam_rub_rotor(4).compile(backend="c")
    evaluator = Evaluator(system)
    evaluator.point({"R_speed": 0.9 * speed})  # the first new speed runs prepare; the fit is made at the second
    got = evaluator.point({"R_speed": speed})
    assert evaluator._fits and all(isinstance(fit, tuple) for fit in evaluator._fits.values())
    p = np.array([system.parameters[name]
                  for name in evaluator._module.PARAMETER_NAMES], dtype=float)
    p[evaluator._index["R_speed"]] = speed
    want = evaluator._prepare(p)
    want[-2:] = evaluator._window
    varying = evaluator._fits[next(iter(evaluator._fits))][1]
    assert varying.size > 0  # gyroscopic terms depend on the speed
    finite = np.isfinite(want)
    assert np.array_equal(finite, np.isfinite(got))
    assert np.all(np.abs(got[finite] - want[finite]) <= 1e-13 * np.maximum(np.abs(want[finite]), 1.0))


def test_cached_mass_matrix_equals_the_constant_part_of_the_derived_one():
    """The generated mass entries (periodic.derived) against the symbolic EquationsOfMotion.linear_mass_matrix."""
    import sympy as sp

    from rotorkit.periodic.hb import HarmonicBalance

    model = beam_rub_rotor(4)
    hb = HarmonicBalance(model.compile(backend="c"), speed_parameter="R_speed", harmonics=1)
    M = model.equations().linear_mass_matrix()
    values = {sp.Symbol(k, real=True): (0.0 if k.endswith("_eccentricity") else v) for k, v in model.parameters.items()}
    want = np.array(M.xreplace(values).evalf(), dtype=float)
    got = hb.mass_matrix(model.parameters)
    assert np.max(np.abs(got - want)) <= 1e-13 * np.max(np.abs(want))
    assert np.count_nonzero(want) > 0
