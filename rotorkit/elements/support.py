"""Elastic support: a station tied to the ground (bearing pedestal, squirrel cage)."""

from dataclasses import dataclass

from ..errors import ParameterError
from .base import Element
from .rotor import check_station

__all__ = ["ElasticSupport"]


@dataclass(frozen=True, slots=True, kw_only=True)
class ElasticSupport(Element):
    """An isotropic spring-damper from a station to the ground.

    ``V = k (x^2 + y^2) / 2`` and ``D = c (x'^2 + y'^2) / 2``.

    Parameters
    ----------
    station : int or str
    stiffness : float or pint.Quantity
        Radial stiffness (N/m), > 0.
    damping : float or pint.Quantity
        Viscous damping (N s/m), >= 0.

    Examples
    --------
    >>> ElasticSupport(station=1, stiffness=1e6, damping=300.0).label()
    'support1'
    """

    station: int | str = None
    stiffness: float = None
    damping: float = 0.0

    _units = {"stiffness": ("N/m", "positive"), "damping": ("N*s/m", "nonnegative")}
    _latex_names = {"stiffness": "k", "damping": "c"}

    def _validate(self):
        object.__setattr__(self, "station", check_station("ElasticSupport", self.station, "station"))
        if self.stiffness is None:
            raise ParameterError(f"ElasticSupport at station {self.station!r}: stiffness is required (N/m)")

    def attached_stations(self):
        return (self.station,)

    def _default_label(self):
        return f"support{self.station}"

    def grounds(self):
        return ((self.station, "x"), (self.station, "y"))

    def contribute(self, ctx):
        from .terms import Terms

        (x, xd), (y, yd) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        k, c = ctx.p["stiffness"], ctx.p["damping"]
        return Terms(potential=k * (x**2 + y**2) / 2, dissipation=c * (xd**2 + yd**2) / 2)
