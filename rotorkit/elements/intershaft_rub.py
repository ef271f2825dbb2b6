"""Inter-shaft rub: a contact between stations of two rotors (an LP shaft inside an HP shaft)."""

from dataclasses import dataclass

from ..errors import ParameterError, TopologyError
from .base import Element, Terms
from .rotor import check_station, torque_targets

__all__ = ["IntershaftRub"]


@dataclass(frozen=True, slots=True, kw_only=True)
class IntershaftRub(Element):
    """A rub between an inner station and the station of another rotor around it.

    With the relative displacement ``d = (x_i - x_o, y_i - y_o)``, ``r = |d|``
    and the penetration ``r - delta > 0``, the normal force on the inner
    station is ``N = k_r (r - delta)`` along ``-d / r``; the Coulomb friction
    ``mu N`` acts along the tangent ``t = (-d_y, d_x) / r`` against the
    sliding of the inner surface on the outer one::

        (Fx_i, Fy_i) = -k_r (r - delta) / r [[1, -s mu], [s mu, 1]] (d_x, d_y)
        (Fx_o, Fy_o) = -(Fx_i, Fy_i)
        M_i = -s mu N R,    M_o = +s mu N (R + delta)

    ``s = sign(v)`` of the sliding speed of the surfaces,
    ``v = Omega_i R - Omega_o (R + delta)`` (the spin speeds of the two
    rotors, signed: a counter-rotating spool has a negative speed ratio or
    speed), written ``s = 2 H(v) - 1``. The friction torques ``M`` act on the
    torsional coordinate of each station and on the spin coordinate of a
    rotor whose speed is a degree of freedom (:class:`~rotorkit.elements.drive.Drive`),
    where those exist. The sliding speed is that of the spin only, like
    :class:`~rotorkit.elements.rub.RubStator`: the whirl and torsional
    vibration speeds (m/s against the tens of m/s of the surfaces) do not
    turn the friction. With the outer station held still and not spinning,
    the loads on the inner station are exactly a ``RubStator``'s. Where the
    sliding speed can change sign (a speed profile or a speed degree of
    freedom), ``v`` is a switch of the equations.

    Parameters
    ----------
    inner_station, outer_station : int or str
        The station inside (e.g. on the LP shaft) and the station around it
        (on the HP shaft); on two different rotors.
    clearance : float or pint.Quantity
        Radial gap delta (m), >= 0.
    contact_stiffness : float or pint.Quantity
        k_r (N/m), >= 0.
    friction_coefficient : float
        mu, >= 0.
    contact_radius : float or pint.Quantity
        R (m), > 0: radius of the inner contact surface; the outer surface
        has radius ``R + delta``.

    Examples
    --------
    >>> IntershaftRub(inner_station=4, outer_station=7, clearance=1e-4, contact_stiffness=5e6,
    ...               friction_coefficient=0.1, contact_radius=0.04).label()
    'intershaftrub4_7'
    """

    inner_station: int | str = None
    outer_station: int | str = None
    clearance: float = None
    contact_stiffness: float = None
    friction_coefficient: float = 0.0
    contact_radius: float = None

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
        for name in ("inner_station", "outer_station"):
            object.__setattr__(self, name, check_station("IntershaftRub", getattr(self, name), name))
        if self.inner_station == self.outer_station:
            raise ParameterError(f"IntershaftRub: inner_station and outer_station are both {self.inner_station!r}; "
                                 "give a station and the station of another rotor around it")
        for name in ("clearance", "contact_stiffness", "contact_radius"):
            if getattr(self, name) is None:
                raise ParameterError(f"IntershaftRub {self.label()!r}: {name} is required "
                                     f"({self.unit_of(name)})")

    def attached_stations(self):
        return (self.inner_station, self.outer_station)

    def _default_label(self):
        return f"intershaftrub{self.inner_station}_{self.outer_station}"

    def effects(self):
        return frozenset({"rub"})

    def check(self, model):
        ri, ro = model.rotor_of(self.inner_station), model.rotor_of(self.outer_station)
        if ri is ro:
            raise TopologyError(
                f"IntershaftRub {self.label()!r}: inner_station {self.inner_station!r} and outer_station "
                f"{self.outer_station!r} are both on rotor {ri.name!r}; an inter-shaft rub joins stations of two "
                "different rotors (use a RubStator for a rub on the casing)"
            )

    def sliding_speed(self, ctx):
        """``v = Omega_i R - Omega_o (R + delta)`` (m/s): the spin surface speed of the inner surface on the outer."""
        p = ctx.p
        radius = p["contact_radius"]
        return ctx.speed(self.inner_station) * radius - ctx.speed(self.outer_station) * (radius + p["clearance"])

    def contribute(self, ctx):
        from ..symbolic.functions import contact_ratio, hypot, ramp, step

        p = ctx.p
        (xi, _), (yi, _) = ctx.coord(self.inner_station, "x"), ctx.coord(self.inner_station, "y")
        (xo, _), (yo, _) = ctx.coord(self.outer_station, "x"), ctx.coord(self.outer_station, "y")
        kr, mu, delta, radius = p["contact_stiffness"], p["friction_coefficient"], p["clearance"], p["contact_radius"]
        dx, dy = xi - xo, yi - yo
        r = hypot(dx, dy)
        normal = kr * ramp(r - delta)
        ratio = contact_ratio(r, delta)
        v = self.sliding_speed(ctx)
        s = 2 * step(v) - 1
        fx = -kr * ratio * (dx - s * mu * dy)
        fy = -kr * ratio * (s * mu * dx + dy)
        loads = {xi: fx, yi: fy, xo: -fx, yo: -fy}
        for station, torque in ((self.inner_station, -s * mu * radius * normal),
                                (self.outer_station, s * mu * (radius + delta) * normal)):
            for q, factor in torque_targets(ctx, station).items():
                loads[q] = loads.get(q, 0) + factor * torque
        switches = [r - delta]
        if not (ctx.speed_is_constant(self.inner_station) and ctx.speed_is_constant(self.outer_station)):
            switches.append(v)
        return Terms(loads=loads, switches=tuple(switches))
