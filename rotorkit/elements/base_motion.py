"""Base rotation: inertia loads of a rotor whose frame (the aircraft) turns.

The coordinates ``x, y`` are measured in the base (engine) frame, whose
``z`` axis is the rotor axis. When the base turns at the angular velocity
``W(t) = (W_x, W_y, W_z)`` (components in the base frame) about a point
``c`` fixed in inertial space (the centre of a turn or pull-up; given in
base coordinates), a mass ``m`` at ``r = (x, y, z_s) - c`` feels, in the
base frame, the inertia loads ::

    F = -m [ W' x r  +  W x (W x r)  +  2 W x r' ],     r' = (x', y', 0)
           (Euler)      (centripetal)   (Coriolis)

of which the lateral components ``F_x, F_y`` act on the station's ``x, y``.
``z_s`` is the station's axial position (``axial_positions``, default 0).

Kept: all three terms on every station mass, with their dependence on the
displacements (the centripetal term softens the supports by ``m |W_perp|^2``,
the Coriolis term couples ``x`` and ``y``).
Neglected: the offset of an eccentric disk's centroid in these loads (order
``e W^2``, against the unbalance's ``e Omega^2``), the axial component
``F_z`` (no axial coordinate), and, until the model has tilt coordinates,
the gyroscopic moment ``I_p Omega x W`` on spinning disks (a moment: it acts
only on tilts). The translation of the base's reference point and gravity
are a :class:`~rotorkit.elements.maneuver.Maneuver` field; combine the
two (gravity turns with the base in a pull-up: give it as ``Maneuver.profile``).

Examples
--------
A steady level turn at 0.5 rad/s about a vertical axis 800 m to the left:

>>> turn = BaseRotation(rate_y=0.5, center_x=-800.0)
>>> sorted(turn.parameters())
['center_x', 'center_y', 'center_z', 'rate_x', 'rate_y', 'rate_z']
"""

from dataclasses import dataclass
from typing import Callable

import sympy as sp

from ..errors import ParameterError
from ..units import to_si
from .base import Element, Terms
from .rotor import check_station

__all__ = ["BaseRotation"]


@dataclass(frozen=True, slots=True, kw_only=True)
class BaseRotation(Element):
    """The base (aircraft) turns: Euler, centripetal and Coriolis loads on every station mass.

    Parameters
    ----------
    rate_x, rate_y, rate_z : float or pint.Quantity
        Constant base angular velocity (rad/s) in the base frame (``z``:
        rotor axis, ``y``: up). Parameters of the model.
    center_x, center_y, center_z : float or pint.Quantity
        The point the base turns about, in base coordinates (m).
    rate : tuple of 3 callables, optional
        Instead of constant rates: ``W_i(t)`` as functions of a sympy
        symbol ``t`` (structural, like ``Maneuver.profile``); their time
        derivatives give the Euler term. List jump times in ``event_times``.
    axial_positions : dict, optional
        Station -> axial position ``z_s`` (m); stations not listed are at 0.
    """

    rate_x: float = 0.0
    rate_y: float = 0.0
    rate_z: float = 0.0
    center_x: float = 0.0
    center_y: float = 0.0
    center_z: float = 0.0
    rate: tuple | None = None
    axial_positions: tuple = ()
    event_times: tuple = ()

    _units = {**{f"rate_{a}": ("rad/s", None) for a in "xyz"}, **{f"center_{a}": ("m", None) for a in "xyz"}}
    _latex_names = {**{f"rate_{a}": rf"W_{a}" for a in "xyz"}, **{f"center_{a}": rf"c_{a}" for a in "xyz"}}

    def _validate(self):
        positions = self.axial_positions
        if isinstance(positions, dict):
            positions = tuple(positions.items())
        try:
            positions = tuple((check_station("BaseRotation", s, "axial_positions key"),
                               to_si(z, "m", f"BaseRotation.axial_positions[{s!r}]")) for s, z in positions)
        except (TypeError, ValueError) as exc:
            if isinstance(exc, ParameterError):
                raise
            raise ParameterError(f"BaseRotation.axial_positions = {self.axial_positions!r}: expected a dict "
                                 "station -> axial position (m)") from exc
        object.__setattr__(self, "axial_positions", positions)
        if self.rate is not None:
            if not (isinstance(self.rate, (tuple, list)) and len(self.rate) == 3 and all(map(callable, self.rate))):
                raise ParameterError(f"BaseRotation.rate = {self.rate!r}: expected three functions of t (W_x, W_y, W_z)")
            object.__setattr__(self, "rate", tuple(self.rate))
            self.rates(sp.Symbol("t", real=True), {})
        times = self.event_times
        if isinstance(times, (str, bytes)) or not hasattr(times, "__iter__"):
            raise ParameterError(f"BaseRotation.event_times = {times!r}: expected a sequence of times (s)")
        object.__setattr__(self, "event_times", tuple(to_si(e, "s", f"BaseRotation event_times[{i}]")
                                                      for i, e in enumerate(times)))

    def _default_label(self):
        return "base_rotation"

    def parameters(self):
        params = Element.parameters(self)
        if self.rate is not None:
            for a in "xyz":
                params.pop(f"rate_{a}")
        return params

    def parameter_units(self):
        return {f: self.unit_of(f) for f in self.parameters()}

    def fixed_time_events(self):
        return self.event_times

    def structure(self):
        if self.rate is None:
            return Element.structure(self)
        t = sp.Symbol("t", real=True)
        return (type(self).__name__, self.label(), tuple(sp.srepr(w) for w in self.rates(t, {})),
                self.axial_positions)

    def rates(self, t, p):
        """(W_x, W_y, W_z) as sympy expressions."""
        if self.rate is None:
            return tuple(p[f"rate_{a}"] for a in "xyz")
        out = []
        for a, fn in zip("xyz", self.rate):
            try:
                w = sp.sympify(fn(t))
            except Exception as exc:
                raise ParameterError(f"BaseRotation.rate ({a}): calling it with a sympy symbol t failed: {exc}") from exc
            if w.free_symbols - {t}:
                raise ParameterError(f"BaseRotation.rate ({a}): unknown symbols {sorted(map(str, w.free_symbols - {t}))}")
            out.append(w)
        return tuple(out)

    def contribute(self, ctx):
        t = ctx.t
        W = sp.Matrix(self.rates(t, ctx.p))
        Wd = W.diff(t)
        c = sp.Matrix([ctx.p[f"center_{a}"] for a in "xyz"])
        z_of = dict(self.axial_positions)
        loads = {}
        for station, mass in ctx.masses():
            (x, xd), (y, yd) = ctx.coord(station, "x"), ctx.coord(station, "y")
            r = sp.Matrix([x, y, sp.Float(z_of.get(station, 0.0))]) - c
            v = sp.Matrix([xd, yd, 0])
            a = Wd.cross(r) + W.cross(W.cross(r)) + 2 * W.cross(v)
            fx, fy = sp.expand(-mass * a[0]), sp.expand(-mass * a[1])
            if fx != 0:
                loads[x] = loads.get(x, 0) + fx
            if fy != 0:
                loads[y] = loads.get(y, 0) + fy
        return Terms(loads=loads)

