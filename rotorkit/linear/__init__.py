"""Linear analyses of a model or of matrices ``M, C + W G, K + W H``.

One entry for each analysis, importable from here (numpy only at import; scipy,
sympy and matplotlib load when an analysis runs):

- :func:`linear_model`, :class:`LinearModel` (:mod:`~rotorkit.linear.linear_model`): the
  matrices of a model, exact at every speed; built on :mod:`~rotorkit.linear.linear_matrices`
  (the symbolic or cached numeric assembly) and :mod:`~rotorkit.linear.linearize`
  (:func:`static_equilibrium` and :func:`linearize` of a compiled system);
- :func:`natural_frequencies` (:mod:`~rotorkit.linear.modes`): the modes of a compiled system at its
  operating point, as :class:`Modes` (:mod:`~rotorkit.linear.modal`: eigen-solutions, tables,
  whirl from :mod:`~rotorkit.linear.whirl`);
- :func:`campbell` (:mod:`~rotorkit.linear.campbell`): Campbell and stability diagrams;
- :func:`critical_speed_map` (:mod:`~rotorkit.linear.critical_map`);
- :func:`unbalance_response` (:mod:`~rotorkit.linear.unbalance`) and :func:`frequency_response`
  (:mod:`~rotorkit.linear.frf`), both solved by :mod:`~rotorkit.linear.harmonic`;
- :func:`static_deflection` (:mod:`~rotorkit.linear.static`): deflection and bearing reactions.

Helpers: :mod:`~rotorkit.linear.roots` (root bracketing, mode assignment between speeds),
:mod:`~rotorkit.linear.tables` (CSV output of result tables).

These modules lived in :mod:`rotorkit.analysis` before; the old import paths
(``rotorkit.analysis.campbell`` and so on) still give the same modules.
"""

from .campbell import Campbell, campbell
from .critical_map import CriticalSpeedMap, critical_speed_map
from .frf import FRF, frequency_response
from .linear_model import LinearModel, linear_model
from .linearize import linearize, static_equilibrium
from .modal import Modes
from .modes import natural_frequencies
from .static import StaticDeflection, static_deflection
from .unbalance import Unbalance, UnbalanceResponse, unbalance_response

__all__ = [
    "LinearModel",
    "linear_model",
    "linearize",
    "static_equilibrium",
    "Modes",
    "natural_frequencies",
    "Campbell",
    "campbell",
    "CriticalSpeedMap",
    "critical_speed_map",
    "Unbalance",
    "UnbalanceResponse",
    "unbalance_response",
    "FRF",
    "frequency_response",
    "StaticDeflection",
    "static_deflection",
]
