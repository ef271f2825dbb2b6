"""Speed as a degree of freedom: a rotor turned by a torque instead of a prescribed speed.

Give a :class:`Drive` as a rotor's speed, ``Rotor(name="LP", stations=...,
speed=Drive.constant(torque=..., initial_speed=...))``. The rotor then gets
one more coordinate, ``spin<s>`` at its first station ``s``: the spin angle
on top of ``Omega_0 t``, so that the spin angle and speed are ::

    phi(t)   = Omega_0 t + spin,      Omega = Omega_0 + spin'

(``Omega_0 = initial_speed``; a state of zeros, the default of
:func:`~rotorkit.simulate`, starts the rotor at ``Omega_0``). Everything
that used ``Omega t`` and ``Omega`` uses ``phi`` and ``Omega``: the unbalance
centroids ``(x + e cos phi, y + e sin phi)``, the disks' polar inertia
``J Omega^2 / 2``, the gyroscopic terms of rigid disks, the cage of a ball
bearing, speed-dependent bearing coefficients. Lagrange's equations then
give the spin equation ::

    (J + sum m e^2) Omega' = T_drive(Omega, t) - T_loss(Omega) + (rub torques) + (unbalance coupling)

with ``J`` the polar inertia of the rotor's parts: ``polar_inertia`` of
the drive (motor, shaft: beam elements' own polar inertia is not added)
plus the disks of the rotor and of rotors geared to it (``speed_ratio``
``gamma``: ``gamma^2 J``). Beam elements keep their gyroscopic coupling,
derived in full (``rotorkit.symbolic.lagrange._state_gyroscopics``).
Disks with torsion turn at ``phi + alpha``: the torque reaches the rest of
the rotor through the torsional shafts. The losses are ``T_loss = drag Omega + windage Omega |Omega|``.

The drive torque ``T_drive``, one of:

``Drive.constant(torque)``
    ``T_drive = T_0`` (N m).
``Drive.motor(speeds, torques)``
    A motor curve ``T(Omega)``: piecewise linear through the points,
    held at the end values outside the table; ``speeds`` strictly
    increasing. Its kinks are switches of the equations.
``Drive.expression(function, parameters=...)``
    ``T = function(Omega, **parameters)`` built from sympy functions.
``Drive.controller(target, proportional, integral)``
    A PI speed controller, ``T = k_p e + k_i z`` with the speed error
    ``e = Omega_ref - Omega`` and its integral
    ``z = integral_0^t e = (Omega_ref - Omega_0) t - spin``: the integral
    state is the angle lag behind the reference, so it is already a state
    of the model (no extra equation; ``z(0) = 0`` with ``spin(0) = 0``).

The values are parameters of the derived equations, named
``<rotor>_speed_<key>`` (``LP_speed_torque``, ``LP_speed_initial``,
``LP_speed_w0``, ``LP_speed_torque0``): changing them needs no new
derivation.

Examples
--------
>>> d = Drive.constant(torque=2.0, initial_speed=100.0, polar_inertia=0.01, drag=1e-3)
>>> sorted(d.values())
['drag', 'inertia', 'initial', 'torque', 'windage']
>>> Drive.motor(speeds=[0.0, 300.0], torques=[5.0, 0.0], initial_speed=0.0).values()["torque1"]
0.0
"""

import math
import numbers
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import ParameterError, TopologyError
from ..units import to_si
from .tabulated import check_table

__all__ = ["Drive"]

_KINDS = ("constant", "motor", "expression", "controller")
#: field -> (SI unit, sign rule, key in values())
_COMMON = {"initial_speed": ("rad/s", None, "initial"), "polar_inertia": ("kg*m**2", "nonnegative", "inertia"),
           "drag": ("N*m*s/rad", "nonnegative", "drag"), "windage": ("N*m*s**2/rad**2", "nonnegative", "windage")}
_CONTROLLER = {"target": ("rad/s", None), "proportional": ("N*m*s/rad", "nonnegative"),
               "integral": ("N*m/rad", "nonnegative")}


def _number(value, unit, name, sign=None):
    if isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} = {value!r}: expected a number")
    si = to_si(value, unit, name, sign=sign)
    if not isinstance(si, numbers.Real) or not math.isfinite(si):
        raise ParameterError(f"{name} = {value!r}: expected a finite number")
    return float(si)


@dataclass(frozen=True, slots=True, kw_only=True)
class Drive:
    """A rotor speed that is a degree of freedom, driven by a torque; give it as ``Rotor(speed=...)``.

    Build one with :meth:`constant`, :meth:`motor`, :meth:`expression` or
    :meth:`controller` (see the module docstring for the equations); the
    keywords below are common to all of them.

    Parameters
    ----------
    initial_speed : float, pint.Quantity or str
        ``Omega_0`` (rad/s): the speed at ``spin' = 0``, where a state of zeros starts.
    polar_inertia : float or pint.Quantity
        Polar inertia (kg m^2), >= 0, beyond the rotor's disks (motor
        armature, shaft, blades not modelled as disks).
    drag : float
        Viscous loss torque coefficient (N m s/rad), >= 0: ``drag Omega``.
    windage : float
        Windage loss torque coefficient (N m s^2/rad^2), >= 0: ``windage Omega |Omega|``.
    """

    kind: str = "constant"
    initial_speed: float = 0.0
    polar_inertia: float = 0.0
    drag: float = 0.0
    windage: float = 0.0
    torque: float | None = None
    speeds: tuple = ()
    torques: tuple = ()
    function: Callable | None = None
    constants: tuple = field(default=())  # (name, SI value) pairs of an expression
    target: float | None = None
    proportional: float | None = None
    integral: float | None = None

    # -- constructors -----------------------------------------------------
    @classmethod
    def constant(cls, torque, **common):
        """A constant drive torque ``torque`` (N m)."""
        return cls(kind="constant", torque=torque, **common)

    @classmethod
    def motor(cls, speeds, torques, **common):
        """A motor curve: torque ``torques[i]`` (N m) at speed ``speeds[i]`` (rad/s), piecewise linear."""
        return cls(kind="motor", speeds=speeds, torques=torques, **common)

    @classmethod
    def expression(cls, function, *, parameters=None, **common):
        """``T = function(Omega, **parameters)`` (N m), e.g. ``lambda w, t0, ws: t0 * (1 - w / ws)``."""
        parameters = {} if parameters is None else parameters
        if not isinstance(parameters, dict):
            raise ParameterError(f"Drive.expression: parameters = {parameters!r}: expected a dict name -> number")
        return cls(kind="expression", function=function, constants=tuple(parameters.items()), **common)

    @classmethod
    def controller(cls, target, proportional, integral=0.0, **common):
        """A PI speed controller on ``target`` (rad/s): gains ``proportional`` (N m s/rad), ``integral`` (N m/rad)."""
        return cls(kind="controller", target=target, proportional=proportional, integral=integral, **common)

    def __post_init__(self):
        who = f"Drive.{self.kind}" if self.kind in _KINDS else "Drive"
        if self.kind not in _KINDS:
            raise ParameterError(f"Drive.kind = {self.kind!r}: expected one of {', '.join(_KINDS)}")
        for name, (unit, sign, _) in _COMMON.items():
            object.__setattr__(self, name, _number(getattr(self, name), unit, f"{who}: {name}", sign))
        if self.kind == "constant":
            if self.torque is None:
                raise ParameterError(f"{who}: torque is required (N m)")
            object.__setattr__(self, "torque", _number(self.torque, "N*m", f"{who}: torque"))
        elif self.kind == "motor":
            ws, ts = check_table(self.speeds, "speeds", "torques", self.torques, unit_x="rad/s", unit_y="N*m",
                                 owner=who)
            object.__setattr__(self, "speeds", ws)
            object.__setattr__(self, "torques", ts)
        elif self.kind == "expression":
            if not callable(self.function):
                raise ParameterError(f"{who}: function = {self.function!r}: expected a function of the speed")
            consts = []
            for name, value in self.constants:
                if not isinstance(name, str) or not name.isidentifier() or name in self._fixed_keys():
                    raise ParameterError(f"{who}: parameter name {name!r}: expected an identifier other than "
                                         f"{', '.join(self._fixed_keys())}")
                consts.append((name, _number(value, "", f"{who}: parameter {name!r}")))
            object.__setattr__(self, "constants", tuple(consts))
            import sympy as sp

            self.drive_torque(sp.Symbol("w", real=True), sp.Symbol("t", real=True), sp.Symbol("s", real=True),
                              {k: sp.Symbol(k, real=True) for k in self.values()})  # fail early
        else:
            for name, (unit, sign) in _CONTROLLER.items():
                if getattr(self, name) is None:
                    raise ParameterError(f"{who}: {name} is required ({unit})")
                object.__setattr__(self, name, _number(getattr(self, name), unit, f"{who}: {name}", sign))

    @staticmethod
    def _fixed_keys():
        return tuple(key for _, _, key in _COMMON.values())

    # -- parameters (the SpeedProfile protocol of Rotor.speed) ------------
    def values(self):
        """Key (without the ``speed_`` prefix) -> SI value."""
        out = {key: getattr(self, name) for name, (_, _, key) in _COMMON.items()}
        if self.kind == "constant":
            out["torque"] = self.torque
        elif self.kind == "motor":
            out.update({f"w{i}": v for i, v in enumerate(self.speeds)})
            out.update({f"torque{i}": v for i, v in enumerate(self.torques)})
        elif self.kind == "expression":
            out.update(dict(self.constants))
        else:
            out.update({name: getattr(self, name) for name in _CONTROLLER})
        return out

    def units(self):
        """Key -> SI unit."""
        out = {key: unit for unit, _, key in _COMMON.values()}
        if self.kind == "constant":
            out["torque"] = "N*m"
        elif self.kind == "motor":
            out.update({f"w{i}": "rad/s" for i in range(len(self.speeds))})
            out.update({f"torque{i}": "N*m" for i in range(len(self.torques))})
        elif self.kind == "expression":
            out.update({k: "" for k, _ in self.constants})
        else:
            out.update({name: unit for name, (unit, _) in _CONTROLLER.items()})
        return out

    def signs(self):
        """Key -> sign rule (``"nonnegative"`` or None)."""
        out = {key: sign for _, sign, key in _COMMON.values()}
        if self.kind == "controller":
            out.update({name: sign for name, (_, sign) in _CONTROLLER.items()})
        return out

    def time_event_fields(self):
        return ()

    def with_values(self, **values):
        """A copy with some values changed (keys as in :meth:`values`), fully re-validated."""
        import dataclasses

        current = self.values()
        unknown = set(values) - set(current)
        if unknown:
            raise ParameterError(f"Drive: unknown values {sorted(unknown)}; known: {sorted(current)}")
        current.update(values)
        fields = {name: current[key] for name, (_, _, key) in _COMMON.items()}
        if self.kind == "constant":
            fields["torque"] = current["torque"]
        elif self.kind == "motor":
            n = len(self.speeds)
            fields["speeds"] = [current[f"w{i}"] for i in range(n)]
            fields["torques"] = [current[f"torque{i}"] for i in range(n)]
        elif self.kind == "expression":
            fields["constants"] = tuple((k, current[k]) for k, _ in self.constants)
        else:
            fields.update({name: current[name] for name in _CONTROLLER})
        return dataclasses.replace(self, **fields)

    def structure(self):
        """What the equations' form depends on (not the values)."""
        if self.kind == "motor":
            return ("drive", "motor", len(self.speeds))
        if self.kind == "expression":
            import sympy as sp

            w, t, s = (sp.Symbol(n, real=True) for n in ("w", "t", "s"))
            p = {k: sp.Symbol(k, real=True) for k in self.values()}
            return ("drive", "expression", sp.srepr(self.drive_torque(w, t, s, p)))
        return ("drive", self.kind)

    # -- expressions ---------------------------------------------------------
    def speed(self, p, spin_speed):
        """``Omega = Omega_0 + spin'``; ``p`` maps :meth:`values` keys to symbols."""
        return p["initial"] + spin_speed

    def angle(self, t, p, spin):
        """``phi = Omega_0 t + spin``."""
        return p["initial"] * t + spin

    def drive_torque(self, speed, t, spin, p):
        """``T_drive`` (N m) as a sympy expression of the speed, time and spin coordinate."""
        if self.kind == "constant":
            return p["torque"]
        if self.kind == "motor":
            from ..symbolic.tables import interpolate_table

            n = len(self.speeds)
            return interpolate_table(speed, [p[f"w{i}"] for i in range(n)], [p[f"torque{i}"] for i in range(n)])
        if self.kind == "controller":
            integral_state = (p["target"] - p["initial"]) * t - spin
            return p["proportional"] * (p["target"] - speed) + p["integral"] * integral_state
        import sympy as sp

        try:
            expr = sp.sympify(self.function(speed, **{k: p[k] for k, _ in self.constants}))
        except Exception as exc:
            raise ParameterError(
                "Drive.expression: function must accept the speed and the named parameters "
                f"({', '.join(k for k, _ in self.constants) or 'none'}) and return a sympy expression; "
                f"calling it failed: {exc}"
            ) from exc
        extra = expr.free_symbols - sp.sympify(speed).free_symbols - set(p.values())
        if extra:
            raise ParameterError(f"Drive.expression: the torque uses unknown symbols {sorted(map(str, extra))}; "
                                 "pass them in parameters={...}")
        return expr

    def loss_torque(self, speed, p):
        """``drag Omega + windage Omega |Omega|`` (N m); ``|Omega| = Omega (2 H(Omega) - 1)``, smooth to print."""
        from ..symbolic.functions import step

        return p["drag"] * speed + p["windage"] * speed**2 * (2 * step(speed) - 1)

    def switches(self, speed, p):
        """The kinks of the torque law: the motor table's breakpoints in speed."""
        if self.kind == "motor":
            return tuple(speed - p[f"w{i}"] for i in range(len(self.speeds)))
        return ()

    # -- the rotor's terms -------------------------------------------------
    def check(self, rotor, model):
        """The rotor's drive needs some polar inertia (a disk on it or ``polar_inertia``)."""
        driven = [r for r in model.rotors.values() if _root(model, r) is rotor]
        stations = {s for r in driven for s in r.stations}
        if self.polar_inertia == 0 and not any(s in stations for s in model.disks):
            raise TopologyError(
                f"Rotor {rotor.name!r}: its speed is a degree of freedom (Drive) but nothing gives it polar "
                "inertia; add a Disk on the rotor or give Drive(..., polar_inertia=...) (kg m^2)"
            )

    def contribute(self, rotor, ctx):
        """Kinetic energy of the spin of the disks without torsion, and the drive and loss torques."""
        from .base import Terms

        p = {k: ctx.parameter(rotor, f"speed_{k}") for k in self.values()}
        spin, spin_speed = ctx.coord(rotor.stations[0], "spin")
        speed = self.speed(p, spin_speed)
        kinetic = p["inertia"] * speed**2 / 2
        for station, disk in ctx.model.disks.items():
            if _root(ctx.model, ctx.model.rotor_of(station)) is rotor and not getattr(disk, "torsion", False):
                kinetic += disk.polar_inertia_expr(ctx.bind(disk).p) * ctx.speed(station) ** 2 / 2
        torque = self.drive_torque(speed, ctx.t, spin, p) - self.loss_torque(speed, p)
        return Terms(kinetic=kinetic, loads={spin: torque}, switches=self.switches(speed, p))


def _root(model, rotor):
    while rotor.speed is None:
        rotor = model.rotors[rotor.reference]
    return rotor
