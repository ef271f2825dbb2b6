"""Physical elements: each contributes energy terms and loads to a model.

The element modules load on first use of their names (PEP 562): reading a model
file imports only the modules of the types it holds.
"""

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # the names for static tools (the API docs, type checkers); at run time __getattr__ imports them
    from .base import Element, Terms
    from .base_motion import BaseRotation
    from .beam import BeamSegment
    from .bearing import BallBearing
    from .journal_bearing import JournalBearing
    from .damping import ModalDamping, Rayleigh
    from .linear_bearing import LinearBearing
    from .maneuver import Maneuver
    from .masses import Disk, DiskGeometry, LumpedMass
    from .pedestal import Pedestal
    from .material import Material
    from .rotor import Rotor
    from .rub import RubStator
    from .shaft import ShaftSegment
    from .intershaft_rub import IntershaftRub
    from .drive import Drive
    from .speed import SpeedProfile
    from .squeeze_film import SqueezeFilmDamper
    from .support import ElasticSupport
    from .tapered import TaperedBeamSegment
    from .seal import Seal

#: public name -> the submodule defining it, imported on first access
TYPE_MODULES = {
    "Element": "base",
    "Terms": "base",
    "BaseRotation": "base_motion",
    "BeamSegment": "beam",
    "BallBearing": "bearing",
    "JournalBearing": "journal_bearing",
    "Rayleigh": "damping",
    "ModalDamping": "damping",
    "LinearBearing": "linear_bearing",
    "Maneuver": "maneuver",
    "Disk": "masses",
    "DiskGeometry": "masses",
    "LumpedMass": "masses",
    "Pedestal": "pedestal",
    "Material": "material",
    "Rotor": "rotor",
    "RubStator": "rub",
    "ShaftSegment": "shaft",
    "IntershaftRub": "intershaft_rub",
    "Drive": "drive",
    "SpeedProfile": "speed",
    "SqueezeFilmDamper": "squeeze_film",
    "ElasticSupport": "support",
    "TaperedBeamSegment": "tapered",
    "Seal": "seal",
}


def __getattr__(name):
    if name in TYPE_MODULES:
        value = getattr(importlib.import_module(f"{__name__}.{TYPE_MODULES[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))


__all__ = [
    "Element",
    "Terms",
    "Material",
    "BeamSegment",
    "TaperedBeamSegment",
    "Rotor",
    "Rayleigh",
    "ModalDamping",
    "Disk",
    "DiskGeometry",
    "LumpedMass",
    "ShaftSegment",
    "ElasticSupport",
    "BallBearing",
    "RubStator",
    "Maneuver",
    "SpeedProfile",
    "LinearBearing",
    "Pedestal",
    "BaseRotation",
    "SqueezeFilmDamper",
    "JournalBearing",
    "IntershaftRub",
    "Drive",
    "Seal",
]
