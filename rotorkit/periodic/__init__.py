"""Periodic steady states of nonlinear rotors: harmonic balance, continuation, stability.

- :mod:`rotorkit.periodic.hb`: the harmonic-balance residual with AFT and its analytic Jacobian, damped Newton;
- :mod:`rotorkit.periodic.continuation`: pseudo-arclength continuation in any parameter;
- :mod:`rotorkit.periodic.stability`: Floquet multipliers (monodromy matrix, Hill's method), bifurcations;
- :mod:`rotorkit.periodic.crossings`: where a multiplier leaves the unit circle between two points;
- :mod:`rotorkit.periodic.switching`: the switch onto the period-doubled branch at a period doubling;
- :mod:`rotorkit.periodic.branch`: the :class:`Branch` result.

The user entry is :mod:`rotorkit.analysis.periodic`. Nothing heavy is imported here.
"""

from .errors import ConvergenceError, NoOscillatingInput

__all__ = ["ConvergenceError", "NoOscillatingInput"]
