"""Analyses of models that are neither signal processing nor linear: energy, stiffness, loads, periodic.

- :mod:`rotorkit.analysis.energy`: energy balance along a run;
- :mod:`rotorkit.analysis.stiffness`: time scales and the integration method that fits;
- :mod:`rotorkit.analysis.loads`: the manoeuvre load on a station;
- :mod:`rotorkit.analysis.periodic`: periodic solutions, responses and branches
  (the entry to :mod:`rotorkit.periodic`).

Signal processing lives in :mod:`rotorkit.signals`, the linear analyses
(modes, Campbell, unbalance response, FRFs, static deflection, critical speed
map, linear models) in :mod:`rotorkit.linear`. Their old import paths keep
working: ``rotorkit.analysis.campbell`` *is* the module
``rotorkit.linear.campbell`` (same object, see :data:`MOVED`),
``rotorkit.analysis.signals`` is the package :mod:`rotorkit.signals`, and
:mod:`rotorkit.analysis.modes` still re-exports what it used to. The signal
functions stay importable from here, as before.
"""

import importlib
import importlib.abc
import importlib.util
import sys

from ..signals import (
    DEFAULT_RATIOS,
    FREQUENCY_UNITS,
    OrderLabel,
    Peak,
    Spectrum,
    TimeFrequency,
    amplitude_at,
    amplitude_spectrum,
    find_peaks,
    highpass,
    label_orders,
    stft,
)

__all__ = [
    "DEFAULT_RATIOS",
    "FREQUENCY_UNITS",
    "Spectrum",
    "TimeFrequency",
    "Peak",
    "OrderLabel",
    "highpass",
    "amplitude_spectrum",
    "stft",
    "find_peaks",
    "label_orders",
    "amplitude_at",
]

#: old module path -> its new home; importing the old path gives the new module itself
MOVED = {
    **{f"{__name__}.{name}": f"rotorkit.linear.{name}"
       for name in ("campbell", "critical_map", "frf", "harmonic", "linear_matrices", "linear_model", "linearize",
                    "modal", "roots", "static", "tables", "unbalance", "whirl")},
    f"{__name__}.signals": "rotorkit.signals",
}


class _MovedModules(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Import a moved module's old path as the module at its new path (one module object, not a copy)."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname in MOVED:
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec):
        module = importlib.import_module(MOVED[spec.name])
        spec.loader_state = module.__spec__  # the import machinery sets __spec__ to the alias's spec ...
        return module

    def exec_module(self, module):
        module.__spec__ = module.__spec__.loader_state  # ... which is put back here: the module is already run


if not any(type(finder).__qualname__ == _MovedModules.__qualname__ for finder in sys.meta_path):  # once, reload too
    sys.meta_path.insert(0, _MovedModules())


def __getattr__(name):  # rotorkit.analysis.campbell as an attribute, without an import statement
    if f"{__name__}.{name}" in MOVED:
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
