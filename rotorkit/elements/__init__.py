"""Physical elements: each contributes energy terms and loads to a model."""

from .base import Element, Terms
from .bearing import BallBearing
from .maneuver import Maneuver
from .masses import Disk, LumpedMass
from .rotor import Rotor
from .rub import RubStator
from .shaft import ShaftSegment
from .speed import SpeedProfile
from .support import ElasticSupport

__all__ = [
    "Element",
    "Terms",
    "Rotor",
    "Disk",
    "LumpedMass",
    "ShaftSegment",
    "ElasticSupport",
    "BallBearing",
    "RubStator",
    "Maneuver",
    "SpeedProfile",
]
