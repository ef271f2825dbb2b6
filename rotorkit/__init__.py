"""rotorkit: compose rotors from physical objects, derive their Lagrange
equations with sympy, compile them and simulate.

>>> import rotorkit
>>> model = rotorkit.preset("al31f")
>>> model.coordinate_names[:3]
('x1', 'x2', 'x3')
"""

from .elements import (
    BallBearing,
    Disk,
    ElasticSupport,
    LumpedMass,
    Maneuver,
    Rotor,
    RubStator,
    ShaftSegment,
)
from .errors import ParameterError, RotorkitError, SimulationError, TopologyError, UnitError
from .model import Model
from .modelfile import load_model
from .presets import list_presets, preset
from .result import Result, load_result
from .simulate import simulate
from .system import System, available_backends

__version__ = "0.1.0"

__all__ = [
    "Rotor",
    "Disk",
    "LumpedMass",
    "ShaftSegment",
    "ElasticSupport",
    "BallBearing",
    "RubStator",
    "Maneuver",
    "Model",
    "load_model",
    "System",
    "Result",
    "simulate",
    "preset",
    "list_presets",
    "load_result",
    "available_backends",
    "RotorkitError",
    "ParameterError",
    "UnitError",
    "TopologyError",
    "SimulationError",
]
