"""Fluid-film bearings from their geometry: finite-difference Reynolds solutions and the coefficients they give.

- :mod:`rotorkit.fluidfilm.reynolds`: the Reynolds equation of a plain journal bearing on the unwrapped film, with
  the Reynolds (Swift-Stieber) cavitation condition as a complementarity problem;
- :mod:`rotorkit.fluidfilm.plain_journal`: :class:`PlainJournalBearing`, its static equilibrium under a load and the
  eight stiffness and damping coefficients against speed, handed to
  :class:`~rotorkit.elements.linear_bearing.LinearBearing`;
- :mod:`rotorkit.fluidfilm.published`: the published tables it is verified against (Someya, Raimondi & Boyd) and
  this film's quantities in their conventions.

The nonlinear short-bearing film (for time simulation) is the element
:class:`~rotorkit.elements.journal_bearing.JournalBearing`; both agree at small ``L / D``.
"""

import importlib

__all__ = ["PlainJournalBearing", "BearingCoefficients", "FilmGrid", "FilmSolution", "solve_film"]

_LAZY = {"PlainJournalBearing": "plain_journal", "BearingCoefficients": "plain_journal", "FilmGrid": "reynolds",
         "FilmSolution": "reynolds", "solve_film": "reynolds"}


def __getattr__(name):
    if name in _LAZY:
        return getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
