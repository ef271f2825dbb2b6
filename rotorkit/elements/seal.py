"""Annular seal (labyrinth, damper or liquid annular seal) as a coefficient element.

A seal acts on the rotor like a linear bearing: the force on the rotor at
``station`` is ``F = -K d - C d' - M_a d''`` with the same 2x2
coefficients, constant or tabulated against the rotor speed and/or the
whirl frequency, with the same interpolation and extrapolation
(:class:`Seal` *is* a :class:`~rotorkit.elements.LinearBearing`: one table
machinery, see its module docstring for the tables, the CSV format and the
whirl frequency at which a frequency table is read). The coefficients come
from the user (a bulk-flow code such as ISOTSEAL, tests, the literature);
rotorkit computes none.

What differs from a bearing:

- the direct stiffness ``kxx``, ``kyy`` may be negative: liquid annular and
  labyrinth seals often have a negative direct stiffness (Childs 1993,
  chapters 3 and 5), which softens the rotor;
- when a seal's direct stiffness is negative somewhere, building the model
  checks that the assembled static stiffness (the symmetric part of ``K``
  at the model's parameters, the rotor speed included) is still positive
  definite and warns with :class:`StaticInstabilityWarning` when it is not:
  the rotor then diverges statically (its lowest natural frequency is
  imaginary). :func:`static_stiffness_margin` returns the lowest
  eigenvalue of that matrix for any model.

The check derives the model's linear matrices (cached per structure) at
construction, only for a model with a negative seal stiffness.

Source: D. W. Childs, *Turbomachinery Rotordynamics* (Wiley 1993), ch. 4-5
(seal coefficients, negative direct stiffness); API 617 (2014), 4.8.6
(seal coefficients in the stability analysis).
"""

import warnings
from dataclasses import dataclass

from .linear_bearing import DIRECT_COEFFICIENTS, LinearBearing

__all__ = ["Seal", "StaticInstabilityWarning", "static_stiffness_margin"]


class StaticInstabilityWarning(RuntimeWarning):
    """The assembled static stiffness of a rotor is not positive definite (a seal's negative stiffness)."""


@dataclass(frozen=True, slots=True, kw_only=True)
class Seal(LinearBearing):
    """An annular seal: 2x2 stiffness, damping and added mass, constant or tabulated; direct stiffness of any sign.

    Parameters are those of :class:`~rotorkit.elements.LinearBearing`
    (``station``, ``kxx``..``cyy``, ``mxx``..``myy``, tilt coefficients,
    ``speeds``, ``frequencies``, ``whirl``, ``interpolation``,
    ``extrapolation``), except that ``kxx``, ``kyy`` (N/m) may be negative.
    Build tables with :meth:`tabulated`, :meth:`frequency_table` or
    :meth:`from_csv`.

    Examples
    --------
    >>> s = Seal(station=2, kxx=-2e6, kyy=-2e6, kxy=5e5, kyx=-5e5, cxx=800.0, cyy=800.0)
    >>> s.label(), s.kxx
    ('seal2', -2000000.0)
    """

    _units = {**LinearBearing._units, "kxx": ("N/m", None), "kyy": ("N/m", None)}
    _direct_checked = tuple(f for f in DIRECT_COEFFICIENTS if f not in ("kxx", "kyy"))
    _direct_rule = ", any sign"

    def _default_label(self):
        other = "" if self.other_station is None else f"_{self.other_station}"
        return f"seal{self.station}{other}"

    def _negative(self):
        for f in ("kxx", "kyy"):
            values = getattr(self, f)
            flat = [values] if not self._tabulated() else (
                [v for row in values for v in row] if self._grid() else list(values))
            if any(v < 0 for v in flat):
                return True
        return False

    def check(self, model):
        LinearBearing.check(self, model)
        negative = [e for e in model.elements if isinstance(e, Seal) and e._negative()]
        if not negative or negative[-1] is not self:  # once per model, by the last such seal
            return
        # the model's remaining checks first (they raise what they would raise anyway), then the matrices
        model._check_stiffness_paths()
        model._check_symbol_names()
        margin = static_stiffness_margin(model)
        if margin is not None and margin < 0:
            labels = ", ".join(repr(e.label()) for e in negative)
            warnings.warn(f"Model {model.name!r}: the static stiffness matrix is not positive definite (lowest "
                          f"scaled eigenvalue {margin:.4g}) with the negative direct stiffness of seal(s) {labels}: "
                          "the rotor is statically unstable (it diverges; its lowest natural frequency is "
                          "imaginary)", StaticInstabilityWarning, stacklevel=4)


def static_stiffness_margin(model, values=None, t=0.0):
    """Lowest eigenvalue of the scaled symmetric static stiffness (dimensionless), or None if not linear.

    The matrix is ``D^-1/2 S D^-1/2`` with ``S = (K + K^T) / 2`` the
    symmetric part of the stiffness ``K`` at ``values`` (default the
    model's parameters, its rotor speeds included) and ``D`` its diagonal's
    magnitude, so that translations (N/m) and tilts (N m/rad) compare. By
    Sylvester's law of inertia its sign is that of ``S``'s lowest
    eigenvalue: negative means statically unstable, 0 a free motion.
    """
    import numpy as np

    from ..linear.linear_matrices import linear_matrices

    matrices = linear_matrices(model, t, values)
    if matrices is None:
        return None
    K = matrices[2].toarray()
    S = (K + K.T) / 2
    d = np.abs(np.diag(S))
    scale = np.sqrt(np.maximum(d, 1e-12 * max(float(d.max()), 1e-300)))
    lowest = float(np.linalg.eigvalsh(S / np.outer(scale, scale))[0])
    return 0.0 if abs(lowest) < 1e-10 else lowest
