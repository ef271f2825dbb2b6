"""Rotor (spool): a set of stations spinning at one speed."""

from dataclasses import dataclass

from ..errors import ParameterError
from .base import Element, Terms

__all__ = ["Rotor", "check_station"]


def check_station(owner, station):
    """Raise unless ``station`` is a valid station label (int >= 0 or identifier)."""
    ok = (isinstance(station, int) and not isinstance(station, bool) and station >= 0) or (
        isinstance(station, str) and station.isidentifier()
    )
    if not ok:
        raise ParameterError(
            f"{owner}: station {station!r} must be a non-negative int or an identifier string"
        )


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
        if isinstance(self.stations, (str, int)):
            object.__setattr__(self, "stations", (self.stations,))
        else:
            object.__setattr__(self, "stations", tuple(self.stations))
        Element.__post_init__(self)

    def _validate(self):
        if self.name is None:
            raise ParameterError("Rotor.name is required, e.g. Rotor(name='LP', ...)")
        if not self.stations:
            raise ParameterError(f"Rotor {self.name!r}: stations is empty; give at least one station")
        for s in self.stations:
            check_station(f"Rotor {self.name!r}", s)
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
        if self.speed is not None and self.reference is not None:
            raise ParameterError(f"Rotor {self.name!r}: reference is only used with speed_ratio")

    def attached_stations(self):
        return self.stations

    def label(self):
        return self.name

    def contribute(self, ctx):
        return Terms()
