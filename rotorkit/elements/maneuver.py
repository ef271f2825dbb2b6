"""Flight manoeuvre and gravity: a uniform acceleration field on every mass."""

from dataclasses import dataclass
from typing import Callable

from ..errors import ParameterError, TopologyError
from .base import Element

__all__ = ["Maneuver"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Maneuver(Element):
    """Gravity and manoeuvre loads: a force ``m_i (a_x(t), a_y(t))`` on every mass.

    The loads act on the bending coordinates of each station (on the eccentric
    centroid, with no torsional term). ``y`` points up: steady flight gives
    ``(0, -g)``. Build one with :meth:`steady`, :meth:`barrel_roll` or
    :meth:`profile`; at most one per model.

    Barrel roll (the aircraft rolls at ``rate`` on a circle of ``radius``
    between ``start`` and ``end``; it spins about itself at twice the rate)::

        theta = rate * clip(t - start, 0, end - start)
        a_x =  w(t) rate^2 radius cos(theta) - g sin(2 theta)
        a_y = -w(t) rate^2 radius sin(theta) - g cos(2 theta)

    with ``w(t) = 1`` in ``[start, end)`` and 0 outside: the inertial load
    switches on and off as steps, which are time discontinuities.

    Examples
    --------
    >>> Maneuver.steady().label()
    'maneuver'
    >>> Maneuver.barrel_roll(rate=3.14159, radius=3.0, start=2.0, end=4.0).time_event_fields()
    ('roll_start', 'roll_end')
    """

    kind: str = "steady"
    gravity: float | None = None
    roll_rate: float | None = None
    roll_radius: float | None = None
    roll_start: float | None = None
    roll_end: float | None = None
    accel_x: Callable | None = None
    accel_y: Callable | None = None
    event_times: tuple = ()

    _units = {
        "gravity": ("m/s**2", "nonnegative"),
        "roll_rate": ("rad/s", None),
        "roll_radius": ("m", "nonnegative"),
        "roll_start": ("s", None),
        "roll_end": ("s", None),
    }
    _latex_names = {
        "gravity": "g",
        "roll_rate": r"\omega_{bz}",
        "roll_radius": "R_{bz}",
        "roll_start": "t_{s}",
        "roll_end": "t_{e}",
    }

    @classmethod
    def steady(cls, gravity=9.81):
        """Steady level flight: gravity only (m/s^2)."""
        return cls(kind="steady", gravity=gravity)

    @classmethod
    def barrel_roll(cls, *, rate, radius, start, end, gravity=9.81):
        """Barrel roll at ``rate`` (rad/s) on ``radius`` (m) from ``start`` to ``end`` (s)."""
        return cls(kind="barrel_roll", gravity=gravity, roll_rate=rate, roll_radius=radius,
                   roll_start=start, roll_end=end)

    @classmethod
    def profile(cls, accel_x, accel_y, *, event_times=()):
        """A generic load profile from functions of time ``a(t)`` (m/s^2, gravity included).

        The functions are called once with a sympy symbol ``t`` and must be
        built from arithmetic and sympy functions (``sympy.sin``, ``sympy.Piecewise``,
        :func:`rotorkit.symbolic.functions.window`). List the times at which
        they jump in ``event_times`` so the integrator restarts there.
        """
        from ..units import to_si

        if isinstance(event_times, (str, bytes)) or not hasattr(event_times, "__iter__"):
            raise ParameterError(f"Maneuver.profile: event_times = {event_times!r}: expected a sequence of times (s)")
        times = tuple(to_si(e, "s", f"Maneuver.profile event_times[{i}]") for i, e in enumerate(event_times))
        return cls(kind="profile", gravity=None, accel_x=accel_x, accel_y=accel_y, event_times=times)

    def _validate(self):
        kinds = ("steady", "barrel_roll", "profile")
        if self.kind not in kinds:
            raise ParameterError(f"Maneuver.kind={self.kind!r} is unknown; expected one of {kinds}")
        if self.kind != "profile" and self.gravity is None:
            raise ParameterError(f"Maneuver ({self.kind}): gravity = None; expected a number in m/s^2 (e.g. 9.81)")
        if self.kind == "barrel_roll":
            for f in ("roll_rate", "roll_radius", "roll_start", "roll_end"):
                if getattr(self, f) is None:
                    raise ParameterError(f"Maneuver.barrel_roll: {f} is required")
            if not self.roll_end > self.roll_start:
                raise ParameterError(
                    f"Maneuver.barrel_roll: end={self.roll_end} s must be after start={self.roll_start} s"
                )
        if self.kind == "profile":
            for f in ("accel_x", "accel_y"):
                if not callable(getattr(self, f)):
                    raise ParameterError(f"Maneuver.profile: {f} must be a function of time, got {getattr(self, f)!r}")
            import sympy as sp

            self.acceleration(sp.Symbol("t", real=True), {})  # fail early on unusable functions

    def _default_label(self):
        return "maneuver"

    def time_event_fields(self):
        return ("roll_start", "roll_end") if self.kind == "barrel_roll" else ()

    def fixed_time_events(self):
        """Event times that are not parameters (profiles)."""
        return self.event_times

    def effects(self):
        out = {"gravity" if self.kind == "steady" else "maneuver"}
        if self.kind == "barrel_roll" and self.gravity:
            out.add("gravity")
        return frozenset(out)

    def check(self, model):
        if sum(isinstance(e, Maneuver) for e in model.elements) > 1:
            raise TopologyError("Model: more than one Maneuver; a scene has one load field (gravity included)")

    def structure(self):
        base = Element.structure(self)
        if self.kind != "profile":
            return base
        import sympy as sp

        t = sp.Symbol("t", real=True)
        return base[:2] + (tuple(sp.srepr(a) for a in self.acceleration(t, {})), self.event_times)

    def acceleration(self, t, p):
        """The field ``(a_x, a_y)`` as sympy expressions of ``t`` and the symbols ``p``."""
        import sympy as sp

        from ..symbolic.functions import window

        if self.kind == "steady":
            return sp.S.Zero, -p["gravity"]
        if self.kind == "barrel_roll":
            rate, radius, g = p["roll_rate"], p["roll_radius"], p["gravity"]
            start, end = p["roll_start"], p["roll_end"]
            theta = rate * sp.Min(sp.Max(t - start, 0), end - start)
            w = window(t, start, end)
            return (w * rate**2 * radius * sp.cos(theta) - g * sp.sin(2 * theta),
                    -w * rate**2 * radius * sp.sin(theta) - g * sp.cos(2 * theta))
        try:
            ax, ay = sp.sympify(self.accel_x(t)), sp.sympify(self.accel_y(t))
        except Exception as exc:
            raise ParameterError(
                "Maneuver.profile: accel_x/accel_y must accept a sympy symbol t and return an "
                f"expression built with sympy functions (e.g. sympy.sin(t)); calling them failed: {exc}"
            ) from exc
        extra = (ax.free_symbols | ay.free_symbols) - {t}
        if extra:
            raise ParameterError(f"Maneuver.profile: the expressions use unknown symbols {sorted(map(str, extra))}")
        return ax, ay

    def contribute(self, ctx):
        from .terms import Terms

        ax, ay = self.acceleration(ctx.t, ctx.p)
        # each element's mass under the uniform field: Q = (M r_x) a_x + (M r_y) a_y
        loads = {q: mx * ax + my * ay for q, (mx, my) in ctx.rigid_body_masses().items()}
        return Terms(loads=loads)
