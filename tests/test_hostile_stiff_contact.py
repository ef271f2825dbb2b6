"""Stiff contact whose result changes with the tolerance is flagged without being asked for.

A Jeffcott rotor (2 kg on 2e4 N/m, spin 300 rad/s, unbalance 2e-4 m) against
a stator at 1e-4 m clearance: it presses on the stator all the time. At a
contact stiffness of 1e10-1e11 N/m the step size collapses at every contact
and two successful runs at rtol 1e-6 and 1e-8 differ by several per cent
of the amplitude. Before, ``simulate`` reported plain success; now
``check_convergence="auto"`` (the default) runs the convergence check for a
contact stiffness >= 1e10 N/m and warns with the figure. A soft contact costs
nothing extra (no check).
"""

import re

import numpy as np
import pytest

import rotorkit as rk
from rotorkit.convergence import STIFF_CONTACT, TRUSTED, ConvergenceWarning
from rotorkit.errors import ParameterError

SPAN = (0.0, 0.05)


@pytest.fixture(scope="module")
def system():
    return rk.Model([rk.Rotor(name="R", stations=(1,), speed=300.0),
                     rk.Disk(station=1, mass=2.0, radius=0.1, eccentricity=2e-4, torsion=False),
                     rk.ElasticSupport(station=1, stiffness=2e4, damping=8.0),
                     rk.RubStator(station=1, clearance=1e-4, contact_stiffness=1e6, friction_coefficient=0.0)],
                    name="stiff_contact_jeffcott").compile()


@pytest.mark.parametrize("stiffness", [1e10, 1e11])
def test_stiff_contact_that_depends_on_the_tolerance_is_flagged_with_the_figure(system, stiffness):
    stiff = system.with_parameters(rub1_contact_stiffness=stiffness)
    named = re.escape(f"stiff contact (rub1_contact_stiffness = {stiffness:.0e} N/m): ")
    with pytest.warns(ConvergenceWarning, match=named + r"the result depends on the tolerance; NOT converged: against rtol "
                                                r"1e-08, x1 differs by .* \([\d.]+ % of its amplitude"):
        result = rk.simulate(stiff, SPAN)
    check = result.stats["convergence"]
    assert check["checked_because"] == f"rub1_contact_stiffness = {stiffness:.3g} N/m"
    # the figure, independently: the same run at rtol 1e-8, atol 1e-11
    tight = rk.simulate(stiff, SPAN, rtol=1e-8, atol=1e-11, check_convergence=False)
    difference = np.max(np.abs(result["x1"] - tight["x1"]))
    assert check["difference"] == pytest.approx(difference, rel=1e-9)
    assert difference / np.max(np.abs(tight["x1"])) > TRUSTED  # it does depend on the tolerance
    assert result.stats["success"] and np.max(np.hypot(result["x1"], result["y1"])) > 0.99e-4  # on the stator


def test_soft_contact_is_not_checked_and_the_check_can_be_turned_off(system, recwarn):
    assert "convergence" not in rk.simulate(system, SPAN).stats  # 1e6 N/m: no extra run
    assert system.parameters["rub1_contact_stiffness"] < STIFF_CONTACT
    stiff = system.with_parameters(rub1_contact_stiffness=1e11)
    assert "convergence" not in rk.simulate(stiff, SPAN, check_convergence=False).stats
    assert not [w for w in recwarn if issubclass(w.category, ConvergenceWarning)]
    with pytest.raises(ParameterError, match=r"check_convergence='yes': expected True, False or 'auto'"):
        rk.simulate(stiff, SPAN, check_convergence="yes")
