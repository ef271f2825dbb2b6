"""Plain cylindrical journal bearing from its geometry: static equilibrium and the eight coefficients against speed.

:class:`PlainJournalBearing` solves the finite-length Reynolds equation with
the Reynolds (Swift-Stieber) cavitation condition
(:mod:`rotorkit.fluidfilm.reynolds`) for the journal position that carries
the load at a speed, and the linearised film there:

    F = F0 - K dq - C dq',   K = -dF/dq,   C = -dF/dq'   (q = (x, y) of the journal),

the first-order perturbation of the film (central differences in position,
exact in velocity, the cavitation boundary held: its motion is second
order under the Reynolds condition). :meth:`PlainJournalBearing.coefficients`
tabulates them against speed and
:meth:`BearingCoefficients.to_linear_bearing` hands the table to
:class:`~rotorkit.elements.linear_bearing.LinearBearing`.

Dimensionless numbers (as in Someya's *Journal-Bearing Databook* and Lund):
Sommerfeld ``S = mu N L D (R/c)^2 / W`` (``N = Omega / (2 pi)`` rev/s),
``k_ij = K_ij c / W``, ``b_ij = C_ij c Omega / W``.
"""

import math
from dataclasses import dataclass

import numpy as np

from ..elements.journal_bearing import static_load_vector
from ..errors import ParameterError
from ..units import to_si
from .reynolds import FilmGrid, film_derivatives, solve_film

__all__ = ["PlainJournalBearing", "BearingCoefficients"]

_FIELDS = ("kxx", "kxy", "kyx", "kyy", "cxx", "cxy", "cyx", "cyy")


@dataclass(frozen=True)
class BearingCoefficients:
    """Static equilibrium and linearised film of a journal bearing at a list of speeds.

    Attributes
    ----------
    speeds : numpy.ndarray, shape (n,)
        Journal speeds (rad/s), increasing.
    sommerfeld : numpy.ndarray, shape (n,)
        ``S = mu N L D (R/c)^2 / W``.
    eccentricity_ratio, attitude_angle : numpy.ndarray, shape (n,)
        ``e / c`` and the angle (rad) from the load to the eccentricity, in the direction of rotation.
    position : numpy.ndarray, shape (n, 2)
        Journal centre ``(x, y)`` (m) from the bore centre.
    stiffness, damping : numpy.ndarray, shape (n, 2, 2)
        ``K`` (N/m) and ``C`` (N s/m), ``[[xx, xy], [yx, yy]]``.
    load : numpy.ndarray, shape (2,)
        The static load on the journal (N); the film carries its negative.
    clearance : float
        Radial clearance c (m).
    """

    speeds: np.ndarray
    sommerfeld: np.ndarray
    eccentricity_ratio: np.ndarray
    attitude_angle: np.ndarray
    position: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray
    load: np.ndarray
    clearance: float

    def as_dict(self):
        """``{"kxx": array (n,), ..., "cyy": ...}`` in SI (N/m, N s/m)."""
        return {f: (self.stiffness if f[0] == "k" else self.damping)[:, "xy".index(f[1]), "xy".index(f[2])]
                for f in _FIELDS}

    def dimensionless(self):
        """``{"kxx": K c / W, ..., "cxx": C c Omega / W, ...}``, arrays (n,) (the Databook's ``k_ij``, ``b_ij``)."""
        w = float(np.hypot(*self.load))
        return {f: v * self.clearance / w * (1.0 if f[0] == "k" else self.speeds)
                for f, v in self.as_dict().items()}

    def plot(self, kind="stiffness", ax=None, dimensionless=False):
        """The four ``kind`` ("stiffness" or "damping") coefficients against speed; returns the lines.

        ``dimensionless=True`` plots ``K c / W`` or ``C c Omega / W`` (the Databook's ``k_ij``, ``b_ij``). Draws on
        ``ax`` (default: the current axes).
        """
        import matplotlib.pyplot as plt

        if kind not in ("stiffness", "damping"):
            raise ParameterError(f"BearingCoefficients.plot: kind = {kind!r}: expected 'stiffness' or 'damping'")
        ax = plt.gca() if ax is None else ax
        values = self.dimensionless() if dimensionless else self.as_dict()
        fields = _FIELDS[:4] if kind == "stiffness" else _FIELDS[4:]
        lines = [ax.plot(self.speeds, values[f], marker="o", label=f)[0] for f in fields]
        unit = "" if dimensionless else (" (N/m)" if kind == "stiffness" else " (N s/m)")
        ax.set_xlabel("speed (rad/s)")
        ax.set_ylabel(f"{kind}{unit}")
        ax.legend()
        return lines

    def to_linear_bearing(self, station, *, interpolation="pchip", extrapolation="hold", name=None, **options):
        """A :class:`~rotorkit.elements.linear_bearing.LinearBearing` tabulated at these speeds (constant at one).

        ``interpolation`` ("pchip" by default: monotone between the computed points) and ``extrapolation``
        ("hold") as in :meth:`LinearBearing.tabulated`; ``options`` go there too (``other_station``,
        ``pedestal``).
        """
        from ..elements.linear_bearing import LinearBearing

        if self.speeds.size == 1:  # one speed: constant coefficients, no table
            return LinearBearing(station=station, name=name, **options,
                                 **{f: float(v[0]) for f, v in self.as_dict().items()})
        table = {f: [float(v) for v in values] for f, values in self.as_dict().items()}
        return LinearBearing.tabulated(station=station, speeds=[float(w) for w in self.speeds], name=name,
                                       interpolation=interpolation, extrapolation=extrapolation, **options, **table)


@dataclass(frozen=True, slots=True, kw_only=True)
class PlainJournalBearing:
    """A plain (360 degree, cylindrical) journal bearing: geometry, oil and static load.

    Isoviscous, laminar, incompressible, rigid aligned surfaces, Reynolds
    (Swift-Stieber) cavitation; the film is computed by finite differences
    (:mod:`rotorkit.fluidfilm.reynolds`). Coordinates as
    :class:`~rotorkit.elements.journal_bearing.JournalBearing`: ``x, y``
    from the bore centre, the journal spins about ``+z``.

    Parameters
    ----------
    diameter : float or pint.Quantity or str
        Journal diameter D (m), > 0.
    length : float or pint.Quantity or str
        Bearing length L (m), > 0.
    clearance : float or pint.Quantity or str
        Radial clearance c (m), 0 < c < D/2.
    viscosity : float or pint.Quantity or str
        Dynamic viscosity mu (Pa s), > 0.
    load : float, pint.Quantity, str or (float, float)
        Static load on the journal: a magnitude (N, > 0) acting in ``-y``, or the vector ``(F_x, F_y)`` (N);
        stored as the vector, a tuple of floats.
    grooves : tuple of (float, float)
        Axial supply grooves held at ambient pressure: ``(centre, width)`` in degrees, the centre measured
        from ``+x`` about ``+z`` (fixed in the bore). Default none: a plain 360 degree film. The nodes within
        ``width / 2`` of the centre are held at ambient pressure, so the groove the grid sees spans its outermost
        nodes: choose ``n_theta`` so that the edges fall on nodes (``width`` a multiple of ``360 / n_theta``).
    n_theta, n_z : int
        Finite-difference nodes around the circumference (>= 24) and on the half length (>= 4).

    Examples
    --------
    >>> b = PlainJournalBearing(diameter="100 mm", length="50 mm", clearance="100 um", viscosity="0.03 Pa*s",
    ...                         load="5 kN")
    >>> op = b.coefficients(["3000 rpm"])
    >>> round(float(op.eccentricity_ratio[0]), 2)
    0.57
    """

    diameter: float = None
    length: float = None
    clearance: float = None
    viscosity: float = None
    load: object = None
    grooves: tuple = ()
    n_theta: int = 72
    n_z: int = 12

    def __post_init__(self):
        who = "PlainJournalBearing"
        for name, unit in (("diameter", "m"), ("length", "m"), ("clearance", "m"), ("viscosity", "Pa*s")):
            value = getattr(self, name)
            if value is None:
                raise ParameterError(f"{who}: {name} is required ({unit}, > 0)")
            object.__setattr__(self, name, to_si(value, unit, f"{who} {name}", sign="positive"))
        if not self.clearance < self.diameter / 2:
            raise ParameterError(f"{who}: clearance = {self.clearance!r} m: expected less than the radius "
                                 f"{self.diameter / 2!r} m")
        object.__setattr__(self, "load", tuple(float(v) for v in static_load_vector(self.load, who)))  # hashable
        grooves = []
        for k, groove in enumerate(self.grooves):
            try:
                centre, width = (float(v) for v in groove)
            except (TypeError, ValueError):
                raise ParameterError(f"{who}: grooves[{k}] = {groove!r}: expected (centre, width) in degrees") from None
            if not (math.isfinite(centre) and 0 < width < 180):
                raise ParameterError(f"{who}: grooves[{k}] = {groove!r}: expected a finite centre and a width in "
                                     "(0, 180) degrees")
            grooves.append((centre, width))
        object.__setattr__(self, "grooves", tuple(grooves))
        FilmGrid(slenderness=self.length / self.diameter, n_theta=self.n_theta, n_z=self.n_z)  # checks the grid

    # -- derived quantities ----------------------------------------------------
    @property
    def grid(self):
        """The :class:`~rotorkit.fluidfilm.reynolds.FilmGrid` of this bearing."""
        return FilmGrid(slenderness=self.length / self.diameter, n_theta=self.n_theta, n_z=self.n_z)

    def _groove_mask(self, grid):
        """The angles of ``grid`` inside a groove, shape (n_theta,), or None without grooves."""
        if not self.grooves:
            return None
        mask = np.zeros(grid.n_theta, bool)
        for centre, width in self.grooves:
            distance = np.abs((grid.theta - math.radians(centre) + math.pi) % (2 * math.pi) - math.pi)
            mask |= distance <= math.radians(width) / 2 + 1e-12
        return mask

    def _force_scale(self, omega):
        """``mu Omega R^3 L / (2 c^2)`` (N): the dimensionless film force times this is the force."""
        R = self.diameter / 2
        return self.viscosity * omega * R**3 * self.length / (2 * self.clearance**2)

    def sommerfeld(self, speed):
        """``S = mu N L D (R/c)^2 / W`` at ``speed`` (rad/s, or a quantity / string such as "3000 rpm")."""
        omega = _speed(speed)
        R = self.diameter / 2
        return self.viscosity * omega / (2 * math.pi) * self.length * self.diameter * (R / self.clearance) ** 2 / \
            float(np.hypot(*self.load))

    # -- solution ----------------------------------------------------------------
    def equilibrium(self, speed):
        """The film solution (:class:`~rotorkit.fluidfilm.reynolds.FilmSolution`) that carries the load at ``speed``."""
        from scipy.optimize import brentq

        omega = _speed(speed)
        grid = self.grid
        target = -np.array(self.load) / self._force_scale(omega)  # dimensionless film force wanted
        magnitude = float(np.hypot(*target))
        guess = {"free": None}

        def plain(eps):
            s = solve_film(grid, (eps, 0.0), full_film=guess["free"])
            guess["free"] = s.full_film
            return s

        low, high = 1e-6, 0.995
        if np.hypot(*plain(high).force) < magnitude:
            raise ParameterError(f"PlainJournalBearing at {omega!r} rad/s: the load {np.hypot(*self.load)!r} N needs "
                                 f"an eccentricity ratio > {high} (Sommerfeld number {self.sommerfeld(omega):.3g}): "
                                 "too heavy a load or too low a speed for this film")
        if np.hypot(*plain(low).force) > magnitude:
            raise ParameterError(f"PlainJournalBearing at {omega!r} rad/s: the load {np.hypot(*self.load)!r} N is "
                                 f"carried at an eccentricity ratio < {low} (Sommerfeld number "
                                 f"{self.sommerfeld(omega):.3g}): too light a load for a static equilibrium")
        eps = brentq(lambda e: np.hypot(*plain(e).force) - magnitude, low, high, xtol=1e-7)
        s = plain(eps)
        turn = math.atan2(target[1], target[0]) - math.atan2(s.force[1], s.force[0])
        position = eps * np.array([math.cos(turn), math.sin(turn)])
        # the grid is not invariant under the turn (nor are grooves): Newton polishes the turned guess, its
        # active set the (eps, 0) film's turned by the nearest number of nodes
        free = np.roll(s.full_film, int(round(turn / grid.dtheta)), axis=0)
        return self._newton(grid, solve_film(grid, position, full_film=free), target)

    def _newton(self, grid, solution, target, steps=40):
        """Newton on the journal position until the discrete film's force equals ``target`` (to 1e-11)."""
        ambient = self._groove_mask(grid)
        s = solve_film(grid, solution.position, full_film=solution.full_film, ambient=ambient)
        for _ in range(steps):
            residual = s.force - target
            if np.hypot(*residual) < 1e-11 * np.hypot(*target):
                return s
            J = film_derivatives(s)[:, :2]
            step = np.linalg.solve(J, -residual)
            position = np.array(s.position) + step
            while np.hypot(*position) >= 0.995:  # stay inside the bore
                step /= 2
                position = np.array(s.position) + step
            s = solve_film(grid, position, full_film=s.full_film, ambient=ambient)
        raise ParameterError("PlainJournalBearing: the film's equilibrium did not converge in "
                             f"{steps} Newton steps")

    def coefficients(self, speeds):
        """Static equilibrium and the eight coefficients at each speed.

        Parameters
        ----------
        speeds : sequence of float, pint.Quantity or str
            Journal speeds (rad/s, or quantities such as "3000 rpm"), > 0, increasing.

        Returns
        -------
        BearingCoefficients
        """
        omegas = np.array([_speed(w) for w in _as_list(speeds)])
        if omegas.size == 0 or np.any(np.diff(omegas) <= 0):
            raise ParameterError(f"PlainJournalBearing.coefficients: speeds = {speeds!r}: expected one or more "
                                 "increasing speeds > 0")
        n = omegas.size
        S, eps, phi = np.empty(n), np.empty(n), np.empty(n)
        pos, K, C = np.empty((n, 2)), np.empty((n, 2, 2)), np.empty((n, 2, 2))
        load_angle = math.atan2(self.load[1], self.load[0])
        for k, omega in enumerate(omegas):
            s = self.equilibrium(omega)
            J = film_derivatives(s)
            scale = self._force_scale(omega)
            K[k] = -J[:, :2] * scale / self.clearance
            C[k] = -J[:, 2:] * scale / (self.clearance * omega)
            X, Y = s.position
            eps[k] = math.hypot(X, Y)
            phi[k] = (math.atan2(Y, X) - load_angle + math.pi) % (2 * math.pi) - math.pi
            pos[k] = (X * self.clearance, Y * self.clearance)
            S[k] = self.sommerfeld(omega)
        return BearingCoefficients(speeds=omegas, sommerfeld=S, eccentricity_ratio=eps, attitude_angle=phi,
                                   position=pos, stiffness=K, damping=C, load=np.array(self.load),
                                   clearance=self.clearance)

    def to_linear_bearing(self, speeds, station, *, interpolation="pchip", extrapolation="hold", name=None,
                          **options):
        """A :class:`~rotorkit.elements.linear_bearing.LinearBearing` with this film's coefficients at ``speeds``.

        Short for ``self.coefficients(speeds).to_linear_bearing(station, ...)``.

        Examples
        --------
        >>> b = PlainJournalBearing(diameter=0.1, length=0.05, clearance=1e-4, viscosity=0.03, load=5000.0)
        >>> lb = b.to_linear_bearing(["2000 rpm", "4000 rpm"], station=2)
        >>> lb.interpolation, len(lb.speeds)
        ('pchip', 2)
        """
        return self.coefficients(speeds).to_linear_bearing(station, interpolation=interpolation,
                                                          extrapolation=extrapolation, name=name, **options)


def _as_list(speeds):
    if isinstance(speeds, (str, bytes)) or np.ndim(speeds) == 0 and not isinstance(speeds, (list, tuple)):
        return [speeds]
    return list(speeds)


def _speed(speed):
    omega = to_si(speed, "rad/s", "PlainJournalBearing speed")
    if not (math.isfinite(omega) and omega > 0):
        raise ParameterError(f"PlainJournalBearing: speed = {speed!r}: expected a spin speed > 0 (rad/s): a bearing "
                             "at rest carries no load")
    return omega
