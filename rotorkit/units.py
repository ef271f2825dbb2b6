"""Units at the boundary: pint quantities or plain SI floats in, SI floats inside.

pint is imported lazily and no global pint state is changed. A quantity from
any pint registry is accepted: it is converted with its own registry.
"""

import math
import numbers
import re

from .errors import ParameterError, UnitError

__all__ = ["to_si", "fast_si", "to_si_array", "registry", "parse_quantity", "parse_unit", "display_factor", "SPEED_UNITS"]

_REGISTRY = None


def registry():
    """The pint registry rotorkit uses for its outputs (created on first use)."""
    global _REGISTRY
    if _REGISTRY is None:
        import pint

        _REGISTRY = pint.UnitRegistry()
    return _REGISTRY


#: limits of the quantity grammar: every text it accepts is parsed in time linear in its length
MAX_TEXT = 200
MAX_EXPONENT = 12  # |exponent| of any unit name after multiplying out parentheses
MAX_DEPTH = 3  # nested parentheses
MAX_NAMES = 16  # unit names in one expression

NUMBER_PATTERN = re.compile(r"[+-]?(?:inf(?:inity)?|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d{1,3})?)(?![\w.])", re.IGNORECASE)
_TOKEN = re.compile(r"\s*(?:(?P<name>(?:[^\W\d]|°)(?:\w|°)*)|(?P<int>[+-]?[\d.]+)|(?P<op>\*\*|[*/^()·]))")
_NAME = re.compile(r"[A-Za-zµμ°Ω_]+")
_GRAMMAR = ("a number, optionally followed by a unit expression: unit names joined by *, / or a space, "
            f"exponents ^n or **n (n, 1.5 or (3/2)) with |n| <= {MAX_EXPONENT}, at most {MAX_DEPTH} nested parentheses")


class _NotANumber(UnitError):
    """The text does not start with a number (to_si words this for its own callers)."""


def _tokens(text, where):
    tokens, pos = [], 0
    while pos < len(text):
        match = _TOKEN.match(text, pos)
        if not match:
            if text[pos:].strip() == "":
                break
            raise UnitError(f"{where}: unexpected {text[pos:].strip()[:20]!r} in the unit; expected {_GRAMMAR}")
        kind = match.lastgroup
        tokens.append((kind, match.group(kind)))
        pos = match.end()
    return tokens


class _UnitParser:
    """Recursive descent over the unit tokens; builds {name: exponent} with bounded exponents.

    Exponents are ints, or :class:`fractions.Fraction` for a fractional one (``m^1.5``, ``s^(1/2)``; the
    module is imported then: reading ``"2 MN/m"`` does not need it).
    """

    def __init__(self, tokens, where):
        self.tokens, self.pos, self.where, self.names = tokens, 0, where, 0

    def fail(self, what):
        raise UnitError(f"{self.where}: {what}; expected {_GRAMMAR}")

    def peek(self):
        return self.tokens[self.pos] if self.pos < len(self.tokens) else (None, None)

    def take(self):
        token = self.peek()
        self.pos += 1
        return token

    def expression(self, depth):
        powers = {}
        kind, text = self.peek()
        if kind == "int" and text == "1" and self.tokens[self.pos + 1:self.pos + 2] == [("op", "/")]:
            self.pos += 1  # a leading "1/" as in "1/s"
            sign = -1
            self.take()
        else:
            sign = 1
        while True:
            self.merge(powers, self.term(depth), sign)
            kind, text = self.peek()
            if kind == "op" and text in ("*", "·"):
                self.take()
                sign = 1
            elif kind == "op" and text == "/":
                self.take()
                sign = -1
            elif kind == "name" or (kind == "op" and text == "("):
                sign = 1  # a space multiplies: "N m"
            else:
                return powers

    def term(self, depth):
        kind, text = self.take()
        if kind == "name":
            if not _NAME.fullmatch(text) or len(text) > 40:
                self.fail(f"{text!r} is not a unit name")
            self.names += 1
            if self.names > MAX_NAMES:
                self.fail(f"more than {MAX_NAMES} unit names")
            powers = {text: 1}
        elif kind == "op" and text == "(":
            if depth >= MAX_DEPTH:
                self.fail(f"more than {MAX_DEPTH} nested parentheses")
            powers = self.expression(depth + 1)
            if self.take() != ("op", ")"):
                self.fail("unbalanced parentheses")
        else:
            self.fail(f"{text!r} where a unit name was expected" if text else "the unit ends too early")
        kind, text = self.peek()
        if kind == "op" and text in ("^", "**"):
            self.take()
            exponent = self.exponent()
            powers = {name: power * exponent for name, power in powers.items()}
            if self.peek() in (("op", "^"), ("op", "**")):
                self.fail("an exponent of an exponent")
        for name, power in powers.items():
            if abs(power) > MAX_EXPONENT:
                self.fail(f"{name} to the power {power}")
        return powers

    def exponent(self):
        """A small exponent: ``n``, ``n.5`` style decimals (``1.5``) or a fraction in parentheses ``(3/2)``."""
        kind, text = self.take()
        if kind == "int" and re.fullmatch(r"[+-]?\d{1,2}", text):
            return int(text)
        if kind == "int" and re.fullmatch(r"[+-]?\d{1,2}\.\d{1,2}", text):
            from fractions import Fraction

            return Fraction(text)
        if (kind, text) == ("op", "("):
            (k1, num), (k2, op), (k3, den), (k4, close) = (self.take() for _ in range(4))
            if (k1, k2, k3, k4, op, close) == ("int", "op", "int", "op", "/", ")") and \
                    re.fullmatch(r"[+-]?\d{1,2}", num) and re.fullmatch(r"\d{1,2}", den) and int(den) > 0:
                from fractions import Fraction

                return Fraction(int(num), int(den))
        self.fail(f"the exponent {text!r} is not a small number (n, 1.5 or (3/2))")

    def merge(self, powers, more, sign):
        for name, power in more.items():
            powers[name] = powers.get(name, 0) + sign * power
            if abs(powers[name]) > MAX_EXPONENT:
                self.fail(f"{name} to the power {powers[name]}")


def parse_unit(text, name="unit"):
    """A pint unit from a bounded unit expression (``"N/m"``, ``"kg*m^2"``, ``"1/s"``, ``"(m/s)**2"``).

    pint's own string evaluation is never used on the whole text: the
    expression is parsed here (unit names, ``*``, ``/``, a space, ``^n`` or
    ``**n`` (an integer, a short decimal such as 1.5 or a fraction ``(3/2)``) with ``|n| <= 12``, at most 3 nested parentheses) and only single
    unit names are looked up in the registry, so no text can make it hang.

    Raises
    ------
    UnitError
        Not such an expression, or a name pint does not know.
    """
    where = f"{name} = {text!r}"
    if not isinstance(text, str):
        raise UnitError(f"{where}: a unit must be a string")
    if len(text) > MAX_TEXT:
        raise UnitError(f"{name}: the unit text is longer than {MAX_TEXT} characters")
    parser = _UnitParser(_tokens(text, where), where)
    powers = parser.expression(0)
    if parser.pos != len(parser.tokens):
        parser.fail(f"unexpected {parser.tokens[parser.pos][1]!r}")
    ureg = registry()
    unit = ureg.Unit("dimensionless")
    for unit_name, power in powers.items():
        if power == 0:
            continue
        try:
            unit = unit * ureg.Unit(unit_name) ** (int(power) if power.denominator == 1 else float(power))
        except Exception as exc:  # pint's UndefinedUnitError and friends
            raise UnitError(f"{where}: {unit_name!r} is not a unit pint knows (e.g. N/m, mm, rpm, kg*m^2)") from exc
    return unit


#: units read without pint (its import and registry cost about 1.5 s, the whole load of a model file):
#: name -> (factor to SI, exponents of (m, kg, s)); angles are dimensionless, as in pint. Anything else
#: (Hz, which is ambiguous for an angular quantity, imperial units, ...) goes through pint.
_FAST_UNITS = {
    **{n: (f, (1, 0, 0)) for n, f in (("m", 1.0), ("mm", 1e-3), ("cm", 1e-2), ("um", 1e-6), ("µm", 1e-6),
                                       ("μm", 1e-6))},
    **{n: (f, (0, 1, 0)) for n, f in (("kg", 1.0), ("g", 1e-3))},
    **{n: (f, (0, 0, 1)) for n, f in (("s", 1.0), ("ms", 1e-3), ("min", 60.0))},
    **{n: (f, (1, 1, -2)) for n, f in (("N", 1.0), ("kN", 1e3), ("MN", 1e6))},
    **{n: (f, (-1, 1, -2)) for n, f in (("Pa", 1.0), ("kPa", 1e3), ("MPa", 1e6), ("GPa", 1e9))},
    "rad": (1.0, (0, 0, 0)),
    "deg": (math.pi / 180.0, (0, 0, 0)),
    "rpm": (2.0 * math.pi / 60.0, (0, 0, -1)),
}


_FAST_UNIT_MEMO = {}  # unit text -> _fast_unit's answer: a model file repeats a handful of units


def _fast_unit(text):
    """(factor to SI, dimension) of a unit expression of the names in ``_FAST_UNITS``, or None (memoised)."""
    try:
        return _FAST_UNIT_MEMO[text]
    except KeyError:
        pass
    answer = _parse_fast_unit(text)
    if len(_FAST_UNIT_MEMO) < 256:
        _FAST_UNIT_MEMO[text] = answer
    return answer


def _parse_fast_unit(text):
    if not text:
        return 1.0, (0, 0, 0)
    try:
        parser = _UnitParser(_tokens(text, "unit"), "unit")
        powers = parser.expression(0)
    except UnitError:
        return None
    if parser.pos != len(parser.tokens):
        return None
    factor, dims = 1.0, [0, 0, 0]
    for unit_name, power in powers.items():
        if unit_name not in _FAST_UNITS or power.denominator != 1:
            return None
        f, d = _FAST_UNITS[unit_name]
        factor *= f ** int(power)
        dims = [a + int(power) * b for a, b in zip(dims, d)]
    return factor, tuple(dims)


def fast_si(text, unit):
    """``text`` (a number and a unit of the common engineering units) in the SI ``unit``, without pint.

    Returns None when the text or ``unit`` holds a unit outside the table (the caller then uses pint),
    and raises :class:`UnitError` for a known unit of the wrong dimension. The factors are pint's.

    >>> fast_si("3000 rpm", "rad/s"), fast_si("60 mm", "m"), fast_si("2 MN/m", "N/m"), fast_si("5 furlong", "m")
    (314.1592653589793, 0.06, 2000000.0, None)
    """
    if not isinstance(text, str) or len(text) > MAX_TEXT:
        return None
    stripped = text.strip()
    match = NUMBER_PATTERN.match(stripped)
    if not match:
        return None
    rest = stripped[match.end():].strip()
    if not rest:
        return float(match.group(0))  # a plain number is already in ``unit``, as in to_si
    given, expected = _fast_unit(rest), _fast_unit(unit)
    if given is None or expected is None:
        return None
    if given[1] != expected[1]:
        raise UnitError(f"{text!r} has the wrong unit: expected a quantity in {unit or 'dimensionless'}")
    return float(match.group(0)) * given[0] / expected[0]


def parse_quantity(text, name="value"):
    """A float or a pint quantity from text: ``"2e6"``, ``"2e6 N/m"``, ``"3000 rpm"``.

    The grammar is bounded (see :func:`parse_unit`): a decimal number
    (``inf`` allowed, refused later by the parameter's own finiteness check),
    optionally followed by a unit expression. Anything else, hex, ``nan``,
    a comma decimal, an exponent of an exponent in any spelling, is refused.

    Returns
    -------
    float or pint.Quantity
        A float when the text holds no unit.

    Raises
    ------
    UnitError
        The text is not a number with an optional unit expression.
    """
    if not isinstance(text, str):
        raise UnitError(f"{name} = {text!r}: expected a string such as '2e6 N/m'")
    if len(text) > MAX_TEXT:
        raise UnitError(f"{name}: the text is longer than {MAX_TEXT} characters; expected {_GRAMMAR}")
    stripped = text.strip()
    match = NUMBER_PATTERN.match(stripped)
    if not match:
        raise _NotANumber(f"{name} = {text!r}: not a number or a quantity with units (e.g. 2e6 or '2e6 N/m')")
    value = float(match.group(0))
    rest = stripped[match.end():].strip()
    if not rest:
        return value
    if rest[0] not in "(1" and not (rest[0].isalpha() or rest[0] in "µμ°Ω_"):
        raise _NotANumber(f"{name} = {text!r}: not a number or a quantity with units (e.g. 2e6 or '2e6 N/m')")
    unit = parse_unit(rest, name)
    try:
        return registry().Quantity(value, unit)
    except Exception as exc:  # an offset unit (degC) inside a compound unit
        raise UnitError(f"{name} = {text!r}: {rest!r} cannot carry a value (offset unit in a compound)") from exc


def _is_quantity(value):
    return hasattr(value, "magnitude") and hasattr(value, "to") and hasattr(value, "dimensionality")


#: True for a pint quantity (duck-typed, so pint is not imported); public for other modules
is_quantity = _is_quantity


def to_si(value, unit, name, *, sign=None, allow_none=False):
    """Convert ``value`` to a float in the SI ``unit``, checking dimension and sign.

    Parameters
    ----------
    value : float, int, str or pint.Quantity
        A plain number is taken as already in ``unit``; a string is read by
        :func:`parse_quantity` (``"2e6 N/m"``).
    unit : str
        The SI unit expected, e.g. ``"kg"``, ``"N/m"``, ``"rad/s"``; ``""`` for
        dimensionless.
    name : str
        Parameter name, used in error messages.
    sign : {None, "positive", "nonnegative"}
        Required sign.
    allow_none : bool
        Pass ``None`` through unchanged.

    Returns
    -------
    float

    Raises
    ------
    UnitError
        Wrong dimension or not a number.
    ParameterError
        Not finite, or wrong sign.
    """
    if value is None and allow_none:
        return None
    shown_unit = unit or "dimensionless"
    shown = value  # the messages show what the user gave
    if isinstance(value, str) or _is_quantity(value):
        magnitude = _quantity_parts(value, unit, name, shown, scalar=True)
    elif isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise UnitError(
            f"{name} = {shown!r} is not a number: expected a float in {shown_unit} "
            "or a pint quantity"
        )
    else:
        magnitude = value
    try:
        magnitude = float(magnitude)
    except OverflowError as exc:
        raise ParameterError(f"{name} = {shown!r} is too large: expected a finite value in {shown_unit}") from exc
    except (TypeError, ValueError) as exc:
        raise UnitError(f"{name} = {shown!r} is not a scalar number in {shown_unit}") from exc
    if not math.isfinite(magnitude):
        raise ParameterError(f"{name} = {shown!r} is not finite: expected a finite value in {shown_unit}")
    if sign == "positive" and not magnitude > 0:
        raise ParameterError(f"{name} = {shown!r} must be > 0 ({shown_unit})")
    if sign == "nonnegative" and not magnitude >= 0:
        raise ParameterError(f"{name} = {shown!r} must be >= 0 ({shown_unit})")
    return magnitude


def _quantity_parts(value, unit, name, shown, scalar=False):
    """Magnitude (any shape, still a number or an array) of ``value`` in ``unit``: dimension checked.

    A string of common units is read without pint (:func:`fast_si`); ``scalar`` words the messages for
    one value (:func:`to_si`).
    """
    expected = f"a float in {unit or 'dimensionless'}" if scalar else f"values in {unit or 'dimensionless'}"
    example = "'2e6 N/m'" if scalar else "'3000 rpm'"
    if isinstance(value, str):
        try:
            fast = fast_si(value, unit)
        except UnitError:
            raise UnitError(f"{name} = {shown!r} has the wrong unit: expected a quantity in "
                            f"{unit or 'dimensionless'}") from None
        if fast is not None:
            return fast
        try:
            value = parse_quantity(value, name)
        except _NotANumber:
            raise UnitError(f"{name} = {shown!r} is not a number: expected {expected}, a pint quantity or a "
                            f"string such as {example}") from None
    if _is_quantity(value):
        if unit.startswith("rad") and "hertz" in str(value.units):
            raise UnitError(
                f"{name} = {shown!r}: Hz is ambiguous for an angular quantity (pint takes 1 Hz = 1 rad/s); "
                f"give {unit}, rpm or turn/s (e.g. 50 Hz spin = 50 turn/s)"
            )
        try:
            return value.to(unit or "dimensionless").magnitude
        except Exception as exc:  # pint's DimensionalityError and friends
            raise UnitError(f"{name} = {shown!r} has the wrong unit: expected a quantity in "
                            f"{unit or 'dimensionless'}") from exc
    return value


def to_si_array(value, unit, name, *, complex_values=False):
    """Convert numbers, arrays, pint quantities (scalar or array) or strings to a float array in ``unit``.

    The array form of :func:`to_si`: a pint array keeps its unit until it is
    converted (``Q_([0, 1000], "rpm")`` gives ``[0, 104.7...]`` rad/s, never
    the stripped magnitudes), a string or a sequence of strings and
    quantities is converted item by item (``["0 rpm", "3000 rpm"]``), plain
    numbers are taken as already in ``unit``.

    Parameters
    ----------
    value : float, array_like, str, pint.Quantity or sequence of them
    unit : str
        The SI unit expected (``"rad/s"``, ``"N/m"``, ``"s"``, ``""``).
    name : str
        Parameter name, used in error messages.
    complex_values : bool
        Keep complex numbers (amplitudes); otherwise a float array.

    Returns
    -------
    numpy.ndarray
        Same shape as the input (0-d for a scalar); no finiteness check (the
        caller says what it needs).

    Raises
    ------
    UnitError
        A wrong dimension, or not numbers.

    Examples
    --------
    >>> to_si_array(["0 rpm", "3000 rpm"], "rad/s", "speeds").round(4).tolist()
    [0.0, 314.1593]
    """
    import numpy as np

    shown = value
    value = _quantity_parts(value, unit, name, shown)
    if isinstance(value, (list, tuple)) and any(isinstance(v, str) or _is_quantity(v) for v in value):
        value = [_quantity_parts(v, unit, name, shown) for v in value]
    dtype = complex if complex_values else float
    try:
        array = np.array(value, dtype=dtype)
    except (TypeError, ValueError) as exc:
        raise UnitError(f"{name} = {shown!r} is not numbers: expected values in {unit or 'dimensionless'}, "
                        "a pint quantity or strings such as '3000 rpm'") from exc
    if array.dtype == object:  # pragma: no cover - np.array with a dtype never gives object
        raise UnitError(f"{name} = {shown!r} is not numbers")
    return array


#: output units of a speed or frequency -> factor from rad/s (Hz and rpm as cycles: 1 Hz = 2 pi rad/s)
SPEED_UNITS = {"rad/s": 1.0, "Hz": 1.0 / (2.0 * math.pi), "rpm": 60.0 / (2.0 * math.pi)}
#: output length units -> factor from metres
LENGTH_UNITS = {"m": 1.0, "mm": 1e3, "um": 1e6, "µm": 1e6}


def display_factor(units, kind="speed", name="units"):
    """Factor from SI to the output ``units`` of a printed or plotted quantity.

    Parameters
    ----------
    units : str
        For ``kind="speed"``: ``"rad/s"``, ``"Hz"`` (cycles per second),
        ``"rpm"`` or any angular-speed unit pint knows (``"krpm"`` is not
        one; ``"turn/min"``, ``"deg/s"`` are). For ``kind="length"``: ``"m"``,
        ``"mm"``, ``"um"`` or any length unit.
    kind : {"speed", "length"}
    name : str
        Parameter name in error messages.

    Raises
    ------
    UnitError
        Not a unit of that kind.
    """
    table, si = (SPEED_UNITS, "rad/s") if kind == "speed" else (LENGTH_UNITS, "m")
    if isinstance(units, str) and units in table:
        return table[units]
    if not isinstance(units, str):
        raise UnitError(f"{name}={units!r} is not supported: expected one of {tuple(table)} or a unit "
                        f"of {kind} such as {tuple(table)[-1]!r}")
    try:
        unit = parse_unit(units, name)
        if kind == "speed" and "hertz" in str(unit):
            raise UnitError(f"{name}={units!r}: only 'Hz' itself is read as cycles per second")
        return float(registry().Quantity(1.0, si).to(unit).magnitude)
    except Exception as exc:
        raise UnitError(f"{name}={units!r} is not supported: expected one of {tuple(table)} or a unit "
                        f"of {kind} ({si})") from exc
