"""Pedestal (support mass): a bearing housing with its own mass, stiffness and damping to the ground.

A :class:`Pedestal` is held by the bearing that sits on it
(``LinearBearing(..., pedestal=Pedestal(...))``): the bearing force then
acts between the journal and the pedestal, and the pedestal is tied to the
ground by its own springs and dampers. It brings two coordinates at the
bearing's station, ``px<station>`` and ``py<station>`` (the pedestal's
lateral displacements, m, same axes as ``x``, ``y``); a bearing without a
pedestal brings none. The pedestal translates only (it does not tilt).

Its kinetic, potential and dissipation energies are ::

    T = m (px'^2 + py'^2) / 2
    V = (kxx px^2 + kyy py^2) / 2
    D = (cxx px'^2 + cyy py'^2) / 2

Its values are parameters of the bearing, ``<bearing>_pedestal_mass``,
``<bearing>_pedestal_kxx``, ... (change them without a new derivation).
"""

import dataclasses
from dataclasses import dataclass

from ..errors import ParameterError
from ..units import to_si

__all__ = ["Pedestal", "PEDESTAL_AXES"]

#: the axes of a pedestal's coordinates (``px<station>``, ``py<station>``)
PEDESTAL_AXES = ("px", "py")


@dataclass(frozen=True, slots=True, kw_only=True)
class Pedestal:
    """A bearing's support mass on its own springs and dampers to the ground.

    Parameters
    ----------
    mass : float or pint.Quantity
        Pedestal (housing) mass m (kg), > 0; the same in x and y.
    kxx, kyy : float or pint.Quantity
        Stiffness to the ground in x and y (N/m), > 0 (anisotropic when they differ).
    cxx, cyy : float or pint.Quantity, optional
        Damping to the ground (N s/m), >= 0; None adds no term.

    Examples
    --------
    >>> Pedestal(mass=50.0, kxx=5e7, kyy=2e7, cxx=1e3).parameters()
    {'mass': 50.0, 'kxx': 50000000.0, 'kyy': 20000000.0, 'cxx': 1000.0}
    """

    mass: float = None
    kxx: float = None
    kyy: float = None
    cxx: float | None = None
    cyy: float | None = None

    _units = {"mass": ("kg", "positive"), "kxx": ("N/m", "positive"), "kyy": ("N/m", "positive"),
              "cxx": ("N*s/m", "nonnegative"), "cyy": ("N*s/m", "nonnegative")}

    def __post_init__(self):
        for f, (unit, sign) in self._units.items():
            value = getattr(self, f)
            if value is None:
                if f in ("mass", "kxx", "kyy"):
                    raise ParameterError(f"Pedestal: {f} is required ({unit}, {sign})")
                continue
            object.__setattr__(self, f, to_si(value, unit, f"Pedestal.{f}", sign=sign))

    def unit_of(self, field_name):
        """SI unit of a field."""
        return self._units[field_name][0]

    def parameters(self):
        """Field -> SI value of the fields given."""
        return {f: getattr(self, f) for f in self._units if getattr(self, f) is not None}

    def replace(self, **fields):
        """A copy with some fields changed, re-validated."""
        return dataclasses.replace(self, **fields)

    def structure(self):
        """Which fields are given (the form of the equations)."""
        return tuple(f for f in self._units if getattr(self, f) is not None)

    def terms(self, p, px, py):
        """(T, V, D) with parameter symbols ``p`` (field -> symbol) and coordinates ``px``, ``py`` = (q, q')."""
        import sympy as sp

        (qx, ux), (qy, uy) = px, py
        kinetic = p["mass"] * (ux**2 + uy**2) / 2
        potential = (p["kxx"] * qx**2 + p["kyy"] * qy**2) / 2
        dissipation = sp.S.Zero
        if self.cxx is not None:
            dissipation += p["cxx"] * ux**2 / 2
        if self.cyy is not None:
            dissipation += p["cyy"] * uy**2 / 2
        return kinetic, potential, dissipation
