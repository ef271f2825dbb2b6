"""The convergence check (rotorkit.convergence) against exact solutions and a known unconverged case."""

import math

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.convergence import ConvergenceWarning, check_convergence
from rotorkit.errors import ParameterError

MASS, STIFFNESS, DAMPING = 2.0, 2.0e4, 8.0  # wn = 100 rad/s, zeta = 0.02


def free_decay():
    model = rk.Model([rk.Rotor(name="R", stations=(1,), speed=0.0),
                      rk.Disk(station=1, mass=MASS, radius=0.1, torsion=False),
                      rk.ElasticSupport(station=1, stiffness=STIFFNESS, damping=DAMPING)], name="decay")
    return model.compile()


def exact_x(t, x0):
    wn = math.sqrt(STIFFNESS / MASS)
    zeta = DAMPING / (2 * math.sqrt(STIFFNESS * MASS))
    wd = wn * math.sqrt(1 - zeta**2)
    return x0 * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))


@pytest.mark.parametrize("rtol", [1e-4, 1e-6])
def test_the_difference_to_the_tighter_run_is_the_true_error(rtol):
    system = free_decay()
    x0 = 1e-3
    y0 = system.initial_state(x1=x0)
    result = rk.simulate(system, (0.0, 2.0), y0=y0, rtol=rtol, atol=1e-3 * rtol * x0, check_convergence=True)
    stats = result.stats["convergence"]
    true_error = np.max(np.abs(result["x1"] - exact_x(result.t, x0)))
    assert stats["worst"] == "x1"
    assert true_error > 0
    # the reference run is 100 times more accurate: the difference is the run's own error
    assert stats["difference"] == pytest.approx(true_error, rel=0.1)
    assert stats["relative_difference"] == pytest.approx(true_error / x0, rel=0.1)
    assert stats["converged"]


def test_very_stiff_contact_is_flagged_as_not_converged():
    system = rk.preset("al31f", rub_stiffness=1e10).compile()
    with pytest.warns(ConvergenceWarning, match="NOT converged"):
        result = rk.simulate(system, (0.0, 0.2), atol=1e-12, check_convergence=True)
    assert result.stats["success"]
    assert result.stats["convergence"]["relative_difference"] > 0.1
    assert not result.stats["convergence"]["converged"]


def test_factor_must_tighten():
    system = free_decay()
    result = rk.simulate(system, (0.0, 0.1), y0=system.initial_state(x1=1e-3))
    with pytest.raises(ParameterError, match="factor"):
        check_convergence(system, result, factor=1.0)


def test_cli_run_reports_the_check(tmp_path, capsys):
    import json

    from rotorkit.cli import main

    assert main(["run", "al31f", "--t-end", "0.05", "--out", str(tmp_path), "--check-convergence"]) == 0
    assert "convergence check: converged: against rtol 1e-08" in capsys.readouterr().out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert "convergence" in json.dumps(summary)
