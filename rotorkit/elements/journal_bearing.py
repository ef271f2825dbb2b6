"""Plain journal bearing: short-bearing (Ocvirk) film forces with the journal's spin, and its operating point.

The film force is :func:`~rotorkit.elements.squeeze_film.short_film_forces`
with the squeeze velocity ``(a, b) = (x' + Omega y / 2, y' - Omega x / 2)``:
the journal spinning at ``Omega`` drags the oil at ``Omega / 2`` on average,
so the bearing acts on the journal's velocity relative to a frame whirling at
half the spin speed. Fully nonlinear in ``x, y, x', y'``; the linearised
coefficients at the static equilibrium follow by differentiating the same
expressions (:meth:`JournalBearing.operating_point`).

Static equilibrium of the short pi-film bearing (Ocvirk; Friswell et al.,
*Dynamics of Rotating Machines*, section 5.5; Childs, *Turbomachinery
Rotordynamics*): with the modified Sommerfeld number
``S_s = mu D Omega L^3 / (8 W c^2)`` (``D = 2 R``, ``W`` the load),

    1 / S_s = eps sqrt(16 eps^2 + pi^2 (1 - eps^2)) / (1 - eps^2)^2,
    tan(phi) = pi sqrt(1 - eps^2) / (4 eps),

i.e. ``eps^2`` is the root in (0, 1) of the quartic
``u^4 - 4 u^3 + (6 - S_s^2 (16 - pi^2)) u^2 - (4 + pi^2 S_s^2) u + 1 = 0``.
The attitude angle ``phi`` turns the eccentricity from the load direction in
the direction of rotation. The classical Sommerfeld number is
``S = mu N L D (R / c)^2 / W = (R / L)^2 4 S_s / pi`` (``N = Omega / (2 pi)`` rev/s).
The full film (no cavitation) has ``phi = 90 deg`` and
``1 / S_s = 2 pi eps / (1 - eps^2)^(3/2)``.
"""

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..units import to_si
from .base import Element, Terms
from .rotor import check_station
from .squeeze_film import check_film, short_film_forces

__all__ = ["JournalBearing", "BearingOperatingPoint", "short_bearing_eccentricity", "static_load_vector"]


def short_bearing_eccentricity(modified_sommerfeld, cavitation="pi"):
    """Eccentricity ratio and attitude angle (rad) of a short bearing at a modified Sommerfeld number.

    Parameters
    ----------
    modified_sommerfeld : float
        ``S_s = mu D Omega L^3 / (8 W c^2)`` (dimensionless), > 0.
    cavitation : {"pi", "full"}

    Returns
    -------
    (eps, phi) : tuple of float
        Eccentricity ratio in (0, 1) and attitude angle (rad) from the load line.

    Examples
    --------
    >>> eps, phi = short_bearing_eccentricity(0.1)
    >>> round(eps, 4), round(math.degrees(phi), 2)
    (0.7048, 38.33)
    """
    s = float(modified_sommerfeld)
    if not (math.isfinite(s) and s > 0):
        raise ParameterError(f"modified_sommerfeld = {modified_sommerfeld!r}: expected a finite number > 0")
    if cavitation == "full":
        from scipy.optimize import brentq

        eps = brentq(lambda e: 2 * math.pi * s * e - (1 - e * e) ** 1.5, 0.0, 1.0, xtol=1e-15, rtol=1e-15)
        return eps, math.pi / 2
    pi2 = math.pi**2
    roots = np.roots([1.0, -4.0, 6.0 - s * s * (16.0 - pi2), -(4.0 + pi2 * s * s), 1.0])
    real = [r.real for r in roots if abs(r.imag) <= 1e-9 * max(1.0, abs(r)) and 0.0 < r.real < 1.0]
    if not real:
        raise ParameterError(f"modified_sommerfeld = {s!r}: no eccentricity ratio in (0, 1) found")
    u = min(real, key=lambda v: abs(v * (16 * v + pi2 * (1 - v)) * s * s - (1 - v) ** 4))
    eps = math.sqrt(u)
    return eps, math.atan2(math.pi * math.sqrt(1 - u), 4 * eps)


@dataclass(frozen=True)
class BearingOperatingPoint:
    """A journal bearing at its static equilibrium under a load.

    Attributes
    ----------
    load : numpy.ndarray, shape (2,)
        Static load on the journal (N), ``(F_x, F_y)``; the film carries its negative.
    speed : float
        Journal spin speed (rad/s).
    sommerfeld, modified_sommerfeld : float
        ``S = mu N L D (R/c)^2 / W`` and ``S_s = mu D Omega L^3 / (8 W c^2)``.
    eccentricity_ratio, attitude_angle : float
        ``eps = e / c`` and the angle (rad) from the load to the eccentricity, in the direction of rotation.
    position : numpy.ndarray, shape (2,)
        Journal centre ``(x, y)`` (m).
    stiffness, damping : numpy.ndarray, shape (2, 2)
        ``K = -dF/dq`` (N/m) and ``C = -dF/dq'`` (N s/m) in ``x, y`` order, from the derived Jacobian of
        the film force: the bearing force near the equilibrium is ``F0 - K dq - C dq'``.
    """

    load: np.ndarray
    speed: float
    sommerfeld: float
    modified_sommerfeld: float
    eccentricity_ratio: float
    attitude_angle: float
    position: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray


def _film_jacobian(forces, symbols, point, steps):
    """``d(Fx, Fy) / d(symbols)`` at ``point``: complex-step derivatives of the force expressions.

    ``Im F(q + i h e_j) / h`` is the derivative of the very expressions the equations of motion hold, exact to
    rounding for any tiny ``h`` (no subtraction): the expressions are analytic at an equilibrium with a
    nonzero squeeze velocity. Cheaper than differentiating them symbolically and printing the result.
    """
    import cmath

    import sympy as sp

    complex_functions = {"safe_div": lambda u, v: u / v if v != 0 else 0.0,
                         "hypot": lambda u, v: cmath.sqrt(u * u + v * v), "sqrt": cmath.sqrt, "atan": cmath.atan,
                         "ramp": lambda u: u if u.real > 0 else 0j}
    f = sp.lambdify(symbols, list(forces), modules=[complex_functions, "math"])
    J = np.empty((len(forces), len(symbols)))
    for j, h in enumerate(steps):
        z = [complex(v) for v in point]
        z[j] += 1j * h
        J[:, j] = [value.imag / h for value in f(*z)]
    return J


@dataclass(frozen=True, slots=True, kw_only=True)
class JournalBearing(Element):
    """A plain (cylindrical) journal bearing between a station and the ground, short-bearing theory.

    The journal at the station spins at its rotor's speed ``Omega`` (constant,
    a speed profile or a speed ratio: read from the model) in a fixed bore
    concentric with the undeflected axis. The film force on the station is
    the short-bearing (Ocvirk) force for open ends, incompressible and
    isothermal oil, no fluid inertia, rigid aligned surfaces; with
    ``cavitation="pi"`` (default, Gumbel / half-Sommerfeld) negative
    pressures are zero, with ``"full"`` the whole film acts. See the module
    docstrings of :mod:`rotorkit.elements.journal_bearing` and
    :mod:`rotorkit.elements.squeeze_film` for the formulas. ``x``, ``y``
    are measured from the bore centre; positive ``Omega`` turns about ``+z``.
    The bearing grounds the station through its hydrodynamic stiffness,
    which vanishes at zero speed (a rotor at rest on journal bearings has no
    static equilibrium).

    Parameters
    ----------
    station : int or str
    radius : float or pint.Quantity
        Journal radius R (m), > 0.
    length : float or pint.Quantity
        Bearing length L (m), > 0; ``L / (2 R) > 0.5`` warns (short-bearing validity).
    clearance : float or pint.Quantity
        Radial clearance c (m), 0 < c < R.
    viscosity : float or pint.Quantity
        Dynamic viscosity mu (Pa s), > 0.
    cavitation : {"pi", "full"}
        Film model (structural).

    Examples
    --------
    >>> jb = JournalBearing(station=1, radius=0.025, length=0.02, clearance=5e-5, viscosity=0.02)
    >>> op = jb.operating_point(load=500.0, speed=1000.0)
    >>> round(op.eccentricity_ratio, 4), round(math.degrees(op.attitude_angle), 2)
    (0.3139, 67.17)
    """

    station: int | str = None
    radius: float = None
    length: float = None
    clearance: float = None
    viscosity: float = None
    cavitation: str = "pi"

    _units = {
        "radius": ("m", "positive"),
        "length": ("m", "positive"),
        "clearance": ("m", "positive"),
        "viscosity": ("Pa*s", "positive"),
    }
    _latex_names = {"radius": "R", "length": "L", "clearance": "c", "viscosity": r"\mu"}

    def _validate(self):
        object.__setattr__(self, "station", check_station("JournalBearing", self.station, "station"))
        check_film(f"JournalBearing at station {self.station!r}", self)

    def attached_stations(self):
        return (self.station,)

    def _default_label(self):
        return f"journal{self.station}"

    def grounds(self):
        return ((self.station, "x"), (self.station, "y"))

    def effects(self):
        return frozenset({"journal_bearing"})

    def film_forces(self, x, y, xd, yd, speed, p=None, guarded=True):
        """Film force ``(Fx, Fy)`` and switches as sympy expressions; ``p`` maps fields to symbols (default: values).

        ``guarded=False`` writes the pi film without the guard at zero squeeze velocity (see
        :func:`~rotorkit.elements.squeeze_film.short_film_forces`).
        """
        p = p or {f: getattr(self, f) for f in self._units}
        a, b = xd + speed * y / 2, yd - speed * x / 2
        return short_film_forces(x, y, a, b, clearance=p["clearance"], viscosity=p["viscosity"],
                                 radius=p["radius"], length=p["length"], cavitation=self.cavitation,
                                 guarded=guarded)

    def contribute(self, ctx):
        (x, xd), (y, yd) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        (fx, fy), switches = self.film_forces(x, y, xd, yd, ctx.speed(self.station), ctx.p)
        return Terms(loads={x: fx, y: fy}, switches=switches)

    # -- operating point ------------------------------------------------------
    def sommerfeld_numbers(self, load, speed):
        """``(S, S_s)``: Sommerfeld ``mu N L D (R/c)^2 / W`` and modified ``mu D Omega L^3 / (8 W c^2)``."""
        w = float(np.hypot(*static_load_vector(load, f"JournalBearing {self.label()!r}")))
        omega = abs(self._speed(speed))
        mu, R, L, c = self.viscosity, self.radius, self.length, self.clearance
        return (mu * omega / (2 * math.pi) * L * 2 * R * (R / c) ** 2 / w, mu * 2 * R * omega * L**3 / (8 * w * c**2))

    def operating_point(self, load, speed):
        """Static equilibrium under ``load`` at ``speed`` (closed form) and the linearised coefficients there.

        Parameters
        ----------
        load : float, pint.Quantity or (float, float)
            A magnitude (N, > 0) acting in ``-y`` (gravity), or the load vector ``(F_x, F_y)`` (N) on the journal.
        speed : float, pint.Quantity or str
            Journal spin speed (rad/s, ``"3000 rpm"``), nonzero.

        Returns
        -------
        BearingOperatingPoint
            The eight coefficients are the derivatives of the film force expressions used in the equations
            of motion, at ``(x, y)`` with zero velocity (the model's own analytic Jacobian gives the same:
            :func:`rotorkit.linear.linearize.linearize`).
        """
        import sympy as sp

        F = static_load_vector(load, f"JournalBearing {self.label()!r}")
        omega = self._speed(speed)
        S, Ss = self.sommerfeld_numbers(F, omega)
        eps, phi = short_bearing_eccentricity(Ss, self.cavitation)
        angle = math.atan2(F[1], F[0]) + math.copysign(phi, omega)
        position = eps * self.clearance * np.array([math.cos(angle), math.sin(angle)])
        x, y, xd, yd = sp.symbols("x y xd yd", real=True)
        (fx, fy), _ = self.film_forces(x, y, xd, yd, omega, guarded=False)  # w != 0 at the equilibrium
        h = 1e-20 * self.clearance
        J = _film_jacobian((fx, fy), (x, y, xd, yd), (*position, 0.0, 0.0), (h, h, h * abs(omega), h * abs(omega)))
        return BearingOperatingPoint(load=F, speed=omega, sommerfeld=S, modified_sommerfeld=Ss,
                                     eccentricity_ratio=eps, attitude_angle=phi, position=position,
                                     stiffness=-J[:, :2], damping=-J[:, 2:])

    def _speed(self, speed):
        who = f"JournalBearing {self.label()!r}"
        if isinstance(speed, numbers.Real) and not isinstance(speed, bool):
            omega = float(speed)
        else:
            omega = to_si(speed, "rad/s", f"{who} speed")
        if not (math.isfinite(omega) and omega != 0.0):
            raise ParameterError(f"{who}: speed = {speed!r}: expected a nonzero spin speed (rad/s): a bearing at "
                                 "rest carries no load")
        return omega


def static_load_vector(load, who):
    """The static load ``(F_x, F_y)`` (N) on a bearing from a magnitude (N, acting in -y) or a vector."""
    if load is None:
        raise ParameterError(f"{who}: load is required (N, > 0, or a vector (F_x, F_y))")
    if isinstance(load, (tuple, list, np.ndarray)):
        if len(load) != 2:
            raise ParameterError(f"{who}: load = {load!r}: expected a magnitude (N) or a vector (F_x, F_y) (N)")
        F = np.array([to_si(v, "N", f"{who} load[{i}]") for i, v in enumerate(load)])
    else:
        F = np.array([0.0, -to_si(load, "N", f"{who} load", sign="positive")])
    if not np.all(np.isfinite(F)):
        raise ParameterError(f"{who}: load = {load!r}: expected a finite static load (N)")
    if not np.hypot(*F) > 0:
        raise ParameterError(f"{who}: load = {load!r} is zero: expected a static load to find the equilibrium")
    return F
