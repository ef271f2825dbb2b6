"""Inter-rotor ball bearing with Hertzian contact and clearance."""

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, TopologyError
from .base import Element, Terms
from .rotor import check_station

#: most balls a BallBearing takes (each adds its own contact terms to derive and compile)
MAX_BALLS = 100

__all__ = ["BallBearing"]


def _clean(value):
    """A trigonometric constant as sympy number, exact where it is 0 or +-1."""
    import sympy as sp

    for exact in (0, 1, -1):
        if abs(value - exact) < 1e-14:
            return sp.Integer(exact)
    return sp.Float(value)


@dataclass(frozen=True, slots=True, kw_only=True)
class BallBearing(Element):
    """A ball bearing between two rotors (inner race on one, outer race on the other).

    The cage turns at ``omega_c = (Omega_i R_i + Omega_o R_o) / (R_i + R_o)``
    from the two rotor speeds; ball j sits at
    ``theta_j = omega_c t + 2 pi (j - 1) / N_b``. Its deformation is
    ``delta_j = (x_o - x_i) cos theta_j + (y_o - y_i) sin theta_j - delta_0``
    and the Hertzian force ``F = C_b sum max(delta_j, 0)^n (cos, sin) theta_j``
    acts +F on the inner-race station and -F on the outer-race station.

    Parameters
    ----------
    inner_station, outer_station : int or str
        Stations of the inner and outer race; they must be on different rotors.
    contact_stiffness : float or pint.Quantity
        Hertz constant C_b (N/m^1.5 for n = 1.5).
    clearance : float or pint.Quantity
        Radial clearance delta_0 (m), >= 0.
    n_balls : int
        Number of balls N_b (3 to ``MAX_BALLS`` = 100). Structural: it sets the number of terms.
    inner_race_radius, outer_race_radius : float or pint.Quantity
        R_inner, R_outer (m).
    exponent : float
        Load-deflection exponent n (1.5 for balls). Structural.

    Examples
    --------
    >>> BallBearing(inner_station=4, outer_station=7, contact_stiffness=1.334e10,
    ...             clearance=5e-6, n_balls=8, inner_race_radius=0.0401,
    ...             outer_race_radius=0.0639).label()
    'bearing4_7'
    """

    inner_station: int | str = None
    outer_station: int | str = None
    contact_stiffness: float = None
    clearance: float = 0.0
    n_balls: int = None
    inner_race_radius: float = None
    outer_race_radius: float = None
    exponent: float = 1.5

    _units = {
        "contact_stiffness": ("N/m**1.5", "positive"),  # N/m^n: see unit_of
        "clearance": ("m", "nonnegative"),
        "inner_race_radius": ("m", "positive"),
        "outer_race_radius": ("m", "positive"),
    }
    _latex_names = {
        "contact_stiffness": "C_b",
        "clearance": r"\delta_0",
        "inner_race_radius": "R_{i}",
        "outer_race_radius": "R_{o}",
    }

    def unit_of(self, field_name):
        if field_name == "contact_stiffness":
            n = float(self.exponent) if isinstance(self.exponent, numbers.Real) and not isinstance(
                self.exponent, (bool, np.bool_)) and math.isfinite(self.exponent) else 1.5
            return f"N/m**{n:g}"
        return Element.unit_of(self, field_name)

    def _validate(self):
        who = f"BallBearing {self.inner_station!r}-{self.outer_station!r}"
        object.__setattr__(self, "inner_station", check_station(who, self.inner_station, "inner_station"))
        object.__setattr__(self, "outer_station", check_station(who, self.outer_station, "outer_station"))
        for name in ("contact_stiffness", "inner_race_radius", "outer_race_radius"):
            if getattr(self, name) is None:
                raise ParameterError(f"{who}: {name} is required")
        if isinstance(self.n_balls, (bool, np.bool_)) or not isinstance(self.n_balls, numbers.Integral) \
                or self.n_balls < 3:
            raise ParameterError(f"{who}: n_balls={self.n_balls!r} must be an int >= 3")
        if self.n_balls > MAX_BALLS:
            raise ParameterError(
                f"{who}: n_balls={self.n_balls!r} is more than {MAX_BALLS}: every ball adds its own contact terms, "
                f"so deriving and compiling grow with the count (thousands take minutes); rolling-element "
                f"bearings have 6-{MAX_BALLS} elements: give the real count, or model the bearing by its "
                "linearised coefficients (LinearBearing)")
        object.__setattr__(self, "n_balls", int(self.n_balls))
        if isinstance(self.exponent, (bool, np.bool_)) or not isinstance(self.exponent, numbers.Real) \
                or not math.isfinite(self.exponent) or not self.exponent >= 1:
            raise ParameterError(f"{who}: exponent={self.exponent!r} must be a finite number >= 1 (1.5 for balls)")
        object.__setattr__(self, "exponent", float(self.exponent))
        if self.inner_race_radius > self.outer_race_radius:  # the inner race lies inside the outer one
            raise ParameterError(f"{who}: inner_race_radius = {self.inner_race_radius:g} m is larger than "
                                 f"outer_race_radius = {self.outer_race_radius:g} m; expected R_inner <= R_outer")

    def attached_stations(self):
        return (self.inner_station, self.outer_station)

    def _default_label(self):
        return f"bearing{self.inner_station}_{self.outer_station}"

    def stiffness_links(self):
        i, o = self.inner_station, self.outer_station
        return (((i, "x"), (o, "x")), ((i, "y"), (o, "y")))

    def effects(self):
        return frozenset({"bearing_nonlinearity"})

    def check(self, model):
        ri, ro = model.rotor_of(self.inner_station), model.rotor_of(self.outer_station)
        if ri is ro:
            raise TopologyError(
                f"BallBearing {self.label()!r}: inner_station {self.inner_station!r} and outer_station "
                f"{self.outer_station!r} are both on rotor {ri.name!r}; an inter-rotor bearing joins "
                "stations of two different rotors"
            )

    def cage_speed(self, ctx):
        """Cage speed omega_c as an expression of the rotor speeds."""
        p = ctx.p
        ri, ro = p["inner_race_radius"], p["outer_race_radius"]
        return (ctx.speed(self.inner_station) * ri + ctx.speed(self.outer_station) * ro) / (ri + ro)

    def cage_angle(self, ctx):
        """Cage angle: ``omega_c t`` at constant speeds, the weighted spin angles under speed profiles."""
        if ctx.speed_is_constant(self.inner_station) and ctx.speed_is_constant(self.outer_station):
            return self.cage_speed(ctx) * ctx.t
        p = ctx.p
        ri, ro = p["inner_race_radius"], p["outer_race_radius"]
        return (ctx.spin_angle(self.inner_station) * ri + ctx.spin_angle(self.outer_station) * ro) / (ri + ro)

    def contribute(self, ctx):
        import sympy as sp

        from ..symbolic.functions import ramp

        p = ctx.p
        (xi, _), (yi, _) = ctx.coord(self.inner_station, "x"), ctx.coord(self.inner_station, "y")
        (xo, _), (yo, _) = ctx.coord(self.outer_station, "x"), ctx.coord(self.outer_station, "y")
        theta = self.cage_angle(ctx)
        c0, s0 = sp.cos(theta), sp.sin(theta)
        n = sp.nsimplify(self.exponent)
        fx = fy = sp.S.Zero
        switches = []
        for j in range(self.n_balls):
            # ball angle by angle addition: one sin/cos pair for all balls
            ca, sa = _clean(math.cos(2 * math.pi * j / self.n_balls)), _clean(math.sin(2 * math.pi * j / self.n_balls))
            cj, sj = (c0, s0) if j == 0 else (c0 * ca - s0 * sa, s0 * ca + c0 * sa)
            delta = (xo - xi) * cj + (yo - yi) * sj - p["clearance"]
            switches.append(delta)
            load = ramp(delta) ** n
            fx += load * cj
            fy += load * sj
        cb = p["contact_stiffness"]
        loads = {xi: cb * fx, yi: cb * fy, xo: -cb * fx, yo: -cb * fy}
        return Terms(loads=loads, switches=tuple(switches))
