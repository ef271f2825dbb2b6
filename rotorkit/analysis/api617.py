"""API 617 checks (public entry): the names of :mod:`rotorkit.audit`, importable from the analyses.

See :mod:`rotorkit.audit` and ``docs/api617.md``.
"""

from ..audit.checks import ModeCheck, bearing_stiffness, undamped_critical_map, unbalance_checks
from ..audit.clearance import AmplitudeCheck, ClearanceCheck, amplitude_check
from ..audit.formulas import (
    ANALYSIS_UNBALANCE_MULTIPLE,
    UNBALANCE_CONSTANT,
    AmplificationFactor,
    amplification_factor,
    analysis_unbalance,
    clearance_scale_factor,
    required_separation_margin,
    separation_margin,
    unbalance_magnitude,
    vibration_limit,
    wachel_cross_coupling,
)
from ..audit.placement import Placement, outboard_masses, placements
from ..audit.report import write_report
from ..audit.run import Api617Audit, api617_audit
from ..audit.shear_moment import ShearMoment, shear_moment
from ..audit.stability import Level1Stability, forward_fraction, level1_stability

__all__ = ["UNBALANCE_CONSTANT", "ANALYSIS_UNBALANCE_MULTIPLE", "unbalance_magnitude", "analysis_unbalance",
           "vibration_limit", "clearance_scale_factor", "Placement", "placements", "outboard_masses",
           "AmplitudeCheck", "ClearanceCheck", "amplitude_check", "AmplificationFactor", "amplification_factor",
           "required_separation_margin", "separation_margin", "wachel_cross_coupling", "Level1Stability",
           "level1_stability", "forward_fraction", "ShearMoment", "shear_moment", "ModeCheck", "bearing_stiffness",
           "undamped_critical_map", "unbalance_checks", "Api617Audit", "api617_audit", "write_report"]
