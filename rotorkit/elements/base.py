"""The element contract: small frozen dataclasses that contribute energy terms.

An element holds physics only (SI floats after construction). The model
gives it a :class:`Context` (coordinates, time, rotor speeds, its own
parameter symbols) and the element returns :class:`Terms`: kinetic energy,
potential energy, Rayleigh dissipation and generalised forces. Lagrange's
equations are linear in these, so the model derives each element's
contribution on its own and adds them up.

To add an element type: subclass :class:`Element` in a new module of this
package, declare ``_units`` (field -> (SI unit, sign rule)), and implement
``attached_stations``, ``contribute`` and, if it switches in time, ``time_events``.
"""

from dataclasses import dataclass, field
from typing import ClassVar, Mapping

import sympy as sp

from ..errors import ParameterError
from ..units import to_si

__all__ = ["Element", "Terms"]


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
    """

    kinetic: sp.Expr = sp.S.Zero
    potential: sp.Expr = sp.S.Zero
    dissipation: sp.Expr = sp.S.Zero
    loads: Mapping = field(default_factory=dict)
    switches: tuple = ()


@dataclass(frozen=True, slots=True, kw_only=True)
class Element:
    """Base class of every physical element.

    Parameters
    ----------
    name : str, optional
        Label used for the element's parameter names (``"<name>_<field>"``);
        a default is made from the element type and its station.
    """

    name: str | None = None

    #: field -> (SI unit, sign rule); fields listed here become parameters
    _units: ClassVar[Mapping[str, tuple[str, str | None]]] = {}
    #: fields whose value is a time at which the equations jump
    _time_event_fields: ClassVar[tuple[str, ...]] = ()
    #: LaTeX base letter per field, for rendering
    _latex_names: ClassVar[Mapping[str, str]] = {}

    def __post_init__(self):
        if self.name is not None and (not isinstance(self.name, str) or not self.name.isidentifier()):
            raise ParameterError(
                f"{type(self).__name__}.name = {self.name!r} must be a Python identifier "
                "(letters, digits, underscores), e.g. 'disk2'"
            )
        for field_name, (_, sign) in self._units.items():
            value = getattr(self, field_name)
            default = self.__dataclass_fields__[field_name].default
            if value is None and default is not None:
                raise ParameterError(
                    f"{type(self).__name__}.{field_name} = None: expected a number in "
                    f"{self.unit_of(field_name) or 'dimensionless units'} (default {default!r})"
                )
            if value is not None:
                si = to_si(value, self.unit_of(field_name), f"{type(self).__name__}.{field_name}", sign=sign)
                object.__setattr__(self, field_name, si)
        self._validate()

    def unit_of(self, field_name) -> str:
        """SI unit of a parameter field (override where it depends on structure)."""
        return self._units[field_name][0]

    def _validate(self):
        """Element-specific checks beyond unit and sign (override)."""

    # -- contract ---------------------------------------------------------
    def label(self) -> str:
        """The element's name, or a default such as ``disk2``."""
        return self.name or self._default_label()

    def _default_label(self) -> str:
        stations = "_".join(str(s) for s in self.attached_stations())
        return f"{type(self).__name__.lower()}{stations}"

    def attached_stations(self) -> tuple:
        """The stations this element attaches to."""
        return ()

    def parameters(self) -> dict[str, float]:
        """Field -> SI value of every parameter this element holds."""
        return {f: getattr(self, f) for f in self._units if getattr(self, f) is not None}

    def parameter_units(self) -> dict[str, str]:
        """Field -> SI unit string of each parameter."""
        return {f: self.unit_of(f) for f in self._units if getattr(self, f) is not None}

    def contribute(self, ctx) -> Terms:
        """Return the element's :class:`Terms` (override)."""
        raise NotImplementedError

    def time_event_fields(self) -> tuple[str, ...]:
        """Parameters (field names) whose values are times of discontinuity."""
        return self._time_event_fields

    def _repr_latex_(self):
        """Jupyter display: type, label and parameters with symbols and units."""
        from ..display import element_latex

        return element_latex(self)

    def structure(self) -> tuple:
        """What the equations' form depends on, other than parameter values."""
        values = []
        for f in self.__dataclass_fields__:
            if f in self._units or f == "name":
                values.append((f, getattr(self, f) is None))
            else:
                values.append((f, repr(getattr(self, f))))
        return (type(self).__name__, self.label(), tuple(values))
