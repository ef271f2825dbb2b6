"""Shaft segment: bending and torsional elasticity between two stations of a rotor."""

from dataclasses import dataclass

from ..errors import ParameterError, TopologyError
from .base import Element
from .rotor import check_station

__all__ = ["ShaftSegment", "END_CONDITIONS"]

#: bending stiffness factor c in k = c E I / l^3, by end condition
END_CONDITIONS = {
    "clamped-free": 3,  # cantilever, tip load
    "clamped-guided": 12,  # both ends clamped against rotation, one end sliding
}


@dataclass(frozen=True, slots=True, kw_only=True)
class ShaftSegment(Element):
    """Massless shaft between two stations of one rotor.

    Bending: a lateral spring ``k`` between the stations in x and y, given
    directly (``bending_stiffness``) or as ``c E I / l^3`` from
    ``youngs_modulus``, ``area_moment``, ``length`` and ``end_condition``
    (``"clamped-free"``: c = 3; ``"clamped-guided"``: c = 12).

    Torsion: a spring ``k_t`` between the torsion angles of the two stations,
    given directly or as ``G I_p / l``. A station without a torsional
    coordinate turns exactly at the rotor speed (alpha = 0): a segment to such
    a station ties the disk to the constant-speed drive.

    Mass belongs to stations (:class:`~rotorkit.LumpedMass`), not segments.

    Parameters
    ----------
    start, end : int or str
        The two stations.
    length : float or pint.Quantity, optional
        Segment length (m); needed for stiffness from material data.
    bending_stiffness : float or pint.Quantity, optional
        Lateral stiffness (N/m).
    youngs_modulus : float or pint.Quantity, optional
        E (Pa).
    area_moment : float or pint.Quantity, optional
        Second moment of area I (m^4).
    end_condition : {"clamped-free", "clamped-guided"}, optional
    bending_damping : float or pint.Quantity
        Lateral damping (N s/m).
    torsional_stiffness : float or pint.Quantity, optional
        k_t (N m/rad).
    shear_modulus : float or pint.Quantity, optional
        G (Pa).
    polar_area_moment : float or pint.Quantity, optional
        Polar second moment of area I_p (m^4).
    torsional_damping : float or pint.Quantity
        Torsional damping (N m s/rad).

    Examples
    --------
    >>> s = ShaftSegment(start=1, end=2, length=0.33, youngs_modulus=2e11,
    ...                  area_moment=1.178e-7, end_condition="clamped-free")
    >>> round(s.bending_stiffness_value())
    1966775
    """

    start: int | str = None
    end: int | str = None
    length: float | None = None
    bending_stiffness: float | None = None
    youngs_modulus: float | None = None
    area_moment: float | None = None
    end_condition: str | None = None
    bending_damping: float | None = None
    torsional_stiffness: float | None = None
    shear_modulus: float | None = None
    polar_area_moment: float | None = None
    torsional_damping: float | None = None

    _units = {
        "length": ("m", "positive"),
        "bending_stiffness": ("N/m", "positive"),
        "youngs_modulus": ("Pa", "positive"),
        "area_moment": ("m**4", "positive"),
        "bending_damping": ("N*s/m", "nonnegative"),
        "torsional_stiffness": ("N*m/rad", "positive"),
        "shear_modulus": ("Pa", "positive"),
        "polar_area_moment": ("m**4", "positive"),
        "torsional_damping": ("N*m*s/rad", "nonnegative"),
    }
    _latex_names = {
        "length": "l",
        "bending_stiffness": "k",
        "youngs_modulus": "E",
        "area_moment": "I",
        "bending_damping": "c",
        "torsional_stiffness": "k_t",
        "shear_modulus": "G",
        "polar_area_moment": "I_p",
        "torsional_damping": "c_t",
    }
    structure_matrices = ("stiffness",)

    def _validate(self):
        who = f"ShaftSegment {self.start!r}-{self.end!r}"
        object.__setattr__(self, "start", check_station(who, self.start, "start"))
        object.__setattr__(self, "end", check_station(who, self.end, "end"))
        if self.start == self.end:
            raise ParameterError(f"{who}: start and end are the same station; give two stations")
        material = (self.youngs_modulus, self.area_moment)
        if self.bending_stiffness is not None and any(v is not None for v in material):
            raise ParameterError(f"{who}: give bending_stiffness or youngs_modulus and area_moment, not both")
        if any(v is not None for v in material):
            if None in material or self.length is None or self.end_condition is None:
                raise ParameterError(
                    f"{who}: bending stiffness from material needs youngs_modulus, area_moment, "
                    f"length and end_condition (one of {sorted(END_CONDITIONS)})"
                )
        if self.end_condition is not None and (not isinstance(self.end_condition, str)
                                               or self.end_condition not in END_CONDITIONS):
            raise ParameterError(
                f"{who}: end_condition={self.end_condition!r} is unknown; expected one of {sorted(END_CONDITIONS)}"
            )
        if self.bending_damping is not None and not self.has_bending():
            raise ParameterError(f"{who}: bending_damping given without a bending stiffness")
        torsion_material = (self.shear_modulus, self.polar_area_moment)
        if self.torsional_stiffness is not None and any(v is not None for v in torsion_material):
            raise ParameterError(f"{who}: give torsional_stiffness or shear_modulus and polar_area_moment, not both")
        if any(v is not None for v in torsion_material) and (None in torsion_material or self.length is None):
            raise ParameterError(
                f"{who}: torsional stiffness from material needs shear_modulus, polar_area_moment and length"
            )
        if self.torsional_damping is not None and not self.has_torsion():
            raise ParameterError(f"{who}: torsional_damping given without a torsional stiffness")
        if not self.has_bending() and not self.has_torsion():
            raise ParameterError(
                f"{who}: no stiffness given; give bending_stiffness (or E, I, length, end_condition) "
                "and/or torsional_stiffness (or G, I_p, length)"
            )

    def attached_stations(self):
        return (self.start, self.end)

    def _default_label(self):
        return f"shaft{self.start}_{self.end}"

    def stiffness_links(self):
        links = ()
        if self.has_bending():
            links += (((self.start, "x"), (self.end, "x")), ((self.start, "y"), (self.end, "y")))
        if self.has_torsion():  # a station without alpha turns with the drive
            links += (((self.start, "alpha"), (self.end, "alpha")),)
        return links

    def check(self, model):
        ra, rb = model.rotor_of(self.start), model.rotor_of(self.end)
        if ra is not rb:
            raise TopologyError(
                f"ShaftSegment {self.label()!r}: stations {self.start!r} (rotor {ra.name!r}) and {self.end!r} "
                f"(rotor {rb.name!r}) are on different rotors; couple rotors with a BallBearing"
            )
        if self.has_torsion() and not (model.has_coordinate(self.start, "alpha")
                                       or model.has_coordinate(self.end, "alpha")):
            raise TopologyError(
                f"ShaftSegment {self.label()!r}: torsional stiffness between stations with no torsional "
                "coordinate has no effect; give a Disk at one end torsion=True, or drop the torsion"
            )

    def has_bending(self):
        return self.bending_stiffness is not None or self.youngs_modulus is not None

    def has_torsion(self):
        return self.torsional_stiffness is not None or self.shear_modulus is not None

    def bending_stiffness_value(self):
        """Lateral stiffness in N/m from the current values."""
        if self.bending_stiffness is not None:
            return self.bending_stiffness
        return END_CONDITIONS[self.end_condition] * self.youngs_modulus * self.area_moment / self.length**3

    def torsional_stiffness_value(self):
        """Torsional stiffness in N m/rad from the current values."""
        if self.torsional_stiffness is not None:
            return self.torsional_stiffness
        return self.shear_modulus * self.polar_area_moment / self.length

    def contribute(self, ctx):
        from .terms import Terms

        p = ctx.p
        potential = dissipation = 0
        if self.has_bending():
            if self.bending_stiffness is not None:
                k = p["bending_stiffness"]
            else:
                k = END_CONDITIONS[self.end_condition] * p["youngs_modulus"] * p["area_moment"] / p["length"] ** 3
            c = p.get("bending_damping", 0)
            for axis in ("x", "y"):
                (qa, ua), (qb, ub) = ctx.coord(self.start, axis), ctx.coord(self.end, axis)
                potential += k * (qa - qb) ** 2 / 2
                dissipation += c * (ua - ub) ** 2 / 2
        if self.has_torsion():
            if self.torsional_stiffness is not None:
                kt = p["torsional_stiffness"]
            else:
                kt = p["shear_modulus"] * p["polar_area_moment"] / p["length"]
            ct = p.get("torsional_damping", 0)
            (qa, ua), (qb, ub) = ctx.coord(self.start, "alpha", drive=True), ctx.coord(self.end, "alpha", drive=True)
            potential += kt * (qa - qb) ** 2 / 2
            dissipation += ct * (ua - ub) ** 2 / 2
        return Terms(potential=potential, dissipation=dissipation)
