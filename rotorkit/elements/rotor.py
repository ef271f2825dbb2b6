"""Rotor (spool): a set of stations spinning at one speed."""

import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, TopologyError
from .base import Element, Terms

__all__ = ["Rotor", "check_station"]


def check_station(owner, station, field="station"):
    """Return ``station`` as a valid label (int >= 0 or identifier), or raise naming ``field``."""
    if isinstance(station, numbers.Integral) and not isinstance(station, (bool, np.bool_)) and station >= 0:
        return int(station)
    if isinstance(station, str) and station.isidentifier():
        return station
    raise ParameterError(f"{owner}: {field} = {station!r}: expected a station (a non-negative int or an identifier string)")


@dataclass(frozen=True, slots=True, kw_only=True)
class Rotor(Element):
    """A rotor (spool): stations that spin together at a constant speed.

    Give either ``speed`` or ``speed_ratio`` with ``reference`` (the name of
    another rotor): the HP spool of a dual rotor spins at
    ``speed_ratio * speed(reference)``.

    Parameters
    ----------
    name : str
        Rotor name, e.g. ``"LP"``; parameters are ``<name>_speed`` or
        ``<name>_speed_ratio``.
    stations : tuple of int or str
        Stations on this rotor, in axial order. Each station gets the
        bending coordinates ``x<station>``, ``y<station>``.
    speed : float or pint.Quantity, optional
        Spin speed (rad/s).
    speed_ratio : float, optional
        Speed relative to ``reference``.
    reference : str, optional
        Name of the rotor ``speed_ratio`` refers to.

    Examples
    --------
    >>> lp = Rotor(name="LP", stations=(1, 2, 3), speed=1500.0)
    >>> hp = Rotor(name="HP", stations=(7,), speed_ratio=1.8, reference="LP")
    >>> hp.attached_stations()
    (7,)
    """

    stations: tuple = ()
    speed: float | None = None
    speed_ratio: float | None = None
    reference: str | None = None

    _units = {"speed": ("rad/s", None), "speed_ratio": ("", "positive")}
    _latex_names = {"speed": r"\Omega", "speed_ratio": r"\gamma"}

    def __post_init__(self):
        if isinstance(self.stations, (str, numbers.Integral)):
            object.__setattr__(self, "stations", (self.stations,))
        elif isinstance(self.stations, (tuple, list, range)):
            object.__setattr__(self, "stations", tuple(self.stations))
        else:
            raise ParameterError(f"Rotor {self.name!r}: stations = {self.stations!r}: expected a tuple of stations, "
                                 "e.g. (1, 2, 3)")
        object.__setattr__(self, "stations", tuple(check_station(f"Rotor {self.name!r}", st, "stations")
                                                   for st in self.stations))
        Element.__post_init__(self)

    def _validate(self):
        if self.name is None:
            raise ParameterError("Rotor.name is required, e.g. Rotor(name='LP', ...)")
        if not self.stations:
            raise ParameterError(f"Rotor {self.name!r}: stations is empty; give at least one station")
        if len(set(self.stations)) != len(self.stations):
            raise ParameterError(f"Rotor {self.name!r}: stations={self.stations!r} lists a station twice")
        if (self.speed is None) == (self.speed_ratio is None):
            raise ParameterError(
                f"Rotor {self.name!r}: give exactly one of speed (rad/s) or speed_ratio with reference"
            )
        if self.speed_ratio is not None and not self.reference:
            raise ParameterError(
                f"Rotor {self.name!r}: speed_ratio={self.speed_ratio} needs reference=<name of another rotor>"
            )
        if self.reference is not None and not isinstance(self.reference, str):
            raise ParameterError(f"Rotor {self.name!r}: reference = {self.reference!r}: expected a rotor name (str)")
        if self.speed is not None and self.reference is not None:
            raise ParameterError(f"Rotor {self.name!r}: reference is only used with speed_ratio")

    def attached_stations(self):
        return self.stations

    def owned_stations(self):
        return self.stations

    def coordinates(self):
        return tuple((s, axis) for axis in ("x", "y") for s in self.stations)

    def check(self, model):
        seen, r = [self.name], self
        while r.speed is None:
            if r.reference not in model.rotors:
                raise TopologyError(
                    f"Rotor {r.name!r}: reference={r.reference!r} is not a rotor of the model "
                    f"(rotors: {sorted(model.rotors)})"
                )
            r = model.rotors[r.reference]
            if r.name in seen:
                raise TopologyError(f"Rotor speeds refer to each other in a loop: {seen + [r.name]}")
            seen.append(r.name)

    def explain(self, model, problem, coordinates):
        stations = list(dict.fromkeys(s for s, axis in coordinates if axis in ("x", "y")))
        if not stations:
            return None
        if problem == "inertia":
            return (f"Model: station {stations[0]!r} (rotor {self.name!r}) has no mass, so its equations "
                    "are singular; add LumpedMass(station=..., mass=...) or a Disk there")
        what = ("has no support" if len(stations) == len(self.stations)
                else f"has stations {stations} with no stiffness path to a support")
        return (f"Rotor {self.name!r} {what}: it would drift freely; add an ElasticSupport, a "
                "ShaftSegment with bending stiffness, or a BallBearing to a supported rotor")

    def label(self):
        return self.name

    def contribute(self, ctx):
        return Terms()
