"""Inertia at a station: rigid disks (with unbalance) and lumped shaft masses."""

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError, TopologyError
from .base import Element
from .rotor import check_station

__all__ = ["Disk", "DiskGeometry", "LumpedMass"]


@dataclass(frozen=True, slots=True, kw_only=True)
class DiskGeometry:
    """What :meth:`Disk.from_geometry` was given: a uniform annular disk of a material.

    Kept on the disk so that a model file writes the geometry as it was
    written (not only the mass and inertias it gives).

    Attributes
    ----------
    width, outer_diameter, inner_diameter : float
        (m), SI after construction.
    material : Material
    diametral : bool
        Whether the disk has a diametral inertia (tilt coordinates).
    """

    width: float = None
    outer_diameter: float = None
    material: object = None
    inner_diameter: float = 0.0
    diametral: bool = True

    _units = {"width": ("m", "positive"), "outer_diameter": ("m", "positive"),
              "inner_diameter": ("m", "nonnegative")}

    def __post_init__(self):
        from ..units import to_si
        from .material import Material

        who = "DiskGeometry"
        if not isinstance(self.material, Material):
            raise ParameterError(f"{who}: material = {self.material!r}: expected a rotorkit Material, "
                                 "e.g. Material.steel()")
        for name, (unit, sign) in self._units.items():
            object.__setattr__(self, name, to_si(getattr(self, name), unit, f"{who}: {name}", sign=sign))
        if not self.inner_diameter < self.outer_diameter:
            raise ParameterError(f"{who}: inner_diameter = {self.inner_diameter:g} m must be smaller than "
                                 f"outer_diameter = {self.outer_diameter:g} m")
        if not isinstance(self.diametral, (bool, np.bool_)):
            raise ParameterError(f"{who}: diametral = {self.diametral!r} must be True or False")
        object.__setattr__(self, "diametral", bool(self.diametral))

    def properties(self):
        """``{mass, polar_inertia, radius, diametral_inertia}`` (SI) of the uniform annular disk."""
        ro, ri, w = self.outer_diameter / 2, self.inner_diameter / 2, self.width
        mass = self.material.density * np.pi * (ro**2 - ri**2) * w
        polar = mass * (ro**2 + ri**2) / 2
        return {"mass": mass, "polar_inertia": polar, "radius": ro,
                "diametral_inertia": polar / 2 + mass * w**2 / 12 if self.diametral else None}


@dataclass(frozen=True, slots=True, kw_only=True)
class Disk(Element):
    """A rigid disk at a station, with mass unbalance and optional torsion.

    The disk centroid sits at ``(x + e cos phi, y + e sin phi)`` with the
    phase ``phi = Omega t + phase (+ alpha)``, where ``Omega`` is the speed of
    the disk's rotor and ``alpha`` the torsional coordinate (``torsion=True``).
    The kinetic energy ``T = 1/2 m |v_G|^2 + 1/2 J phi'^2`` gives, through
    Lagrange's equations, the unbalance forcing and, with torsion, a
    state-dependent mass matrix coupling ``x, y, alpha`` (entries
    ``-m e sin phi``, ``m e cos phi``, ``J + m e^2``).

    Parameters
    ----------
    station : int or str
        Station of the disk.
    mass : float or pint.Quantity
        Mass (kg), > 0.
    polar_inertia : float or pint.Quantity, optional
        Polar moment of inertia about the centroid (kg m^2).
    radius : float or pint.Quantity, optional
        Disk radius (m). Without ``polar_inertia`` the disk is a uniform thin
        disk, ``J = m R^2 / 2``. A rub stator uses it as contact radius.
    eccentricity : float or pint.Quantity
        Distance of the centroid from the shaft axis (m), >= 0.
    phase : float
        Initial phase of the centroid (rad).
    torsion : bool
        Give the disk a torsional coordinate ``alpha<station>``.
    diametral_inertia : float or pint.Quantity, optional
        Moment of inertia about a diameter through the centroid (kg m^2).
        Needs tilt coordinates at the station (a beam element there): adds
        ``1/2 I_d (thx'^2 + thy'^2)`` and the gyroscopic term
        ``I_p phi' thx' thy`` (``phi' = Omega (+ alpha')``) to T; in a
        turning base (:class:`~rotorkit.elements.base_motion.BaseRotation`)
        also the base's gyroscopic and Euler moments
        (:func:`~rotorkit.elements.base_motion.tilt_kinetic`).

    See Also
    --------
    Disk.from_geometry : a disk built from its width, diameters and material.

    Examples
    --------
    >>> Disk(station=2, mass=10.0, radius=0.075, eccentricity=46.35e-6, torsion=True).label()
    'disk2'
    """

    station: int | str = None
    mass: float = None
    polar_inertia: float | None = None
    radius: float | None = None
    eccentricity: float = 0.0
    phase: float = 0.0
    torsion: bool = False
    diametral_inertia: float | None = None
    geometry: DiskGeometry | None = None

    _units = {
        "mass": ("kg", "positive"),
        "polar_inertia": ("kg*m**2", "positive"),
        "diametral_inertia": ("kg*m**2", "positive"),
        "radius": ("m", "positive"),
        "eccentricity": ("m", "nonnegative"),
        "phase": ("rad", None),
    }
    _latex_names = {"mass": "m", "polar_inertia": "J", "radius": "R", "eccentricity": "e", "phase": r"\phi",
                    "diametral_inertia": "I_d"}
    structure_matrices = ("mass",)

    @classmethod
    def from_geometry(cls, *, station, width, outer_diameter, material, inner_diameter=0.0, diametral=True,
                      eccentricity=0.0, phase=0.0, torsion=False, name=None):
        """A uniform annular disk from width w, diameters and a :class:`~rotorkit.elements.material.Material`.

        ``m = rho pi (r_o^2 - r_i^2) w``, ``I_p = m (r_o^2 + r_i^2) / 2``,
        ``I_d = I_p / 2 + m w^2 / 12``; ``radius`` is r_o. With
        ``diametral=False`` the disk has no diametral inertia (a station
        without tilt coordinates).

        Examples
        --------
        >>> from rotorkit.elements.material import Material
        >>> d = Disk.from_geometry(station=3, width=0.07, inner_diameter=0.05, outer_diameter=0.28,
        ...                        material=Material.steel())
        >>> round(d.mass, 2), round(d.polar_inertia, 4), round(d.diametral_inertia, 4)
        (32.59, 0.3296, 0.1781)
        """
        geometry = DiskGeometry(width=width, outer_diameter=outer_diameter, inner_diameter=inner_diameter,
                                material=material, diametral=diametral)  # checked there
        return cls(station=station, geometry=geometry, eccentricity=eccentricity, phase=phase, torsion=torsion,
                   name=name)

    #: the fields a geometry gives
    _FROM_GEOMETRY = ("mass", "polar_inertia", "radius", "diametral_inertia")

    def replace_parameters(self, **fields):
        """A copy with some parameters changed; changing what the geometry gives drops the geometry."""
        import dataclasses

        if self.geometry is not None and any(f in fields for f in self._FROM_GEOMETRY):
            fields["geometry"] = None
        return dataclasses.replace(self, **fields)

    def _validate(self):
        object.__setattr__(self, "station", check_station("Disk", self.station, "station"))
        if self.geometry is not None:
            if not isinstance(self.geometry, DiskGeometry):
                raise ParameterError(f"Disk at station {self.station!r}: geometry = {self.geometry!r}: expected a "
                                     "DiskGeometry (use Disk.from_geometry)")
            for name, value in self.geometry.properties().items():
                given = getattr(self, name)
                if given is None:
                    object.__setattr__(self, name, value)
                elif value is None or not np.isclose(given, value, rtol=1e-12, atol=0.0):
                    raise ParameterError(f"Disk at station {self.station!r}: {name} = {given!r} disagrees with "
                                         f"its geometry ({value!r}); give one or the other")
        if self.mass is None:
            raise ParameterError(f"Disk at station {self.station!r}: mass is required (kg)")
        if self.polar_inertia is None and self.radius is None:
            raise ParameterError(
                f"Disk at station {self.station!r}: give polar_inertia (kg m^2) or radius (m)"
            )
        if not isinstance(self.torsion, (bool, np.bool_)):
            raise ParameterError(f"Disk at station {self.station!r}: torsion={self.torsion!r} must be True or False")
        object.__setattr__(self, "torsion", bool(self.torsion))

    def attached_stations(self):
        return (self.station,)

    def _default_label(self):
        return f"disk{self.station}"

    def coordinates(self):
        return ((self.station, "alpha"),) if self.torsion else ()

    def inertia(self):
        out = ((self.station, "x"), (self.station, "y")) + (((self.station, "alpha"),) if self.torsion else ())
        return out + self.requires()

    def requires(self):
        return ((self.station, "thx"), (self.station, "thy")) if self.diametral_inertia is not None else ()

    def effects(self):
        return frozenset({"unbalance"} if self.eccentricity is not None else ()) | (
            frozenset({"torsion"}) if self.torsion else frozenset()) | (
            frozenset({"gyroscopic"}) if self.diametral_inertia is not None else frozenset())

    def check(self, model):
        others = [e for e in model.elements_at(self.station) if isinstance(e, Disk)]
        if len(others) > 1:
            raise TopologyError(f"Model: station {self.station!r} has more than one Disk; merge them into one")

    def explain(self, model, problem, coordinates):
        if problem == "support" and (self.station, "alpha") in coordinates:
            return (f"Disk at station {self.station!r} has torsion=True but no torsional stiffness path to the drive "
                    "(a station without torsional coordinate); add a ShaftSegment with torsional_stiffness "
                    "(or shear_modulus, polar_area_moment, length) from it towards the drive")
        return None

    def rigid_body_mass(self, ctx):
        import sympy as sp

        x, y = ctx.coord(self.station, "x")[0], ctx.coord(self.station, "y")[0]
        m = ctx.p["mass"]
        return {x: (m, sp.S.Zero), y: (sp.S.Zero, m)}

    def polar_inertia_expr(self, p):
        """J as an expression of the parameter symbols ``p``."""
        if self.polar_inertia is not None:
            return p["polar_inertia"]
        return p["mass"] * p["radius"] ** 2 / 2

    def contribute(self, ctx):
        import sympy as sp

        from .terms import Terms

        p = ctx.p
        (_, xd), (_, yd) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        spin = ctx.speed(self.station)
        m, e = p["mass"], p["eccentricity"]
        phi = ctx.spin_angle(self.station) + p["phase"]  # Omega t at constant speed
        phi_dot = spin
        if self.torsion:
            alpha, alpha_dot = ctx.coord(self.station, "alpha")
            phi, phi_dot = phi + alpha, spin + alpha_dot
        vx = xd - e * phi_dot * sp.sin(phi)
        vy = yd + e * phi_dot * sp.cos(phi)
        kinetic = m * (vx**2 + vy**2) / 2
        if self.torsion:
            kinetic += self.polar_inertia_expr(p) * phi_dot**2 / 2
        if self.diametral_inertia is not None:
            (a, ad), (b, bd) = ctx.coord(self.station, "thx"), ctx.coord(self.station, "thy")
            kinetic += p["diametral_inertia"] * (ad**2 + bd**2) / 2 + self.polar_inertia_expr(p) * phi_dot * ad * b
            from .base_motion import base_frame, tilt_kinetic

            frame = base_frame(ctx)
            if frame is not None:  # a turning base: its gyroscopic and Euler moments on the tilts
                kinetic += tilt_kinetic(p["diametral_inertia"], self.polar_inertia_expr(p), phi_dot, (a, b), (ad, bd),
                                        frame.W)
        return Terms(kinetic=kinetic)


@dataclass(frozen=True, slots=True, kw_only=True)
class LumpedMass(Element):
    """A point mass at a station (a lumped piece of shaft), bending only.

    Parameters
    ----------
    station : int or str
    mass : float or pint.Quantity
        Mass (kg), > 0.

    Examples
    --------
    >>> LumpedMass(station=1, mass=2.0).label()
    'mass1'
    """

    station: int | str = None
    mass: float = None

    _units = {"mass": ("kg", "positive")}
    _latex_names = {"mass": "m"}
    structure_matrices = ("mass",)

    def _validate(self):
        object.__setattr__(self, "station", check_station("LumpedMass", self.station, "station"))
        if self.mass is None:
            raise ParameterError(f"LumpedMass at station {self.station!r}: mass is required (kg)")

    def attached_stations(self):
        return (self.station,)

    def _default_label(self):
        return f"mass{self.station}"

    def inertia(self):
        return ((self.station, "x"), (self.station, "y"))

    def rigid_body_mass(self, ctx):
        import sympy as sp

        x, y = ctx.coord(self.station, "x")[0], ctx.coord(self.station, "y")[0]
        m = ctx.p["mass"]
        return {x: (m, sp.S.Zero), y: (sp.S.Zero, m)}

    def contribute(self, ctx):
        from .terms import Terms

        (_, xd), (_, yd) = ctx.coord(self.station, "x"), ctx.coord(self.station, "y")
        return Terms(kinetic=ctx.p["mass"] * (xd**2 + yd**2) / 2)
