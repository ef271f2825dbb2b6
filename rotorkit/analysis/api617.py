"""API 617 checks (public entry): the names of :mod:`rotorkit.audit`, importable from the analyses.

See :mod:`rotorkit.audit` and ``docs/api617.md``.
"""

from ..audit.checks import ModeCheck, bearing_stiffness, undamped_critical_map, unbalance_checks
from ..audit.formulas import (
    UNBALANCE_CONSTANT,
    AmplificationFactor,
    amplification_factor,
    required_separation_margin,
    separation_margin,
    unbalance_magnitude,
    wachel_cross_coupling,
)
from ..audit.report import write_report
from ..audit.run import Api617Audit, api617_audit
from ..audit.shear_moment import ShearMoment, shear_moment
from ..audit.stability import Level1Stability, forward_fraction, level1_stability

__all__ = ["UNBALANCE_CONSTANT", "unbalance_magnitude", "AmplificationFactor", "amplification_factor",
           "required_separation_margin", "separation_margin", "wachel_cross_coupling", "Level1Stability",
           "level1_stability", "forward_fraction", "ShearMoment", "shear_moment", "ModeCheck", "bearing_stiffness",
           "undamped_critical_map", "unbalance_checks", "Api617Audit", "api617_audit", "write_report"]
