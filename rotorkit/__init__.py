"""rotorkit: compose rotors from physical objects, derive their Lagrange
equations with sympy, compile them and simulate.

>>> import rotorkit
>>> model = rotorkit.preset("al31f")
>>> model.coordinate_names[:3]
('x1', 'x2', 'x3')
"""

import importlib
import sys
import types

from .errors import ParameterError, RotorkitError, SimulationError, TopologyError, UnitError


class _Package(types.ModuleType):
    """rotorkit's module type: ``rotorkit.simulate`` stays the function when its submodule is imported.

    The import system binds every imported submodule to its package's attribute of the same name; for
    ``rotorkit.simulate`` (the submodule) that would hide the function ``simulate``. The binding is dropped
    here instead, so that the function can be looked up lazily like every other name (``import rotorkit``
    and the linear analyses do not load the integration front end, its system and its dataclasses).
    """

    def __setattr__(self, name, value):
        if name == "simulate" and isinstance(value, types.ModuleType):
            return  # the function, resolved by __getattr__ below, keeps the name
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package

#: public name -> the submodule defining it, imported on first access (PEP 562), so that
#: ``import rotorkit`` stays cheap (numpy only): sympy, numba, scipy, pint and matplotlib load when used.
_LAZY = {
    "simulate": "simulate",
    **dict.fromkeys(("BallBearing", "Disk", "ElasticSupport", "LumpedMass", "Maneuver", "Rotor", "RubStator",
                     "ShaftSegment", "BeamSegment", "Material", "LinearBearing", "Pedestal", "SpeedProfile",
                     "BaseRotation", "SqueezeFilmDamper", "JournalBearing", "Rayleigh"), "elements"),
    "ModalDamping": "elements",
    # the linear analyses a user starting from a Model reaches for first
    "campbell": "linear.campbell",
    "Unbalance": "linear.unbalance",
    "unbalance_response": "linear.unbalance",
    "frequency_response": "linear.frf",
    "static_deflection": "linear.static",
    "critical_speed_map": "linear.critical_map",
    "linear_model": "linear.linear_model",
    "LinearModel": "linear.linear_model",
    **dict.fromkeys(("IntershaftRub", "Drive"), "elements"),
    "Model": "model",
    "load_model": "modelfile",
    "preset": "presets",
    "list_presets": "presets",
    "System": "system",
    "available_backends": "system",
    "reduce": "reduction",
    "ReducedSystem": "reduction",
    "PlainJournalBearing": "fluidfilm.plain_journal",
    "Seal": "elements",
    "matched_whirl_modes": "linear.matched_whirl",
    **dict.fromkeys(("Result", "load_result"), "result"),
}


def __getattr__(name):
    if name in _LAZY:
        value = getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
        globals()[name] = value  # later look-ups skip this hook
        return value
    try:  # submodules used as attributes, e.g. rotorkit.analysis after a plain `import rotorkit`
        return importlib.import_module(f"{__name__}.{name}")
    except ModuleNotFoundError as err:
        if err.name != f"{__name__}.{name}":
            raise
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))


__version__ = "0.1.0"

__all__ = [
    "Rotor",
    "Disk",
    "LumpedMass",
    "ShaftSegment",
    "BeamSegment",
    "Material",
    "ElasticSupport",
    "LinearBearing",
    "Pedestal",
    "SpeedProfile",
    "BaseRotation",
    "BallBearing",
    "RubStator",
    "SqueezeFilmDamper",
    "JournalBearing",
    "IntershaftRub",
    "Drive",
    "Maneuver",
    "Rayleigh",
    "ModalDamping",
    "Model",
    "load_model",
    "System",
    "Result",
    "simulate",
    "preset",
    "list_presets",
    "load_result",
    "available_backends",
    "reduce",
    "ReducedSystem",
    "PlainJournalBearing",
    "campbell",
    "Unbalance",
    "unbalance_response",
    "frequency_response",
    "static_deflection",
    "critical_speed_map",
    "linear_model",
    "LinearModel",
    "Seal",
    "matched_whirl_modes",
    "RotorkitError",
    "ParameterError",
    "UnitError",
    "TopologyError",
    "SimulationError",
]
