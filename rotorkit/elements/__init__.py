"""Physical elements: each contributes energy terms and loads to a model."""

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
