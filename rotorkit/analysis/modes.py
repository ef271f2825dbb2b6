"""Old path of the modal analysis, kept for existing code: re-exports its former names.

:func:`natural_frequencies` now lives in :mod:`rotorkit.linear.modes`,
:func:`static_equilibrium` and :func:`linearize` in :mod:`rotorkit.linear.linearize`,
:class:`Modes` in :mod:`rotorkit.linear.modal`, :class:`LinearModel` and
:func:`linear_model` in :mod:`rotorkit.linear.linear_model`, :class:`Campbell`
and :func:`campbell` in :mod:`rotorkit.linear.campbell`.
"""

from ..linear.campbell import Campbell, campbell
from ..linear.linear_model import LinearModel, linear_model
from ..linear.linearize import (
    DEFAULT_CAGE_SAMPLES,
    DEFAULT_EQUILIBRIUM_TOL,
    DEFAULT_RELATIVE_STEP,
    linearize,
    static_equilibrium,
)
from ..linear.modal import Modes
from ..linear.modes import averaged_jacobian, natural_frequencies

__all__ = [
    "Modes",
    "Campbell",
    "LinearModel",
    "static_equilibrium",
    "linearize",
    "linear_model",
    "natural_frequencies",
    "averaged_jacobian",
    "campbell",
    "DEFAULT_CAGE_SAMPLES",
    "DEFAULT_EQUILIBRIUM_TOL",
    "DEFAULT_RELATIVE_STEP",
]
