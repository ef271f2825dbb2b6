"""The model-file format and its writer: what :meth:`rotorkit.Model.save` needs, below :mod:`rotorkit.model`.

The format is described in :mod:`rotorkit.modelfile`, which reads model files (it builds a
:class:`~rotorkit.Model`, so it sits above :mod:`rotorkit.model`) and gives the names defined here as well.
"""

import dataclasses
import math
import numbers
import re
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from .errors import ParameterError

__all__ = ["FORMAT", "VERSION", "RUN_KEYS", "ModelFileError", "register_type", "element_types", "dumps_model",
           "save_model"]

FORMAT = "rotorkit-model"
VERSION = 1
#: keys of the optional [run] table (what ``rotorkit run`` simulates and draws)
RUN_KEYS = ("t_end", "orbit_station", "clearance_parameter", "bending", "torsion")

_REGISTERED = {}


class ModelFileError(ParameterError):
    """A model file is malformed: the message names file, element, field, value and what is expected."""


# -- registry ----------------------------------------------------------------
def register_type(cls):
    """Allow a dataclass (e.g. your own :class:`~rotorkit.elements.Element` subclass) in model files."""
    if not (isinstance(cls, type) and dataclasses.is_dataclass(cls)):
        raise ParameterError(f"register_type({cls!r}): expected a dataclass type")
    _REGISTERED[cls.__name__] = cls
    return cls


def _subclasses(cls):
    for sub in cls.__subclasses__():
        yield sub
        yield from _subclasses(sub)


class _Types(Mapping):
    """Type name -> class; an element module is imported when its name is first looked up."""

    def __init__(self):
        from . import elements
        from .elements.base import Element

        self._elements = elements
        self._lazy = {n: m for n, m in elements.TYPE_MODULES.items() if n not in ("Element", "Terms")}
        self._known = {}
        for cls in _subclasses(Element):  # Element subclasses of rotorkit modules already imported
            if cls.__module__.startswith("rotorkit.") and dataclasses.is_dataclass(cls) and cls.__name__ not in self._lazy:
                self._known.setdefault(cls.__name__, cls)
        self._known.update(_REGISTERED)

    def __getitem__(self, name):
        if name in self._known:
            return self._known[name]
        if name in self._lazy:
            return getattr(self._elements, name)
        raise KeyError(name)

    def __iter__(self):
        return iter(dict.fromkeys([*self._lazy, *self._known]))

    def __len__(self):
        return len(set(self._lazy) | set(self._known))


def element_types():
    """Type name -> class of everything a model file may hold.

    These are the dataclasses exported by :mod:`rotorkit.elements` (elements,
    and the values they hold such as materials and tables), every
    :class:`~rotorkit.elements.Element` subclass defined in rotorkit, and
    the types given to :func:`register_type`. A read-only mapping: the
    module of a type is imported when the type is looked up, so reading a
    file loads only the element modules it uses.
    """
    return _Types()


# -- writing -----------------------------------------------------------------
_ESCAPES = {'"': '\\"', "\\": "\\\\", "\b": "\\b", "\t": "\\t", "\n": "\\n", "\f": "\\f", "\r": "\\r"}


def _toml_string(text):
    out = []
    for ch in text:
        if ch in _ESCAPES:
            out.append(_ESCAPES[ch])
        elif ord(ch) < 0x20 or ord(ch) == 0x7F or 0xD800 <= ord(ch) <= 0xDFFF:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _key(name):
    return name if re.fullmatch(r"[A-Za-z0-9_-]+", name) else _toml_string(name)


def _float(value):
    if math.isnan(value):
        return "nan"
    if math.isinf(value):
        return "inf" if value > 0 else "-inf"
    text = repr(float(value))
    return text if any(c in text for c in ".en") else text + ".0"


def _encode(value, where):
    """A Python value as a TOML value (inline)."""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        return _float(float(value))
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (tuple, list, range)):
        return "[" + ", ".join(_encode(v, f"{where}[{i}]") for i, v in enumerate(value)) + "]"
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return "{ " + ", ".join(f"{_key(k)} = {v}" for k, v in _object_items(value, where)) + " }"
    if isinstance(value, dict) and all(isinstance(k, str) for k in value):
        return "{ " + ", ".join(f"{_key(k)} = {_encode(v, f'{where}.{k}')}" for k, v in value.items()) + " }"
    if callable(value):
        raise ModelFileError(f"{where} is a Python function ({value!r}); a model file holds data only: "
                             "use a tabulated element instead")
    raise ModelFileError(f"{where} = {value!r}: a {type(value).__name__} cannot be written to a model file")


def _quantity(value, unit, where):
    """A field with a unit: ``"<SI value> <unit>"`` (a plain number if dimensionless), arrays item by item."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_quantity(v, unit, f"{where}[{i}]") for i, v in enumerate(value)) + "]"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ModelFileError(f"{where} = {value!r}: expected a number in {unit or 'dimensionless units'}")
    text = _float(float(value))
    return _toml_string(f"{text} {unit}") if unit else text


def _same(a, b):
    try:
        return bool(a == b) if not isinstance(a, np.ndarray) else bool(np.array_equal(a, b))
    except Exception:  # an ambiguous comparison counts as different
        return False


def _derived_fields(obj):
    """Fields the constructor computes from the others: left out of the file, so it holds what was written.

    A field whose value is not its default is left out when building the
    object without it gives the same object (a beam's density from its
    material, a material's Poisson ratio from E and G). Fields are tried
    from the last to the first, so of two fields that give each other the
    earlier one (as a constructor lists its inputs first) is kept.
    """
    cls = type(obj)
    fields = [f for f in dataclasses.fields(cls) if f.init]
    kwargs = {f.name: getattr(obj, f.name) for f in fields if getattr(obj, f.name) is not None}
    derived = set()
    for f in reversed(fields):
        if f.name not in kwargs or f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            continue
        if _same(kwargs[f.name], f.default if f.default is not dataclasses.MISSING else f.default_factory()):
            continue  # a default is written as before
        trial = {k: v for k, v in kwargs.items() if k != f.name}
        try:
            rebuilt = cls(**trial)
        except Exception:  # the field is needed
            continue
        if all(_same(getattr(rebuilt, g.name), getattr(obj, g.name)) for g in fields):
            derived.add(f.name)
            kwargs = trial
    return derived


def _object_items(obj, where):
    """(key, TOML text) of a registered dataclass: ``type`` first, then its fields (None left out)."""
    cls = type(obj)
    if element_types().get(cls.__name__) is not cls:
        raise ModelFileError(f"{where}: {cls.__module__}.{cls.__name__} is not a rotorkit element type; "
                             "register it with rotorkit.modelfile.register_type to write it to a file")
    items = [("type", _toml_string(cls.__name__))]
    units = getattr(cls, "_units", {})
    derived = _derived_fields(obj)
    for f in dataclasses.fields(cls):
        if not f.init:
            continue
        value = getattr(obj, f.name)
        if value is None or f.name in derived:
            continue
        if f.name in units and not dataclasses.is_dataclass(value):  # (a SpeedProfile in Rotor.speed)
            unit = obj.unit_of(f.name) if hasattr(obj, "unit_of") else units[f.name][0]
            items.append((f.name, _quantity(value, unit, f"{where}.{f.name}")))
        else:
            items.append((f.name, _encode(value, f"{where}.{f.name}")))
    return items


def dumps_model(model, *, run=None, description=None):
    """The model file text of ``model`` (see the module docstring for the format).

    Parameters
    ----------
    model : rotorkit.Model
    run : dict, optional
        The ``[run]`` table (keys :data:`RUN_KEYS`): what ``rotorkit run`` draws.
    description : str, optional
        One line written as the file's ``description``.
    """
    lines = ["# rotorkit model file: values with units are \"<number> <unit>\" strings in any unit of the",
             "# right dimension (SI as written here); see docs/modelfiles.md",
             f"format = {_toml_string(FORMAT)}", f"version = {VERSION}", f"name = {_toml_string(model.name)}"]
    if description:
        lines.append(f"description = {_toml_string(description)}")
    for element in model.elements:
        where = f"{type(element).__name__} {element.label()!r}"
        lines += ["", "[[element]]"] + [f"{k} = {v}" for k, v in _object_items(element, where)]
    if run:
        unknown = set(run) - set(RUN_KEYS)
        if unknown:
            raise ModelFileError(f"run table: unknown keys {sorted(unknown)}; expected some of {RUN_KEYS}")
        lines += ["", "[run]"] + [f"{k} = {_encode(v, f'run.{k}')}" for k, v in run.items() if v is not None]
    return "\n".join(lines) + "\n"


def save_model(model, path, *, run=None, description=None):
    """Write ``model`` to ``path`` as a TOML model file (atomically); returns the path."""
    from .files import atomic_write_text

    path = Path(path)
    atomic_write_text(path, dumps_model(model, run=run, description=description))
    return path
