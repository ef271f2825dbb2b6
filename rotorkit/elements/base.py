"""The element contract: small frozen dataclasses that declare what they need and contribute energy terms.

An element holds physics only (SI floats after construction). The model
gathers; it knows no concrete element type. Each element answers:

- :meth:`Element.attached_stations`: the stations it attaches to;
- :meth:`Element.coordinates`: the generalised coordinates it *creates*, as
  ``(station, axis)`` pairs (a rotor creates ``x``/``y`` at its stations, a
  torsional disk ``alpha``, a beam element the tilts ``thx``/``thy``);
- :meth:`Element.requires`: coordinates it needs but does not create (a
  moment spring needs tilts someone else made);
- :meth:`Element.inertia`: coordinates it gives mass or inertia to;
- :meth:`Element.stiffness_links` and :meth:`Element.grounds`: the
  coordinates it ties together elastically, or to the ground;
- :meth:`Element.check`: its own topology rules, given the whole model;
- :meth:`Element.effects`: the effects it brings (``"rub"``, ``"gravity"``...);
- :meth:`Element.contribute`: its :class:`Terms` (kinetic and potential
  energy, Rayleigh dissipation, generalised forces), given a context
  (coordinates, time, rotor speeds, its own parameter symbols);
- :meth:`Element.rigid_body_mass`: the generalised forces a uniform
  acceleration field puts on its coordinates (used by gravity and manoeuvres).

The model checks generically that every coordinate has inertia (else the
mass matrix is singular) and an elastic path to the ground (else the rotor
drifts), and asks the element that created a failing coordinate to explain
(:meth:`Element.explain`). Lagrange's equations are linear in T, V, D and Q,
so each element's contribution is derived on its own and the results added.

Coordinates and sign convention
-------------------------------
The frame is right-handed with ``z`` along the undeflected shaft axis
(increasing with the axial position of the stations) and ``y`` up. At a
station ``s``:

- ``x<s>``, ``y<s>``: lateral displacements of the shaft centre (m);
- ``alpha<s>``: torsional angle about ``+z`` on top of the rotor's spin
  angle ``Omega t`` (rad);
- ``thx<s>``, ``thy<s>``: small rotations (rad) of the cross-section about
  ``+x`` and ``+y`` (right-hand rule). For a bending line ``x(z), y(z)``:
  ``thy = +dx/dz`` and ``thx = -dy/dz``.

A station has ``x``/``y`` always (from its rotor), ``alpha`` and the tilts
only when an element creates them. Coordinates are ordered by axis
(``x``, ``y``, ``alpha``, ``thx``, ``thy``, then any other axis in order of
first declaration), then by station in model order.

To add an element type: subclass :class:`Element` in a new module, declare
``_units`` (field -> (SI unit, sign rule)), and implement ``contribute`` and
the declarations that apply; nothing else in the package changes.
"""

import dataclasses
import functools
import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING, ClassVar, Mapping

from ..errors import ParameterError
from ..units import to_si

__all__ = ["Element", "Terms", "QuadraticForm", "AXES", "loaded_types"]

if TYPE_CHECKING:  # defined in .terms, loaded on first use (see __getattr__)
    from .terms import QuadraticForm, Terms

#: the standard coordinate axes, in coordinate order
AXES = ("x", "y", "alpha", "thx", "thy")


def __getattr__(name):
    """``Terms`` and ``QuadraticForm`` (:mod:`rotorkit.elements.terms`), imported when first used: deriving needs
    them, building and reading models does not."""
    if name in ("Terms", "QuadraticForm"):
        from . import terms

        return getattr(terms, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def loaded_types(*names):
    """The classes ``"module.Class"`` of :mod:`rotorkit.elements` whose module is imported, as a tuple.

    For ``isinstance`` checks against an optional companion type (a rotor's
    ``Drive``, a bearing's ``Pedestal``, a ``BaseRotation`` in the model)
    without importing its module: no instance of a class exists before its
    module is imported, so ``isinstance(x, loaded_types("drive.Drive"))`` is
    the same as ``isinstance(x, Drive)``, and a model without one never
    loads that module (``isinstance(x, ())`` is False).
    """
    found = []
    for name in names:
        module, _, cls = name.rpartition(".")
        value = getattr(sys.modules.get(f"{__package__}.{module}"), cls, None)
        if value is not None:
            found.append(value)
    return tuple(found)


@functools.cache
def _init_fields(cls):
    """Names of the keyword arguments of a dataclass's ``__init__``, in order (not ClassVars such as
    ``structure_matrices``); once per class."""
    return tuple(f.name for f in dataclasses.fields(cls) if f.init)


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
    #: which matrices of its rotor's structure the element's terms make, of ``("mass", "stiffness")``: a rotor's
    #: Rayleigh damping (:mod:`rotorkit.elements.damping`) is built from them
    structure_matrices: ClassVar[tuple[str, ...]] = ()

    def __new__(cls, *args, **kwargs):
        """Unknown keywords (``LinearBearing(kzz=...)``) are an error naming the fields, before ``__init__``."""
        fields = _init_fields(cls) if hasattr(cls, "__dataclass_fields__") else None
        unknown = [k for k in kwargs if fields is not None and k not in fields]
        if unknown:
            import difflib

            from ..errors import ArgumentTypeError

            known = [f for f in fields if not f.startswith("_")]
            near = difflib.get_close_matches(unknown[0], known, n=3)
            hint = f"; did you mean {', '.join(near)}?" if near else ""
            raise ArgumentTypeError(f"{cls.__name__}: unknown field {unknown[0]!r}{hint} (fields: {', '.join(known)})")
        return object.__new__(cls)  # (no zero-argument super(): slots=True makes a new class)

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

    def owned_stations(self) -> tuple:
        """The stations this element defines (a rotor's stations); each station has one owner."""
        return ()

    def internal_stations(self) -> tuple:
        """``(station, host)`` pairs: stations this element adds on the rotor of ``host`` (beam nodes)."""
        return ()

    def coordinates(self) -> tuple:
        """``(station, axis)`` pairs of the coordinates this element creates."""
        return ()

    def requires(self) -> tuple:
        """``(station, axis)`` pairs this element needs but does not create."""
        return ()

    def inertia(self) -> tuple:
        """``(station, axis)`` pairs this element gives mass or inertia to.

        May name coordinates the model does not have (they are ignored).
        """
        return ()

    def stiffness_links(self) -> tuple:
        """Groups of ``(station, axis)`` pairs this element ties together elastically.

        A pair the model has no coordinate for is a prescribed motion (a
        station without ``alpha`` turns with the drive): linking to it ties
        the others to the ground.
        """
        return ()

    def grounds(self) -> tuple:
        """``(station, axis)`` pairs this element ties elastically to the ground."""
        return ()

    def check(self, model) -> None:
        """Check this element's attachments in ``model``; raise TopologyError (override)."""

    def explain(self, model, problem, coordinates) -> str | None:
        """Why coordinates this element created fail a model check, or None for the generic message.

        ``problem`` is ``"inertia"`` (no element gives them mass) or
        ``"support"`` (no elastic path to the ground); ``coordinates`` lists
        the failing ``(station, axis)`` pairs of this element.
        """
        return None

    def effects(self) -> frozenset:
        """The effects this element brings (``"rub"``, ``"gravity"``, ...)."""
        return frozenset()

    def rigid_body_mass(self, ctx) -> dict:
        """Coordinate symbol -> ``(Q_x, Q_y)``: generalised forces per unit uniform acceleration.

        For an element with mass matrix M and rigid translation vectors
        ``r_x``, ``r_y``: ``M r_x`` and ``M r_y``. A uniform acceleration field
        ``(a_x, a_y)`` (gravity, manoeuvre) loads coordinate ``q`` with
        ``Q_x a_x + Q_y a_y``.
        """
        return {}

    def fixed_time_events(self) -> tuple:
        """Event times that are fixed numbers, not parameters (s)."""
        return ()

    def parameters(self) -> dict[str, float]:
        """Field -> SI value of every parameter this element holds."""
        return {f: getattr(self, f) for f in self._units if getattr(self, f) is not None}

    def parameter_units(self) -> dict[str, str]:
        """Field -> SI unit string of each parameter."""
        return {f: self.unit_of(f) for f in self._units if getattr(self, f) is not None}

    def parameter_sign(self, field_name) -> str | None:
        """Sign rule of a parameter field (``"positive"``, ``"nonnegative"`` or None)."""
        return self._units[field_name][1]

    def replace_parameters(self, **fields):
        """A copy with some parameter fields changed (SI values), fully re-validated."""
        return dataclasses.replace(self, **fields)

    def contribute(self, ctx) -> "Terms":
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
