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
the Coriolis term couples ``x`` and ``y``); the same on pedestal masses and,
through the consistent translational mass, on beam elements' distributed
mass; on spinning parts with tilt coordinates (disks with diametral inertia,
beam sections) the gyroscopic moment of spin and base rate, the Euler
moments and the centrifugal tilt terms (:func:`tilt_kinetic`).
Neglected: the offset of an eccentric disk's centroid in these loads (order
``e W^2``, against the unbalance's ``e Omega^2``), the axial component
``F_z`` (no axial coordinate). The translation of the base's reference
point and gravity are a :class:`~rotorkit.elements.maneuver.Maneuver` field;
combine the two (gravity turns with the base in a pull-up: give it as
``Maneuver.profile``).

Examples
--------
A steady level turn at 0.5 rad/s about a vertical axis 800 m to the left:

>>> turn = BaseRotation(rate_y=0.5, center_x=-800.0)
>>> sorted(turn.parameters())
['center_x', 'center_y', 'center_z', 'rate_x', 'rate_y', 'rate_z']
"""

from dataclasses import dataclass
from types import SimpleNamespace

from ..errors import ParameterError
from ..units import to_si
from .base import Element, Terms
from .rotor import check_station

__all__ = ["BaseRotation", "base_frame", "point_mass_loads", "tilt_kinetic", "tilt_loads"]


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
            import sympy as sp

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
        import sympy as sp

        t = sp.Symbol("t", real=True)
        return (type(self).__name__, self.label(), tuple(sp.srepr(w) for w in self.rates(t, {})),
                self.axial_positions)

    def rates(self, t, p):
        """(W_x, W_y, W_z) as sympy expressions."""
        import sympy as sp

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

    def axial_position(self, station):
        """Axial position ``z_s`` (m) of a station given in ``axial_positions``, or None."""
        return dict(self.axial_positions).get(station)

    def frame(self, ctx):
        """The base motion as expressions: ``(W, W', c)`` (3x1 sympy matrices) and a ``z(station)`` function.

        ``ctx`` may be bound to any element: the symbols are this element's
        parameters.
        """
        import sympy as sp

        p = {f: ctx.parameter(self, f) for f in self.parameters()}
        W = sp.Matrix(self.rates(ctx.t, p))
        c = sp.Matrix([p[f"center_{a}"] for a in "xyz"])
        z_of = dict(self.axial_positions)
        return SimpleNamespace(W=W, Wd=W.diff(ctx.t), c=c, z=lambda s: sp.Float(z_of.get(s, 0.0)), positions=z_of)

    def contribute(self, ctx):
        frame = self.frame(ctx)
        loads = {}
        for station, mass in ctx.masses():
            (x, xd), (y, yd) = ctx.coord(station, "x"), ctx.coord(station, "y")
            for q, f in point_mass_loads(mass, (x, y), (xd, yd), frame.z(station), frame).items():
                loads[q] = loads.get(q, 0) + f
        return Terms(loads=loads)


def base_frame(ctx):
    """The model's :class:`BaseRotation` frame (see :meth:`BaseRotation.frame`), or None without one."""
    for e in ctx.model.elements:
        if isinstance(e, BaseRotation):
            return e.frame(ctx)
    return None


def point_mass_loads(mass, q, u, z, frame):
    """``{x: F_x, y: F_y}``: the Euler, centripetal and Coriolis loads on a point mass at ``(x, y, z)``."""
    import sympy as sp

    (x, y), (xd, yd) = q, u
    r = sp.Matrix([x, y, z]) - frame.c
    v = sp.Matrix([xd, yd, 0])
    a = frame.Wd.cross(r) + frame.W.cross(frame.W.cross(r)) + 2 * frame.W.cross(v)
    out = {}
    fx, fy = sp.expand(-mass * a[0]), sp.expand(-mass * a[1])
    if fx != 0:
        out[x] = fx
    if fy != 0:
        out[y] = fy
    return out


def tilt_kinetic(Id, Ip, spin, tilts, rates, W):
    """Kinetic energy a turning base adds to a spinning body with tilts, to second order in the tilts.

    A body with diametral inertia ``Id`` and polar inertia ``Ip`` (kg m^2,
    or per unit length) spins at ``spin`` relative to the base and tilts by
    ``a = thx``, ``b = thy`` (rates ``a'``, ``b'``); the base turns at
    ``W = (W_x, W_y, W_z)``. Its angular velocity is the base's plus the
    relative one, and ``T = 1/2 [Id (w_1^2 + w_2^2) + Ip w_3^2]`` in the
    tilted (Resal) frame; the part that ``W`` adds, to second order in
    ``(a, b, a', b')`` and without the constant, is ::

        Id (W_x a' + W_y b') + Id W_z (a b' - a' b) + Ip W_z a' b
        + (Id W_z - Ip (spin + W_z)) (W_y a - W_x b) + (Id - Ip) W_x W_y a b
        + ((Id - Ip)(W_z^2 - W_y^2) - Ip spin W_z) a^2 / 2
        + ((Id - Ip)(W_z^2 - W_x^2) - Ip spin W_z) b^2 / 2

    whose Lagrange equations hold the gyroscopic moment of the spin and the
    base rate (``-Ip spin W_y`` on ``thx``, ``+Ip spin W_x`` on ``thy``), the
    Euler moments ``-Id W'`` and the centrifugal terms of the base rotation.
    """
    (a, b), (ad, bd) = tilts, rates
    Wx, Wy, Wz = W
    return (Id * (Wx * ad + Wy * bd) + Id * Wz * (a * bd - ad * b) + Ip * Wz * ad * b
            + (Id * Wz - Ip * (spin + Wz)) * (Wy * a - Wx * b) + (Id - Ip) * Wx * Wy * a * b
            + ((Id - Ip) * (Wz**2 - Wy**2) - Ip * spin * Wz) * a**2 / 2
            + ((Id - Ip) * (Wz**2 - Wx**2) - Ip * spin * Wz) * b**2 / 2)


def tilt_loads(Id, Ip, spin, W, t, q, u, Va, Vb, Mr, R):
    """Generalised loads of :func:`tilt_kinetic` over interpolated tilts, by matrices (no symbolic differentiation).

    The tilts are ``thx(z) = N(z) Va q`` and ``thy(z) = N(z) Vb q`` with
    the element's coordinates ``q`` (n x 1; speeds ``u``), ``Va``, ``Vb``
    (m x n) picking the nodal tilts and ``N`` the m rotation shape functions;
    ``Mr = int N^T N dz`` (m x m) and ``R = int N^T dz`` (m x 1). ``Id``,
    ``Ip`` are per unit length. The energy is a sum of terms ``c(t) w1^T B w2``
    and ``c(t) r^T w`` (``w`` = q or u), whose Lagrange loads are written out:
    ``c (B + B^T) q`` for ``q q`` terms, ``c B^T u - c' B q - c B u`` for
    ``u^T B q``, ``c r`` for ``r^T q`` and ``-c' r`` for ``r^T u``.

    Returns
    -------
    sympy.Matrix
        n x 1 loads on ``q``.
    """
    import sympy as sp

    a, b, ad, bd = sp.symbols("_a _b _ad _bd", real=True)
    fields = {a: ("q", Va), b: ("q", Vb), ad: ("u", Va), bd: ("u", Vb)}
    energy = sp.Poly(tilt_kinetic(Id, Ip, spin, (a, b), (ad, bd), W), a, b, ad, bd)
    Q = sp.zeros(len(q), 1)
    for monomial, c in zip(energy.monoms(), energy.coeffs()):
        gens = [g for g, power in zip((a, b, ad, bd), monomial) for _ in range(power)]
        dc = sp.diff(c, t)
        if len(gens) == 2:
            (k1, V1), (k2, V2) = fields[gens[0]], fields[gens[1]]
            if k1 == "q" and k2 == "u":
                (k1, V1), (k2, V2) = (k2, V2), (k1, V1)
            B = V1.T * Mr * V2
            if k1 == "q":  # q^T B q
                Q += c * (B + B.T) * q
            elif k2 == "q":  # u^T B q
                Q += c * B.T * u - c * B * u - (dc * B * q if dc != 0 else sp.zeros(len(q), 1))
            else:
                raise AssertionError("tilt_kinetic has no terms quadratic in the tilt rates")
        elif len(gens) == 1:
            kind, V = fields[gens[0]]
            r = V.T * R
            Q += c * r if kind == "q" else -dc * r
    return Q
