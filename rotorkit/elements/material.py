"""Isotropic linear-elastic materials for shafts and disks."""

import math
import numbers
from dataclasses import dataclass

from ..errors import ParameterError
from ..units import to_si

__all__ = ["Material"]


@dataclass(frozen=True, slots=True, kw_only=True)
class Material:
    """An isotropic linear-elastic material.

    Give ``density``, ``youngs_modulus`` and one of ``shear_modulus`` or
    ``poisson_ratio``; the other follows from ``G = E / (2 (1 + nu))``.
    Values are SI floats or pint quantities.

    Named constructors give typical room-temperature values (check your
    supplier's data sheet for design work):

    ========================  =======  =======  ======  =====================================
    constructor               rho      E        nu      source
                              kg/m^3   GPa
    ========================  =======  =======  ======  =====================================
    ``steel()``               7810     211      0.2993  Friswell et al., *Dynamics of Rotating
                                                        Machines* (2010), examples (G = 81.2 GPa)
    ``steel_4340()``          7850     205      0.29    AISI 4340, ASM Handbook vol. 1 / MatWeb
    ``stainless_17_4ph()``    7800     196      0.272   17-4PH H1025, AK Steel product data
    ``titanium_ti6al4v()``    4430     113.8    0.342   Ti-6Al-4V annealed, ASM Aerospace
                                                        Specification Metals data sheet
    ``inconel_718()``         8190     200      0.294   Inconel 718, Special Metals
                                                        publication SMC-045
    ========================  =======  =======  ======  =====================================

    Parameters
    ----------
    density : float or pint.Quantity
        rho (kg/m^3), > 0.
    youngs_modulus : float or pint.Quantity
        E (Pa), > 0.
    shear_modulus : float or pint.Quantity, optional
        G (Pa), > 0.
    poisson_ratio : float, optional
        nu, in (-1, 0.5).
    name : str, optional

    Examples
    --------
    >>> steel = Material.steel()
    >>> round(steel.shear_modulus / 1e9, 1), round(steel.poisson_ratio, 4)
    (81.2, 0.2993)
    >>> round(Material(density=7800, youngs_modulus=2e11, poisson_ratio=0.3).shear_modulus / 1e9, 2)
    76.92
    """

    density: float = None
    youngs_modulus: float = None
    shear_modulus: float | None = None
    poisson_ratio: float | None = None
    name: str | None = None

    #: SI units of the quantities (model files write them with their unit)
    _units = {"density": ("kg/m**3", "positive"), "youngs_modulus": ("Pa", "positive"),
              "shear_modulus": ("Pa", "positive"), "poisson_ratio": ("", None)}

    def __post_init__(self):
        who = f"Material {self.name!r}" if self.name else "Material"
        for field_name, unit in (("density", "kg/m**3"), ("youngs_modulus", "Pa")):
            value = getattr(self, field_name)
            if value is None:
                raise ParameterError(f"{who}: {field_name} is required ({unit})")
            object.__setattr__(self, field_name, to_si(value, unit, f"{who}.{field_name}", sign="positive"))
        E, nu = self.youngs_modulus, self.poisson_ratio
        if nu is not None:
            if isinstance(nu, bool) or not isinstance(nu, numbers.Real) or not -1.0 < nu < 0.5:
                raise ParameterError(
                    f"{who}: poisson_ratio = {nu!r}: expected a number in (-1, 0.5) for an isotropic material"
                )
            nu = float(nu)
        if self.shear_modulus is None:
            if nu is None:
                raise ParameterError(f"{who}: give shear_modulus (Pa) or poisson_ratio")
            G = E / (2.0 * (1.0 + nu))
        else:
            G = to_si(self.shear_modulus, "Pa", f"{who}.shear_modulus", sign="positive")
            implied = E / (2.0 * G) - 1.0
            if nu is not None and not math.isclose(implied, nu, rel_tol=1e-6, abs_tol=1e-9):
                raise ParameterError(
                    f"{who}: shear_modulus = {G:g} Pa and poisson_ratio = {nu!r} disagree "
                    f"(G = E / (2 (1 + nu)) = {E / (2.0 * (1.0 + nu)):g} Pa); give one of them"
                )
            if not -1.0 < implied < 0.5:
                raise ParameterError(
                    f"{who}: shear_modulus = {G:g} Pa with youngs_modulus = {E:g} Pa gives a Poisson ratio "
                    f"{implied:.4g} outside (-1, 0.5); expected G > E/3 = {E / 3:g} Pa"
                )
            nu = implied if nu is None else nu
        object.__setattr__(self, "shear_modulus", G)
        object.__setattr__(self, "poisson_ratio", nu)

    # -- named constructors ----------------------------------------------------
    @classmethod
    def steel(cls):
        """Steel as in Friswell et al. (2010): rho 7810 kg/m^3, E 211 GPa, G 81.2 GPa."""
        return cls(name="steel", density=7810.0, youngs_modulus=211e9, shear_modulus=81.2e9)

    @classmethod
    def steel_4340(cls):
        """AISI 4340 alloy steel: rho 7850 kg/m^3, E 205 GPa, nu 0.29."""
        return cls(name="steel_4340", density=7850.0, youngs_modulus=205e9, poisson_ratio=0.29)

    @classmethod
    def stainless_17_4ph(cls):
        """17-4PH stainless steel (H1025): rho 7800 kg/m^3, E 196 GPa, nu 0.272."""
        return cls(name="stainless_17_4ph", density=7800.0, youngs_modulus=196e9, poisson_ratio=0.272)

    @classmethod
    def titanium_ti6al4v(cls):
        """Ti-6Al-4V (annealed): rho 4430 kg/m^3, E 113.8 GPa, nu 0.342."""
        return cls(name="titanium_ti6al4v", density=4430.0, youngs_modulus=113.8e9, poisson_ratio=0.342)

    @classmethod
    def inconel_718(cls):
        """Inconel 718 (nickel alloy): rho 8190 kg/m^3, E 200 GPa, nu 0.294."""
        return cls(name="inconel_718", density=8190.0, youngs_modulus=200e9, poisson_ratio=0.294)
