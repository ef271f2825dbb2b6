"""What an element contributes: its energy terms (:class:`Terms`) and finite-element quadratic forms.

Used when a model's equations are derived (:meth:`~rotorkit.elements.base.Element.contribute`), so this
module loads then, not when elements are built: a process with a warm cache never loads it. Both classes are
also importable from :mod:`rotorkit.elements.base`, as before.
"""

from dataclasses import dataclass, field
from typing import Mapping

__all__ = ["Terms", "QuadraticForm"]


@dataclass(frozen=True, slots=True)
class Terms:
    """What one element adds to the Lagrangian system.

    Attributes
    ----------
    kinetic, potential, dissipation : sympy.Expr
        T(q, q', t), V(q, t) and the Rayleigh function D(q') of the element.
    loads : Mapping[sympy.Symbol, sympy.Expr]
        Generalised forces Q_j on coordinates q_j (non-conservative or
        time-dependent loads: contact, bearing, manoeuvre).
    switches : tuple of sympy.Expr
        Functions g(q, t) whose zero crossings are kinks of the equations
        (contact onset and loss); an integrator may locate them and restart.

    An energy left out is sympy's zero (sympy is imported here, when an
    element contributes, not when it is built: a warm start derives nothing
    and never loads sympy).
    """

    kinetic: object = None
    potential: object = None
    dissipation: object = None
    loads: Mapping = field(default_factory=dict)
    switches: tuple = ()
    quadratic: tuple = ()

    def __post_init__(self):
        import sympy as sp

        for name in ("kinetic", "potential", "dissipation"):
            if getattr(self, name) is None:
                object.__setattr__(self, name, sp.S.Zero)


@dataclass(frozen=True, slots=True)
class QuadraticForm:
    """Energies that are quadratic forms over a few coordinates (finite elements).

    ``T = 1/2 u^T M u + u^T N q``, ``V = 1/2 q^T K q``, ``D = 1/2 u^T C u``
    with ``q`` the coordinates and ``u = q'`` their speeds. Lagrange's
    equations of these are ``M q'' + (N - N^T) q' + C q' + K q`` (``N`` holds
    the gyroscopic terms, e.g. ``Omega I_p thx' thy``; when ``N`` depends on
    time, a changing spin speed, the equations also hold ``N' q``: the
    ``I_p Omega'`` terms), so the derivation adds
    the matrices directly instead of differentiating; :meth:`kinetic` and
    friends give the same energies as expressions.

    Attributes
    ----------
    coordinates, speeds : tuple of sympy.Symbol
        q and q' of the form, length m.
    mass, stiffness, damping, gyroscopic : sympy.Matrix or None
        m x m; None for a zero matrix. ``mass``, ``stiffness`` and
        ``damping`` symmetric.
    """

    coordinates: tuple
    speeds: tuple
    mass: object = None
    stiffness: object = None
    damping: object = None
    gyroscopic: object = None

    def _form(self, A, left, right):
        import sympy as sp

        if A is None:
            return sp.S.Zero
        m = len(left)
        return sp.Add(*[A[i, j] * left[i] * right[j] for i in range(m) for j in range(m) if A[i, j] != 0])

    def kinetic(self):
        return self._form(self.mass, self.speeds, self.speeds) / 2 + self._form(self.gyroscopic, self.speeds,
                                                                                self.coordinates)

    def potential(self):
        return self._form(self.stiffness, self.coordinates, self.coordinates) / 2

    def dissipation(self):
        return self._form(self.damping, self.speeds, self.speeds) / 2
