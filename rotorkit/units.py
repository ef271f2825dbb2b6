"""Units at the boundary: pint quantities or plain SI floats in, SI floats inside.

pint is imported lazily and no global pint state is changed. A quantity from
any pint registry is accepted: it is converted with its own registry.
"""

import math
import numbers

from .errors import ParameterError, UnitError

__all__ = ["to_si", "registry"]

_REGISTRY = None


def registry():
    """The pint registry rotorkit uses for its outputs (created on first use)."""
    global _REGISTRY
    if _REGISTRY is None:
        import pint

        _REGISTRY = pint.UnitRegistry()
    return _REGISTRY


def _is_quantity(value):
    return hasattr(value, "magnitude") and hasattr(value, "to") and hasattr(value, "dimensionality")


def to_si(value, unit, name, *, sign=None, allow_none=False):
    """Convert ``value`` to a float in the SI ``unit``, checking dimension and sign.

    Parameters
    ----------
    value : float, int or pint.Quantity
        A plain number is taken as already in ``unit``.
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
    if _is_quantity(value):
        if unit.startswith("rad") and "hertz" in str(value.units):
            raise UnitError(
                f"{name} = {value!r}: Hz is ambiguous for an angular quantity (pint takes 1 Hz = 1 rad/s); "
                f"give {shown_unit}, rpm or turn/s (e.g. 50 Hz spin = 50 turn/s)"
            )
        try:
            magnitude = value.to(unit or "dimensionless").magnitude
        except Exception as exc:  # pint's DimensionalityError and friends
            raise UnitError(
                f"{name} = {value!r} has the wrong unit: expected a quantity in {shown_unit}"
            ) from exc
    elif isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise UnitError(
            f"{name} = {value!r} is not a number: expected a float in {shown_unit} "
            "or a pint quantity"
        )
    else:
        magnitude = value
    try:
        magnitude = float(magnitude)
    except OverflowError as exc:
        raise ParameterError(f"{name} = {value!r} is too large: expected a finite value in {shown_unit}") from exc
    except (TypeError, ValueError) as exc:
        raise UnitError(f"{name} = {value!r} is not a scalar number in {shown_unit}") from exc
    if not math.isfinite(magnitude):
        raise ParameterError(f"{name} = {value!r} is not finite: expected a finite value in {shown_unit}")
    if sign == "positive" and not magnitude > 0:
        raise ParameterError(f"{name} = {value!r} must be > 0 ({shown_unit})")
    if sign == "nonnegative" and not magnitude >= 0:
        raise ParameterError(f"{name} = {value!r} must be >= 0 ({shown_unit})")
    return magnitude
