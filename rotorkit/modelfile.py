"""Model files: a whole model as TOML, with units written out.

A model file is data only: it is read with :mod:`tomllib`, every element
type is looked up in a registry of rotorkit's own element classes, and every
string that stands for a quantity goes through the bounded quantity grammar
of :func:`rotorkit.units.parse_quantity` (no ``eval``, no ``sympify``, no
pint string evaluation). The format, version 1::

    format = "rotorkit-model"
    version = 1
    name = "jeffcott"

    [[element]]
    type = "Rotor"
    name = "R"
    stations = [1]
    speed = "3000 rpm"

    [[element]]
    type = "Disk"
    station = 1
    mass = "2 kg"
    radius = "10 cm"
    eccentricity = "10 um"

    [run]                      # optional: what ``rotorkit run`` draws
    t_end = 2.0
    orbit_station = 1

Rules, the same for every element type (no per-type code):

- one ``[[element]]`` table per element; ``type`` is the class name
  (``Rotor``, ``Disk``, ``ShaftSegment``, ...), the other keys are the
  class's dataclass fields; a field left out takes its default;
- a field with a unit (listed in the class's ``_units``) is a string
  ``"<number> <unit>"`` in any unit of the right dimension (``"12000 rpm"``,
  ``"0.25 m"``, ``"2e6 N/m"``) or a plain number in SI units; dimensionless
  fields are plain numbers;
- other fields are TOML values: numbers, strings, booleans, arrays (tuples,
  tables of numbers as arrays of arrays);
- a nested object (a material, a tabulated profile: any registered
  dataclass) is an inline table with its own ``type`` key and fields,
  following the same rules; a table without ``type`` is a plain mapping;
- ``None`` is written by leaving the key out.

:func:`save_model` writes SI values with ``repr`` precision, so
``load_model(save_model(m))`` gives the same elements, parameter values and
equations. Python functions (``Maneuver.profile(accel_x=...)``) cannot be
written: use a tabulated element instead.
"""

import dataclasses
import functools
import math
import re
from pathlib import Path

from .errors import ParameterError, RotorkitError, UnitError
from .modelformat import (  # noqa: F401  (the format and the writer, importable from here as before)
    FORMAT,
    RUN_KEYS,
    VERSION,
    ModelFileError,
    dumps_model,
    element_types,
    register_type,
    save_model,
)

__all__ = ["FORMAT", "VERSION", "ModelFileError", "dumps_model", "save_model", "loads_model", "load_model",
           "element_types", "register_type", "parse_quantity", "check_run_table", "check_signal", "model_signals"]

#: limits that make a hostile file fail fast
MAX_BYTES = 8 * 2**20
MAX_STRING = 10_000
MAX_DEPTH = 8
MAX_ITEMS = 100_000
_TOP_KEYS = ("format", "version", "name", "description", "element", "run")


# -- quantities ----------------------------------------------------------------
_NUMBER_UNIT = (r"^\s*([+-]?(?:inf|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d{1,3})?))\s*"
                r"((?![eE][+-]?\d)(?:1\s*/\s*)?[A-Za-zµ°Ω][A-Za-zµ°Ω0-9_ /*^.\-]*)?\s*$")  # compiled when used


def _fast_quantity(text):
    """Is ``text`` a number with a unit of the table pint is not needed for (rotorkit.units.fast_si)?"""
    from .units import fast_si

    try:
        return fast_si(text, "m") is not None  # "m": any unit of the table has a dimension, or raises
    except RotorkitError:
        return True  # a known unit of another dimension: still read without pint, by the element


def parse_quantity(text, name):
    """``"<number> [unit]"`` -> float or pint quantity, through the library's bounded grammar.

    Uses :func:`rotorkit.units.parse_quantity` where it exists; otherwise a
    strict fallback of the same grammar (a decimal number with at most a
    three-digit exponent, then a unit expression without numeric powers of
    more than two digits).
    """
    from . import units

    if hasattr(units, "parse_quantity"):
        return units.parse_quantity(text, name)
    if len(text) > 200:
        raise UnitError(f"{name} = {text[:40]!r}...: too long for a quantity (at most 200 characters)")
    match = re.match(_NUMBER_UNIT, text)
    if not match or (match.group(2) and re.search(r"\d\s*\*\*|\*\*\s*\d{3,}|\^\s*\d{3,}", match.group(2))):
        raise UnitError(f"{name} = {text!r}: expected a number, optionally followed by a unit (e.g. '0.25 m')")
    value = float(match.group(1))
    if not match.group(2):
        return value
    try:
        return value * units.registry().Unit(match.group(2).strip())
    except Exception as exc:
        raise UnitError(f"{name} = {text!r}: {match.group(2).strip()!r} is not a unit pint knows") from exc


# -- reading -----------------------------------------------------------------
class _Where:
    def __init__(self, source):
        self.source = source

    def error(self, where, message):
        return ModelFileError(f"{self.source}: {where}: {message}")


def _check_shape(value, depth, counter, where, ctx):
    """Refuse deep nesting, huge strings and huge arrays before building anything."""
    if depth > MAX_DEPTH:
        raise ctx.error(where, f"nested more than {MAX_DEPTH} levels deep; a model file is shallow data")
    counter[0] += 1
    if counter[0] > MAX_ITEMS:
        raise ctx.error(where, f"more than {MAX_ITEMS} values; a model file is small data")
    if isinstance(value, str) and len(value) > MAX_STRING:
        raise ctx.error(where, f"a string of {len(value)} characters (at most {MAX_STRING})")
    if isinstance(value, dict):
        for k, v in value.items():
            _check_shape(v, depth + 1, counter, f"{where}.{k}", ctx)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            _check_shape(v, depth + 1, counter, f"{where}[{i}]", ctx)


def _did_you_mean(name, options):
    import difflib

    near = difflib.get_close_matches(str(name), list(options), n=3)
    return f"did you mean {', '.join(near)}?" if near else f"expected one of: {', '.join(options)}"


def _near(name, options):
    import difflib

    near = difflib.get_close_matches(str(name), list(options), n=3)
    return f"; did you mean {', '.join(near)}?" if near else ""


def _to_python(value):
    """TOML arrays -> tuples (elements are immutable); tables stay dicts."""
    if isinstance(value, list):
        return tuple(_to_python(v) for v in value)
    if isinstance(value, dict):
        return {k: _to_python(v) for k, v in value.items()}
    return value


@functools.cache
def _init_fields(cls):
    """``(names in order, set of names)`` of the keyword arguments of a registered dataclass; once per class."""
    names = tuple(f.name for f in dataclasses.fields(cls) if f.init)
    return names, frozenset(names)


def _build(table, where, ctx, types):
    """An instance of a registered type from its table (fields checked, units parsed)."""
    type_name = table.get("type")
    if not isinstance(type_name, str):
        raise ctx.error(where, f"type = {type_name!r}: expected the name of an element type, e.g. \"Disk\" "
                               f"(types: {', '.join(sorted(types))})")
    cls = types.get(type_name)
    if cls is None:
        raise ctx.error(where, f"unknown type {type_name!r}; {_did_you_mean(type_name, sorted(types))}")
    label = table.get("name") if isinstance(table.get("name"), str) else None
    where = f"{where} ({type_name}{' ' + repr(label) if label else ''})"
    field_names, fields = _init_fields(cls)
    units = getattr(cls, "_units", {})
    kwargs = {}
    for key, raw in table.items():
        if key == "type":
            continue
        if key not in fields:
            raise ctx.error(where, f"unknown field {key!r}; {_did_you_mean(key, list(field_names))}")
        kwargs[key] = _field_value(raw, f"{where} field {key!r}", key in units, ctx, types)
    try:
        return cls(**kwargs)
    except RotorkitError as err:
        fields_named = [k for k in kwargs if re.search(rf"\b{re.escape(k)}\b", str(err))]
        if fields_named:  # show the value as the file wrote it
            key = fields_named[0]
            raise ctx.error(where, f"field {key!r} = {_to_python(table[key])!r}: {err}") from err
        raise ctx.error(where, str(err)) from err
    except (TypeError, ValueError) as err:  # a field of the wrong kind the class did not name
        raise ctx.error(where, f"{err}") from err


def _field_value(raw, where, has_unit, ctx, types):
    if has_unit and not (isinstance(raw, dict) and "type" in raw):
        if isinstance(raw, list):
            return tuple(_field_value(v, f"{where}[{i}]", True, ctx, types) for i, v in enumerate(raw))
        if isinstance(raw, str):
            if _fast_quantity(raw):
                return raw  # the element converts it to its own unit without pint (rotorkit.units.fast_si)
            try:
                return parse_quantity(raw, where)
            except RotorkitError as err:
                raise ModelFileError(f"{ctx.source}: {err}") from err
        if isinstance(raw, bool) or not isinstance(raw, (int, float)):
            raise ctx.error(where, f"= {raw!r}: expected a quantity \"<number> <unit>\" or a number in SI units")
        return float(raw)
    if isinstance(raw, dict) and "type" in raw:
        return _build(raw, where, ctx, types)
    if isinstance(raw, list):
        return tuple(_field_value(v, f"{where}[{i}]", False, ctx, types) for i, v in enumerate(raw))
    return _to_python(raw)


def loads_model(text, *, source="<string>"):
    """Build a model from model-file text; returns ``(model, run)`` (``run``: the ``[run]`` table)."""
    from .model import Model

    ctx = _Where(source)
    if len(text) > MAX_BYTES:
        raise ModelFileError(f"{source}: {len(text)} characters; a model file is at most {MAX_BYTES} bytes")
    data = _parse(text, source)
    _check_shape(data, 0, [0], "file", ctx)
    for key in data:
        if key not in _TOP_KEYS:
            raise ctx.error("top level", f"unknown key {key!r}; {_did_you_mean(key, _TOP_KEYS)}")
    if data.get("format") != FORMAT:
        raise ctx.error("format", f"= {data.get('format')!r}: expected format = \"{FORMAT}\" "
                                  "(is this a rotorkit model file?)")
    version = data.get("version")
    if not isinstance(version, int) or isinstance(version, bool) or version > VERSION or version < 1:
        raise ctx.error("version", f"= {version!r}: this rotorkit reads model files of version 1 to {VERSION}")
    name = data.get("name", Path(source).stem if source != "<string>" else "model")
    if not isinstance(name, str):
        raise ctx.error("name", f"= {name!r}: expected a string")
    tables = data.get("element")
    if not isinstance(tables, list) or not tables or not all(isinstance(t, dict) for t in tables):
        raise ctx.error("element", "expected one or more [[element]] tables")
    types = element_types()
    elements = [_build(t, f"element {i + 1}", ctx, types) for i, t in enumerate(tables)]
    run = data.get("run", {})
    if not isinstance(run, dict):
        raise ctx.error("run", f"= {run!r}: expected a table")
    for key in run:
        if key not in RUN_KEYS:
            raise ctx.error("[run]", f"unknown key {key!r}; {_did_you_mean(key, RUN_KEYS)}")
    if "t_end" in run and (isinstance(run["t_end"], bool) or not isinstance(run["t_end"], (int, float))
                           or not 0 < run["t_end"] < math.inf):
        raise ctx.error("[run] t_end", f"= {run['t_end']!r}: expected a positive number of seconds")
    try:
        model = Model(elements, name=name)
    except RotorkitError as err:
        raise ModelFileError(f"{source}: {err}") from err
    try:
        check_run_table(run, model)
    except ParameterError as err:
        raise ModelFileError(f"{source}: {err}") from None
    return model, dict(run)


def _parse(text, source):
    import tomllib

    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as err:
        raise ModelFileError(f"{source}: not valid TOML: {err}") from err
    except (RecursionError, ValueError, MemoryError) as err:  # absurd nesting, a 5000-digit integer
        raise ModelFileError(f"{source}: not a usable TOML file ({type(err).__name__}: {str(err)[:200]})") from err


def model_signals(model):
    """The signal names a run of ``model`` has: its coordinates and their rates (``x2``, ``x2_dot``, ...)."""
    names = tuple(model.coordinate_names)
    return names + tuple(f"{n}_dot" for n in names)


def check_signal(text, signals, where):
    """``text`` if it is a signal of ``signals`` or a difference ``a-b`` of two; ParameterError otherwise.

    Only such names ever become parts of file names (figures), so a name from
    a file cannot hold a path separator, ``..`` or any other character.
    """
    if not isinstance(text, str):
        raise ParameterError(f"{where} = {text!r}: expected a signal name such as {signals[0]!r} or a difference "
                             f"such as {signals[0]}-{signals[-1]}")
    parts = [part.strip() for part in text.split("-", 1)]
    unknown = [part for part in parts if part not in signals]
    if unknown:
        shown = ", ".join(signals[:12]) + (", ..." if len(signals) > 12 else "")
        raise ParameterError(f"{where} = {text!r}: {unknown[0]!r} is not a signal of the model; its signals are "
                             f"{shown} (or a difference of two, e.g. 'a-b'){_near(unknown[0], signals)}")
    return text


def check_run_table(run, model):
    """Check a ``[run]`` table (or a preset's ``OUTPUTS``) against ``model`` before any run.

    ``orbit_station`` must be a station with ``x`` and ``y`` coordinates,
    ``bending`` and ``torsion`` signals of the model (``torsion`` only on a
    model with torsion coordinates), ``clearance_parameter`` a parameter of
    the model. Raises ParameterError naming the key, the value and what is
    expected.
    """
    signals = model_signals(model)
    station = run.get("orbit_station")
    if station is not None:
        if isinstance(station, bool) or not isinstance(station, (int, str)) \
                or not (model.has_coordinate(station, "x") and model.has_coordinate(station, "y")):
            lateral = [s for s in model.stations if model.has_coordinate(s, "x") and model.has_coordinate(s, "y")]
            raise ParameterError(f"[run] orbit_station = {station!r}: expected a station with x and y "
                                 f"coordinates: {', '.join(map(str, lateral)) or 'none in this model'}")
    for key in ("bending", "torsion"):
        if run.get(key) is not None:
            check_signal(run[key], signals, f"[run] {key}")
    if run.get("torsion") is not None and not any(n.startswith("alpha") for n in model.coordinate_names):
        raise ParameterError(f"[run] torsion = {run['torsion']!r}: the model has no torsion coordinates "
                             "(alpha...); drop the key or add torsion to the model")
    clearance = run.get("clearance_parameter")
    if clearance is not None and clearance not in model.parameters:
        raise ParameterError(f"[run] clearance_parameter = {clearance!r}: not a parameter of the model"
                             f"{_near(str(clearance), list(model.parameters))}")


def load_model(path):
    """Read a model file (TOML, see :mod:`rotorkit.modelfile`) into a :class:`~rotorkit.Model`.

    Examples
    --------
    >>> import tempfile, rotorkit as rk
    >>> m = rk.Model([rk.Rotor(name="R", stations=(1,), speed=300.0),
    ...               rk.Disk(station=1, mass=2.0, radius=0.1),
    ...               rk.ElasticSupport(station=1, stiffness=2e4)])
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     m2 = rk.load_model(m.save(folder + "/jeffcott.toml"))
    >>> m2.parameters == m.parameters
    True
    """
    return read_model_file(path)[0]


def read_model_file(path):
    """``(model, run)`` from a model file: the model and its ``[run]`` table.

    The file is read as data of a bounded size and kind (:func:`rotorkit.files.read_data`):
    a FIFO, a device, a link to one or a file larger than ``MAX_BYTES`` is refused unread.
    """
    from .files import check_path, read_data

    try:
        path = check_path(path, "model file")
    except ParameterError as err:
        raise ModelFileError(str(err)) from None
    try:
        raw = read_data(path, what="model file", max_bytes=MAX_BYTES, error=ModelFileError)
        text = raw.decode("utf-8")
    except OSError as err:
        raise ModelFileError(f"{path}: cannot read the model file ({err.strerror or err})") from err
    except UnicodeDecodeError as err:
        raise ModelFileError(f"{path}: not UTF-8 text ({err.reason} at byte {err.start})") from err
    return loads_model(text, source=str(path))
