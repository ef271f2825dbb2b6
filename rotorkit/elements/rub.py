"""Rub-impact of a disk on a stator: radial contact with Coulomb friction."""

from dataclasses import dataclass

from ..errors import ParameterError, TopologyError
from .base import Element, Terms
from .rotor import check_station, torque_targets

__all__ = ["RubStator"]


@dataclass(frozen=True, slots=True, kw_only=True)
class RubStator(Element):
    """A stator ring around a disk, concentric with the undeflected axis.

    With ``r = sqrt(x^2 + y^2)`` and penetration ``r - delta > 0``:
    ``(Fx, Fy) = -k_r (r - delta) / r [[1, -mu], [mu, 1]] (x, y)`` (normal
    force plus friction opposing the spin), and, if the disk has a torsional
    coordinate, the friction torque ``M = -mu k_r R (r - delta)`` on it. No
    force for ``r <= delta``; finite at ``r = 0``.

    Parameters
    ----------
    station : int or str
        Station of the disk that rubs.
    clearance : float or pint.Quantity
        Radial gap delta (m), >= 0 (0: permanent contact).
    contact_stiffness : float or pint.Quantity
        k_r (N/m), >= 0.
    friction_coefficient : float
        mu, >= 0.
    contact_radius : float or pint.Quantity, optional
        Lever arm of the friction torque (m); default: the disk's radius.

    Examples
    --------
    >>> RubStator(station=2, clearance=1.34e-4, contact_stiffness=8e6,
    ...           friction_coefficient=0.1).label()
    'rub2'
    """

    station: int | str = None
    clearance: float = None
    contact_stiffness: float = None
    friction_coefficient: float = 0.0
    contact_radius: float | None = None

    _units = {
        "clearance": ("m", "nonnegative"),
        "contact_stiffness": ("N/m", "nonnegative"),
        "friction_coefficient": ("", "nonnegative"),
        "contact_radius": ("m", "positive"),
    }
    _latex_names = {
        "clearance": r"\delta",
        "contact_stiffness": "k_r",
        "friction_coefficient": r"\mu",
        "contact_radius": "R",
    }

    def _validate(self):
        object.__setattr__(self, "station", check_station("RubStator", self.station, "station"))
        for name in ("clearance", "contact_stiffness"):
            if getattr(self, name) is None:
                raise ParameterError(f"RubStator at station {self.station!r}: {name} is required")

    def attached_stations(self):
        return (self.station,)

    def _default_label(self):
        return f"rub{self.station}"

    def effects(self):
        return frozenset({"rub"})

    def check(self, model):
        driven = model.rotor_of(self.station).drive is not None
        if (model.has_coordinate(self.station, "alpha") or driven) and self.contact_radius is None:
            if not any(getattr(e, "radius", None) is not None for e in model.elements_at(self.station)):
                raise TopologyError(
                    f"RubStator {self.label()!r}: the disk at station {self.station!r} has no radius for the "
                    "friction torque; give contact_radius=... (m)"
                )

    def contribute(self, ctx):
        from ..symbolic.functions import contact_ratio, hypot, ramp

        p = ctx.p
        (x, _), (y, _) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        kr, mu, delta = p["contact_stiffness"], p["friction_coefficient"], p["clearance"]
        r = hypot(x, y)
        normal = kr * ramp(r - delta)
        ratio = contact_ratio(r, delta)  # (r - delta) / r in contact, finite at r = 0
        loads = {
            x: -kr * ratio * (x - mu * y),
            y: -kr * ratio * (mu * x + y),
        }
        targets = torque_targets(ctx, self.station)  # alpha, and the spin of a driven rotor
        if targets:
            radius = p["contact_radius"] if self.contact_radius is not None else ctx.disk_radius(self.station)
            for q, factor in targets.items():
                loads[q] = factor * (-mu * radius * normal)
        return Terms(loads=loads, switches=(r - delta,))
