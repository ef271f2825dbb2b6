"""API 617 audit of a rotor: the formulas, the lateral checks, shear and moment, the HTML report.

- :mod:`rotorkit.audit.formulas`: unbalance magnitude ``6350 W / N`` and
  the analysis' multiple of it (2), amplification factor (half-power
  bandwidth), separation margins, the probes' vibration limit ``A_vl`` and
  the close-clearance scale factor, the Wachel cross-coupling ``Q_A``;
- :mod:`rotorkit.audit.placement`: where each mode's unbalance goes;
- :mod:`rotorkit.audit.clearance`: the amplitudes at the probes and at the
  close clearances;
- :mod:`rotorkit.audit.stability`: Level I stability (log decrement against
  the applied cross-coupling, ``Q_0``);
- :mod:`rotorkit.audit.shear_moment`: shear force and bending moment
  diagrams from the static solution;
- :mod:`rotorkit.audit.checks`: critical speed map with the bearing curves,
  the unbalance response of each mode;
- :mod:`rotorkit.audit.run`: :func:`api617_audit`, everything at once;
- :mod:`rotorkit.audit.report`: the self-contained HTML report.

The public entry is also :mod:`rotorkit.analysis.api617`. Names load on use.
"""

import importlib

__all__ = ["UNBALANCE_CONSTANT", "ANALYSIS_UNBALANCE_MULTIPLE", "unbalance_magnitude", "analysis_unbalance",
           "vibration_limit", "clearance_scale_factor", "Placement", "placements", "outboard_masses",
           "AmplitudeCheck", "ClearanceCheck", "amplitude_check", "AmplificationFactor", "amplification_factor",
           "required_separation_margin", "separation_margin", "wachel_cross_coupling", "Level1Stability",
           "level1_stability", "ShearMoment", "shear_moment", "ModeCheck", "Api617Audit", "api617_audit",
           "write_report"]

_WHERE = {"UNBALANCE_CONSTANT": "formulas", "ANALYSIS_UNBALANCE_MULTIPLE": "formulas",
          "analysis_unbalance": "formulas", "vibration_limit": "formulas", "clearance_scale_factor": "formulas",
          "Placement": "placement", "placements": "placement", "outboard_masses": "placement",
          "AmplitudeCheck": "clearance", "ClearanceCheck": "clearance", "amplitude_check": "clearance",
          "unbalance_magnitude": "formulas", "AmplificationFactor": "formulas",
          "amplification_factor": "formulas", "required_separation_margin": "formulas",
          "separation_margin": "formulas", "wachel_cross_coupling": "formulas", "Level1Stability": "stability",
          "level1_stability": "stability", "ShearMoment": "shear_moment", "shear_moment": "shear_moment",
          "ModeCheck": "checks", "Api617Audit": "run", "api617_audit": "run", "write_report": "report"}


def __getattr__(name):
    if name in _WHERE:
        return getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
