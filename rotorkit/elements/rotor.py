"""Rotor (spool): a set of stations spinning at one speed."""

import dataclasses
import numbers
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ParameterError, TopologyError
from .base import Element, loaded_types

# SpeedProfile, Drive, Rayleigh and ModalDamping are looked up by loaded_types (a rotor holding one
# imported its module): a rotor at a constant speed without damping never loads those modules.
_LAWS = ("speed.SpeedProfile", "drive.Drive")
_DAMPINGS = ("damping.Rayleigh", "damping.ModalDamping")

if TYPE_CHECKING:  # for the annotations only
    from .damping import ModalDamping, Rayleigh

__all__ = ["Rotor", "check_station", "torque_targets"]


def _rayleigh():
    """:class:`~rotorkit.elements.damping.Rayleigh` (its units serve both dampings), imported when a rotor has one."""
    from .damping import Rayleigh

    return Rayleigh


def check_station(owner, station, field="station"):
    """Return ``station`` as a valid label (int >= 0 or identifier), or raise naming ``field``."""
    if isinstance(station, numbers.Integral) and not isinstance(station, (bool, np.bool_)) and station >= 0:
        return int(station)
    if isinstance(station, str) and station.isidentifier():
        return station
    raise ParameterError(f"{owner}: {field} = {station!r}: expected a station (a non-negative int or an identifier string)")


def torque_targets(ctx, station):
    """Coordinate symbol -> factor: where a torque about +z on ``station``'s cross-section does work.

    A torque ``M`` on the section at ``station`` loads its torsional
    coordinate ``alpha`` (if it has one) with ``M`` and, if the speed of its
    rotor is a degree of freedom (a :class:`~rotorkit.elements.drive.Drive`,
    possibly through ``speed_ratio`` gearing ``gamma``), the rotor's spin
    coordinate with ``gamma M``. Empty when the station turns at a prescribed
    speed without torsion (the drive absorbs the torque).
    """
    out = {}
    alpha = ctx.coord(station, "alpha", drive=True)[0]
    if alpha != 0:
        out[alpha] = 1
    factor, rotor = 1, ctx.model.rotor_of(station)
    while rotor.speed is None:
        factor = factor * ctx.parameter(rotor, "speed_ratio")
        rotor = ctx.model.rotors[rotor.reference]
    if rotor.drive is not None:
        out[ctx.coord(rotor.stations[0], "spin")[0]] = factor
    return out


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
    speed : float, pint.Quantity or SpeedProfile, optional
        Spin speed (rad/s), constant, or a :class:`SpeedProfile` (run-up,
        coast-down: a table or an expression of time). A profile's values
        are parameters ``<name>_speed_<key>`` (``LP_speed_t0``, ``LP_speed_w0``).
    speed_ratio : float, optional
        Speed relative to ``reference``.
    reference : str, optional
        Name of the rotor ``speed_ratio`` refers to.
    damping : Rayleigh or ModalDamping, optional
        Proportional structural damping ``alpha M + beta K`` of the rotor's
        shaft and disks (:mod:`rotorkit.elements.damping`); parameters
        ``<name>_damping_alpha``, ``<name>_damping_beta``. Or
        :class:`~rotorkit.elements.damping.ModalDamping`: damping ratios of
        the model's undamped non-rotating modes, in the linear analyses and
        time runs (no parameters; at most one rotor of a model).

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
    damping: "Rayleigh | ModalDamping | None" = None

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
        profile = self.speed if isinstance(self.speed, loaded_types(*_LAWS)) else None
        if profile is not None:  # the profile (or drive) holds its own checked values
            object.__setattr__(self, "speed", 0.0)
        Element.__post_init__(self)
        if profile is not None:
            object.__setattr__(self, "speed", profile)

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
        if self.damping is not None and not isinstance(self.damping, loaded_types(*_DAMPINGS)):
            raise ParameterError(f"Rotor {self.name!r}: damping = {self.damping!r}: expected Rayleigh(alpha, beta), "
                                 "ModalDamping(ratios=...) or None")

    def attached_stations(self):
        return self.stations

    def owned_stations(self):
        return self.stations

    def coordinates(self):
        spin = ((self.stations[0], "spin"),) if self.drive is not None else ()
        return tuple((s, axis) for axis in ("x", "y") for s in self.stations) + spin

    def inertia(self):
        return ((self.stations[0], "spin"),) if self.drive is not None else ()  # the polar inertia of its parts

    def grounds(self):
        return ((self.stations[0], "spin"),) if self.drive is not None else ()  # held by the drive torque, not elastic

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
        if self.drive is not None:
            self.drive.check(self, model)
        modal = loaded_types("damping.ModalDamping")
        if isinstance(self.damping, modal):
            others = [r.name for r in model.rotors.values() if isinstance(r.damping, modal)]
            if len(others) > 1:
                raise TopologyError(f"Rotors {others} each have ModalDamping: the modes are the model's, so give "
                                    "ModalDamping(ratios=...) to one rotor only")

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
        from .terms import Terms

        rayleigh = isinstance(self.damping, loaded_types("damping.Rayleigh"))
        if rayleigh:
            from .damping import rayleigh_terms
        parts = [terms for terms in (None if self.drive is None else self.drive.contribute(self, ctx),
                                     rayleigh_terms(self, ctx) if rayleigh else None) if terms is not None]
        if len(parts) < 2:
            return parts[0] if parts else Terms()
        (a, b), loads = parts, dict(parts[0].loads)
        for q, load in b.loads.items():
            loads[q] = loads[q] + load if q in loads else load
        return Terms(kinetic=a.kinetic + b.kinetic, potential=a.potential + b.potential,
                     dissipation=a.dissipation + b.dissipation, loads=loads, switches=a.switches + b.switches,
                     quadratic=a.quadratic + b.quadratic)

    # -- speed profiles ------------------------------------------------------
    @property
    def profile(self):
        """The :class:`SpeedProfile`, or None for a constant speed or a ratio."""
        return self.speed if isinstance(self.speed, loaded_types("speed.SpeedProfile")) else None

    @property
    def drive(self):
        """The :class:`~rotorkit.elements.drive.Drive` (speed a degree of freedom), or None."""
        return self.speed if isinstance(self.speed, loaded_types("drive.Drive")) else None

    @property
    def _law(self):
        """The SpeedProfile or Drive holding the speed's parameters, or None."""
        return self.profile if self.profile is not None else self.drive

    def parameters(self):
        damping = {} if self.damping is None else self.damping.parameters()
        if self._law is None:
            return {**Element.parameters(self), **damping}
        return {**{f"speed_{k}": v for k, v in self._law.values().items()}, **damping}

    def parameter_units(self):
        damping = {} if self.damping is None else {f: _rayleigh().unit_of(f) for f in self.damping.parameters()}
        if self._law is None:
            return {**Element.parameter_units(self), **damping}
        return {**{f"speed_{k}": u for k, u in self._law.units().items()}, **damping}

    def parameter_sign(self, field_name):
        if self._damping_field(field_name):
            return "nonnegative"
        if self.drive is not None:
            return self.drive.signs().get(field_name[len("speed_"):])
        return None if self.profile is not None else Element.parameter_sign(self, field_name)

    def unit_of(self, field_name):
        if self._damping_field(field_name):
            return _rayleigh().unit_of(field_name)
        if self._law is not None and field_name.startswith("speed_"):
            return self._law.units()[field_name[len("speed_"):]]
        return Element.unit_of(self, field_name)

    def replace_parameters(self, **fields):
        damped = {k: fields.pop(k) for k in list(fields) if self._damping_field(k)}
        new = self if not damped else dataclasses.replace(self, damping=self.damping.replace(**damped))
        if not fields:
            return new
        if new._law is None:
            return Element.replace_parameters(new, **fields)
        law = new._law.with_values(**{k[len("speed_"):]: v for k, v in fields.items()})
        return dataclasses.replace(new, speed=law)

    def _damping_field(self, field_name):
        """Whether ``field_name`` is a parameter of the rotor's damping (``damping_...``; none without damping)."""
        if self.damping is None:
            return False
        from .damping import PREFIX

        return field_name.startswith(PREFIX)

    def time_event_fields(self):
        if self._law is None:
            return Element.time_event_fields(self)
        return tuple(f"speed_{k}" for k in self._law.time_event_fields())

    def structure(self):
        # the damping's values are parameters: only its presence is structure (absent: the key is unchanged)
        damping = () if self.damping is None else (("damping", type(self.damping).__name__),)
        if self._law is None:
            base = Element.structure(self)
            return base[:2] + (tuple(v for v in base[2] if v[0] != "damping") + damping,)
        return (type(self).__name__, self.label(), (("stations", repr(self.stations)), self._law.structure())
                + damping)

    def spin_symbols(self):
        """``(spin, spin')`` symbols of a driven rotor's spin coordinate (named as the model's states)."""
        import sympy as sp

        name = f"spin{self.stations[0]}"
        return sp.Symbol(name, real=True), sp.Symbol(f"{name}_dot", real=True)

    def speed_expression(self, t, parameter):
        """Spin speed of this (root) rotor as an expression; ``parameter(name)`` gives a symbol."""
        if self.drive is not None:
            return self.drive.speed({"initial": parameter(f"{self.name}_speed_initial")}, self.spin_symbols()[1])
        if self.profile is None:
            return parameter(f"{self.name}_speed")
        return self.profile.speed(t, {k: parameter(f"{self.name}_speed_{k}") for k in self.profile.values()})

    def angle_expression(self, t, parameter):
        """Spin angle ``integral_0^t speed`` of this (root) rotor as an expression."""
        if self.drive is not None:
            return self.drive.angle(t, {"initial": parameter(f"{self.name}_speed_initial")}, self.spin_symbols()[0])
        if self.profile is None:
            return parameter(f"{self.name}_speed") * t
        return self.profile.angle(t, {k: parameter(f"{self.name}_speed_{k}") for k in self.profile.values()})
