"""Squeeze-film damper: short-bearing (Ocvirk) film forces on a bearing housing, pi film or full film.

The film forces are written in closed form for any motion of the journal
centre (not only centred circular orbits), so the same expressions serve the
damper and the plain journal bearing (:mod:`rotorkit.elements.journal_bearing`,
which adds the journal's spin).

Short-bearing film (the derivation)
-----------------------------------
The journal centre sits at ``(x, y)`` in a bore of radial clearance ``c``;
the angle ``theta`` is measured about ``+z`` from ``+x``, so the film
thickness is ``h = c - x cos(theta) - y sin(theta)``. The journal spins at
``Omega`` about ``+z`` (0 for a damper). Reynolds' equation without the
circumferential pressure flow (short bearing, Ocvirk), with open ends
(``p = 0`` at ``z = +-L/2``), incompressible and without fluid inertia:

    d/dz (h^3 / (12 mu) dp/dz) = (Omega / 2) dh/dtheta + dh/dt

gives ``p(theta, z) = 6 mu (L^2/4 - z^2) (a cos(theta) + b sin(theta)) / h^3`` with
the *squeeze velocity*

    a = x' + Omega y / 2,    b = y' - Omega x / 2

(the journal centre's velocity relative to a frame whirling at ``Omega/2``).
Integrated over the land, the pressure per radian is
``P(theta) = mu L^3 (a cos + b sin) / h^3`` and the force on the journal is
``F = -R integral P (cos, sin) dtheta`` (pressure pushes the journal away
from the film it acts on).

*Full film* (no cavitation, ``cavitation="full"``): the integral over the
whole circle. With ``D = c^2 - x^2 - y^2``:

    Fx = -pi mu R L^3 ((D + 3 x^2) a + 3 x y b) / D^(5/2)
    Fy = -pi mu R L^3 (3 x y a + (D + 3 y^2) b) / D^(5/2)

(from ``integral dtheta / h = 2 pi / sqrt(D)`` differentiated twice in ``x``, ``y``).

*Pi film* (Gumbel condition, ``cavitation="pi"``): negative pressures are set
to zero. ``P > 0`` where ``a cos(theta) + b sin(theta) > 0``: the positive
arc is the half circle ``theta0 - pi/2 < theta < theta0 + pi/2`` centred on
the squeeze velocity, ``theta0 = atan2(b, a)``; its ends
``theta0 +- pi/2`` move with the squeeze velocity (for every eccentricity:
``h > 0`` does not change the sign). In the frame turned by ``theta0``
(``chi = theta - theta0``), with the journal at
``p = (x a + y b) / |w|``, ``q = (y a - x b) / |w|`` (``|w| = sqrt(a^2 + b^2)``):

    H(p, q) = integral_{-pi/2}^{pi/2} dchi / (c - p cos(chi) - q sin(chi))
            = (pi + 2 atan(p / sqrt(D))) / sqrt(D)

(the substitution ``t = tan(chi/2)`` maps the half circle onto ``[-1, 1]``,
never crossing a branch), and the arc integrals are its derivatives,
``G11 = integral cos^2/h^3 = H_pp / 2``, ``G12 = integral cos sin/h^3 = H_pq / 2``:

    H_p = (2 + p H) / D,      H_q = q (2 p / (D + p^2) + H) / D
    G11 = (H + 3 p H_p) / (2 D),      G12 = (p H_q + 2 q H_p) / (2 D)
                                         = q (2 p^2 / (D + p^2) + 3 p H + 4) / (2 D^2)
    Fx = -mu R L^3 (a G11 - b G12),   Fy = -mu R L^3 (b G11 + a G12)

At ``w = 0`` the force is zero (``p = q = 0`` there by :func:`safe_div`).
The journal must stay inside the bore: ``D`` is floored at ``1e-12 c^2``
(:data:`FILM_FLOOR`), so that an integrator's trial step beyond the wall
meets a finite, enormous force (and is rejected) instead of a square root
of a negative number.
The pi-film force is smooth except where the squeeze velocity passes
through zero (the arc flips by pi): declared as the switches
``x a + y b = e e'`` (radial squeeze) and ``x b - y a = e^2 (phi' - Omega/2)``
(tangential squeeze), which vanish together there; a restart where only one
changes sign costs a step and nothing else.

Checks: a centred circular orbit of radius ``e = eps c`` at whirl ``w``
(``Omega = 0``) gives the textbook results (San Andres; Vance)
``F_r = -mu R L^3 w / c^2 * 2 eps^2 / (1 - eps^2)^2``,
``F_t = -mu R L^3 w / c^2 * pi eps / (2 (1 - eps^2)^(3/2))`` (pi film),
``F_r = 0`` and twice that ``F_t`` (full film).
"""

import math
import warnings
from dataclasses import dataclass

from ..errors import ParameterError
from .base import Element, Terms
from .rotor import check_station

__all__ = ["SqueezeFilmDamper", "ShortBearingWarning", "short_film_forces", "CAVITATION_MODELS",
           "SHORT_BEARING_LIMIT"]

#: the cavitation conditions of the film: the whole film, or its positive-pressure half (Gumbel)
CAVITATION_MODELS = ("pi", "full")
#: the film thickness floor: ``D = c^2 - x^2 - y^2`` is taken as at least ``FILM_FLOOR c^2`` (eps < 1 - 5e-13)
FILM_FLOOR = 1e-12
#: the largest land length over diameter L / (2 R) for which the short-bearing theory is taken as valid
SHORT_BEARING_LIMIT = 0.5


class ShortBearingWarning(UserWarning):
    """A land too long for the short-bearing (Ocvirk) theory: forces are overestimated."""


def short_film_forces(x, y, a, b, *, clearance, viscosity, radius, length, cavitation="pi", guarded=True):
    """Short-bearing film force on the journal, as sympy expressions (see the module docstring).

    Parameters
    ----------
    x, y : sympy.Expr
        Journal centre relative to the bore centre (m).
    a, b : sympy.Expr
        Squeeze velocity ``(x' + Omega y / 2, y' - Omega x / 2)`` (m/s).
    clearance, viscosity, radius, length : sympy.Expr
        c (m), mu (Pa s), R (m), L (m).
    cavitation : {"pi", "full"}
    guarded : bool
        True: the pi film's division by ``|w|`` is :func:`safe_div` (finite at ``w = 0``, for the equations of
        motion); False: plain division (smaller expressions, faster to differentiate, for ``w != 0`` only).

    Returns
    -------
    (Fx, Fy) : tuple of sympy.Expr
        Force on the journal (N).
    switches : tuple of sympy.Expr
        Zero crossings where the pi film's positive arc flips (empty for the full film).
    """
    import sympy as sp

    from ..symbolic.functions import hypot, ramp, safe_div

    c, k = clearance, viscosity * radius * length**3
    floor = FILM_FLOOR * c**2  # beyond the wall (a rejected trial step) the force stays finite and huge
    D = ramp(c**2 - x**2 - y**2 - floor) + floor
    s = sp.sqrt(D)
    if cavitation == "full":
        d5 = D**2 * s
        fx = -sp.pi * k * ((D + 3 * x**2) * a + 3 * x * y * b) / d5
        fy = -sp.pi * k * (3 * x * y * a + (D + 3 * y**2) * b) / d5
        return (fx, fy), ()
    if cavitation != "pi":
        raise ParameterError(f"cavitation = {cavitation!r}: expected one of {CAVITATION_MODELS}")
    radial, tangential = x * a + y * b, x * b - y * a
    if guarded:
        w = hypot(a, b)
        p, q = safe_div(radial, w), -safe_div(tangential, w)
    else:
        w = sp.sqrt(a**2 + b**2)
        p, q = radial / w, -tangential / w
    H = (sp.pi + 2 * sp.atan(p / s)) / s
    G11 = (H + 3 * p * (2 + p * H) / D) / (2 * D)
    g12 = (2 * p**2 / (D + p**2) + 3 * p * H + 4) / (2 * D**2)  # G12 = q g12
    f = q * g12
    return (-k * (a * G11 - b * f), -k * (b * G11 + a * f)), (radial, tangential)


def check_film(owner, element):
    """Shared checks of a film element: required fields, cavitation, short-bearing validity (warns)."""
    for name in ("radius", "length", "clearance", "viscosity"):
        if getattr(element, name) is None:
            raise ParameterError(f"{owner}: {name} is required ({element.unit_of(name)})")
    if element.cavitation not in CAVITATION_MODELS:
        raise ParameterError(
            f"{owner}: cavitation = {element.cavitation!r}: expected 'pi' (Gumbel: negative pressures set to "
            "zero) or 'full' (no cavitation, 2-pi film)")
    if element.clearance >= element.radius:
        raise ParameterError(
            f"{owner}: clearance = {element.clearance!r} m is not smaller than radius = {element.radius!r} m: "
            "expected a thin film (c / R of order 1e-3)")
    ratio = element.length / (2.0 * element.radius)
    if ratio > SHORT_BEARING_LIMIT:
        warnings.warn(
            f"{owner}: L/D = length / (2 radius) = {ratio:.3g} > {SHORT_BEARING_LIMIT}: the short-bearing "
            "(Ocvirk) theory, which neglects the circumferential pressure flow, overestimates the film forces of so "
            f"long a land; expected L/D <= {SHORT_BEARING_LIMIT}", ShortBearingWarning, stacklevel=5)


@dataclass(frozen=True, slots=True, kw_only=True)
class SqueezeFilmDamper(Element):
    """A squeeze-film damper between a station (the bearing housing) and the ground.

    The non-rotating journal (the outer ring of a rolling bearing) whirls in
    an oil-filled bore concentric with the undeflected axis; its film force
    is the short-bearing (Ocvirk) force of :func:`short_film_forces` with
    ``Omega = 0``: open ends, incompressible, no fluid inertia, isothermal
    (constant ``mu``), rigid surfaces. With ``cavitation="pi"`` only the
    positive pressure acts (Gumbel); ``"full"`` keeps the whole film (a
    sealed, pressurised damper). A centring spring (squirrel cage) of
    stiffness ``k_s`` and damping ``c_s`` may act in parallel:
    ``V = k_s ((x - x_0)^2 + (y - y_0)^2) / 2``, ``D = c_s (x'^2 + y'^2) / 2``,
    whose neutral point ``(x_0, y_0)`` (the static offset) is the journal's
    rest position in the bore without other loads (offset SFD; e.g.
    ``offset_y = m g / k_s`` centres a journal sagging under gravity).

    Sign conventions: ``x``, ``y`` are the station's lateral displacements
    from the bore centre; the force acts on the station. The film force has
    no stiffness at rest: without a centring spring the damper grounds
    nothing, and the rotor must be held by other elements.

    Parameters
    ----------
    station : int or str
        Station of the bearing housing (journal).
    radius : float or pint.Quantity
        Journal radius R (m), > 0.
    length : float or pint.Quantity
        Land length L (m), > 0; ``L / (2 R) > 0.5`` warns (:class:`ShortBearingWarning`).
    clearance : float or pint.Quantity
        Radial clearance c (m), 0 < c < R. The journal must stay inside
        (``x^2 + y^2 < c^2``): the force grows without bound at the wall.
    viscosity : float or pint.Quantity
        Dynamic viscosity mu (Pa s), > 0.
    cavitation : {"pi", "full"}
        Film model (structural: it changes the equations' form).
    centring_stiffness : float or pint.Quantity, optional
        k_s (N/m), > 0.
    centring_damping : float or pint.Quantity, optional
        c_s (N s/m), >= 0.
    offset_x, offset_y : float or pint.Quantity, optional
        Neutral point of the centring spring relative to the bore centre
        (m), inside the clearance; needs ``centring_stiffness``.

    Examples
    --------
    >>> sfd = SqueezeFilmDamper(station=1, radius=0.05, length=0.02, clearance=1.5e-4,
    ...                         viscosity=0.01, centring_stiffness=5e6)
    >>> sfd.label(), round(sfd.centred_damping(), 1)   # pi film: pi mu R L^3 / (2 c^3) (N s/m)
    ('sfd1', 1861.7)
    """

    station: int | str = None
    radius: float = None
    length: float = None
    clearance: float = None
    viscosity: float = None
    cavitation: str = "pi"
    centring_stiffness: float | None = None
    centring_damping: float | None = None
    offset_x: float | None = None
    offset_y: float | None = None

    _units = {
        "radius": ("m", "positive"),
        "length": ("m", "positive"),
        "clearance": ("m", "positive"),
        "viscosity": ("Pa*s", "positive"),
        "centring_stiffness": ("N/m", "positive"),
        "centring_damping": ("N*s/m", "nonnegative"),
        "offset_x": ("m", None),
        "offset_y": ("m", None),
    }
    _latex_names = {
        "radius": "R",
        "length": "L",
        "clearance": "c",
        "viscosity": r"\mu",
        "centring_stiffness": "k_s",
        "centring_damping": "c_s",
        "offset_x": "x_0",
        "offset_y": "y_0",
    }

    def _validate(self):
        object.__setattr__(self, "station", check_station("SqueezeFilmDamper", self.station, "station"))
        who = f"SqueezeFilmDamper at station {self.station!r}"
        check_film(who, self)
        offset = (self.offset_x, self.offset_y)
        if any(v is not None for v in offset):
            if self.centring_stiffness is None:
                raise ParameterError(
                    f"{who}: offset_x/offset_y = {offset!r} is the centring spring's neutral point; give "
                    "centring_stiffness=... (N/m) too")
            r = math.hypot(*(v or 0.0 for v in offset))
            if r >= self.clearance:
                raise ParameterError(
                    f"{who}: the static offset {r:.4g} m is not inside the clearance {self.clearance:.4g} m: "
                    "expected sqrt(offset_x^2 + offset_y^2) < clearance")
        if self.centring_damping is not None and self.centring_stiffness is None:
            raise ParameterError(f"{who}: centring_damping needs centring_stiffness (the squirrel cage)")

    def attached_stations(self):
        return (self.station,)

    def _default_label(self):
        return f"sfd{self.station}"

    def grounds(self):
        return ((self.station, "x"), (self.station, "y")) if self.centring_stiffness is not None else ()

    def effects(self):
        return frozenset({"squeeze_film"})

    def centred_damping(self):
        """Damping coefficient of the film at the centre (N s/m): ``pi mu R L^3 / c^3`` (full), half that (pi)."""
        full = math.pi * self.viscosity * self.radius * self.length**3 / self.clearance**3
        return full if self.cavitation == "full" else full / 2

    def contribute(self, ctx):
        p = ctx.p
        (x, xd), (y, yd) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        (fx, fy), switches = short_film_forces(
            x, y, xd, yd, clearance=p["clearance"], viscosity=p["viscosity"], radius=p["radius"],
            length=p["length"], cavitation=self.cavitation)
        potential = dissipation = None
        if self.centring_stiffness is not None:
            x0 = p["offset_x"] if self.offset_x is not None else 0
            y0 = p["offset_y"] if self.offset_y is not None else 0
            potential = p["centring_stiffness"] * ((x - x0) ** 2 + (y - y0) ** 2) / 2
        if self.centring_damping is not None:
            dissipation = p["centring_damping"] * (xd**2 + yd**2) / 2
        return Terms(potential=potential, dissipation=dissipation, loads={x: fx, y: fy}, switches=switches)
