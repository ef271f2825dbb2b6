"""Labelling of frequencies as orders (and combinations) of the rotor speeds."""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import ParameterError
from .peaks import Peak
from .sampling import check_units, convert, positive_float

__all__ = [
    "DEFAULT_RATIOS",
    "OrderLabel",
    "label_orders",
]


#: Orders of each rotor speed tried by :func:`label_orders`.
DEFAULT_RATIOS = tuple(
    Fraction(r)
    for r in ("1/4", "1/3", "1/2", "2/3", "3/4", "1", "5/4", "4/3", "3/2", "5/3", "7/4", "2", "5/2", "3")
)

# Two candidate lines whose relative errors differ by less than this are "equally close".
_TIE_RTOL = 1e-9


@dataclass(frozen=True, slots=True)
class OrderLabel:
    """The order label of one frequency.

    Attributes
    ----------
    frequency : float
        The labelled frequency (in the ``units`` of :func:`label_orders`).
    label : str or None
        E.g. ``"1/2 low"``, ``"low"``, ``"2 high"``, ``"high - low"``,
        ``"omega_b"``; None when no candidate line is within tolerance.
    ratio : fractions.Fraction or None
        The order ``r`` for a speed harmonic ``r * speed``, ``Fraction(1)``
        for a natural frequency, None for a combination line or no match.
    reference : str or None
        Name of the speed or natural frequency; for a combination line the
        combination itself (``"high - low"``); None for no match.
    error : float or None
        Relative error ``(frequency - line) / line`` to the matched line,
        None for no match. The line is ``frequency / (1 + error)``.
    """

    frequency: float
    label: str | None
    ratio: Fraction | None
    reference: str | None
    error: float | None

    @property
    def matched(self):
        """True when a candidate line was found within tolerance."""
        return self.label is not None


@dataclass(frozen=True, slots=True)
class _Line:
    """A candidate line of :func:`label_orders` (internal)."""

    value: float
    label: str
    ratio: Fraction | None
    reference: str
    complexity: tuple


def _as_fraction(ratio):
    try:
        value = Fraction(ratio) if isinstance(ratio, (str, Fraction, numbers.Integral)) else None
        if value is None:
            value = Fraction(float(ratio)).limit_denominator(64)
    except (TypeError, ValueError, ZeroDivisionError, OverflowError) as exc:
        raise ParameterError(f"ratios contains {ratio!r}: expected positive numbers or fractions like '5/4'") from exc
    if value <= 0:
        raise ParameterError(f"ratios contains {ratio!r}: expected positive numbers or fractions like '5/4'")
    return value


def _check_named(mapping, name, units):
    if mapping is None:
        return {}
    if not isinstance(mapping, Mapping):
        raise ParameterError(f"{name}={mapping!r} is invalid: expected a mapping of names to frequencies in {units}")
    checked = {}
    for key, value in mapping.items():
        if not isinstance(key, str) or not key:
            raise ParameterError(f"{name} has the key {key!r}: expected non-empty string names")
        checked[key] = positive_float(value, f"{name}[{key!r}]", units)
    return checked


def _harmonic_label(ratio, name):
    if ratio == 1:
        return name
    return f"{ratio} {name}"


def _term(coefficient, name):
    return name if abs(coefficient) == 1 else f"{abs(coefficient)} {name}"


def _combination_lines(speeds, max_order):
    """Sum and difference lines ``m a + n b`` of pairs of speeds, ``|m| + |n| <= max_order``."""
    names = list(speeds)
    lines = []
    for i, first in enumerate(names):
        for second in names[i + 1 :]:
            for m in range(-max_order, max_order + 1):
                for n in range(-max_order, max_order + 1):
                    if m == 0 or n == 0 or abs(m) + abs(n) > max_order or math.gcd(m, n) != 1:
                        continue
                    value = m * speeds[first] + n * speeds[second]
                    if value <= 0:
                        continue
                    # positive terms first, then the faster speed first
                    terms = sorted([(m, first), (n, second)], key=lambda c: (c[0] < 0, -speeds[c[1]]))
                    label = _term(*terms[0])
                    coefficient, name = terms[1]
                    label += (" + " if coefficient > 0 else " - ") + _term(coefficient, name)
                    order = abs(m) + abs(n)
                    lines.append(_Line(value, label, None, label, (1, order, 0)))
    return lines


def _candidate_lines(speeds, natural_frequencies, ratios, max_combination_order):
    lines = []
    for name, speed in speeds.items():
        for ratio in ratios:
            complexity = (0, ratio.numerator + ratio.denominator, 0)
            lines.append(_Line(float(ratio * Fraction(speed)), _harmonic_label(ratio, name), ratio, name, complexity))
    for name, value in natural_frequencies.items():
        lines.append(_Line(value, name, Fraction(1), name, (0, 2, 1)))
    return lines + _combination_lines(speeds, max_combination_order)


def _frequency_values(peaks_or_frequencies, units):
    if isinstance(peaks_or_frequencies, (Peak, numbers.Real)):
        peaks_or_frequencies = [peaks_or_frequencies]
    if isinstance(peaks_or_frequencies, np.ndarray):
        peaks_or_frequencies = peaks_or_frequencies.ravel().tolist()
    if not isinstance(peaks_or_frequencies, Iterable):
        raise ParameterError(
            f"peaks_or_frequencies={peaks_or_frequencies!r} is invalid: expected Peaks or frequencies in {units}"
        )
    values = []
    for item in peaks_or_frequencies:
        if isinstance(item, Peak):
            values.append(convert(float(item.frequency), check_units(item.units, "Peak.units"), units))
        elif isinstance(item, numbers.Real) and not isinstance(item, bool) and math.isfinite(item):
            values.append(float(item))
        else:
            raise ParameterError(
                f"peaks_or_frequencies contains {item!r}: expected Peak objects or finite frequencies in {units}"
            )
    return values


def _best_line(frequency, lines, tolerance):
    if frequency <= 0:
        return None, None
    best, best_error = None, None
    for line in lines:
        error = (frequency - line.value) / line.value
        if abs(error) > tolerance:
            continue
        if best is None or abs(error) < abs(best_error) - _TIE_RTOL:
            best, best_error = line, error
        elif abs(error) <= abs(best_error) + _TIE_RTOL and line.complexity < best.complexity:
            best, best_error = line, error
    return best, best_error


def label_orders(
    peaks_or_frequencies,
    speeds,
    natural_frequencies=None,
    ratios=DEFAULT_RATIOS,
    tolerance=0.02,
    units="rad/s",
    max_combination_order=3,
):
    """Label frequencies as orders of the rotor speeds.

    Candidate lines are, for every speed, ``r * speed`` for ``r`` in
    ``ratios``; for every pair of speeds ``a``, ``b`` the combination lines
    ``m a + n b > 0`` with non-zero integers ``|m| + |n| <= max_combination_order``
    (``high - low``, ``high + low``, ``2 low - high``, ...); and the named
    natural frequencies.

    Parameters
    ----------
    peaks_or_frequencies : Peak, float or iterable of them
        Frequencies to label. Plain numbers are in ``units``; a
        :class:`Peak` is converted from its own units.
    speeds : mapping of str to float
        Rotor speeds by name, in ``units``, e.g. ``{"low": 1500.0, "high": 2700.0}``.
    natural_frequencies : mapping of str to float, optional
        Named natural frequencies in ``units``, e.g. ``{"omega_b": 336.0}``.
    ratios : iterable of Fraction, int, float or str, optional
        Orders tried for each speed (default :data:`DEFAULT_RATIOS`); floats
        are rounded to the nearest fraction with denominator <= 64.
    tolerance : float, optional
        Largest relative distance ``|f - line| / line`` accepted (default 0.02).
    units : {"rad/s", "Hz"}, optional
        Units of the speeds, natural frequencies, plain-number frequencies
        and of the returned ``OrderLabel.frequency``.
    max_combination_order : int, optional
        Largest ``|m| + |n|`` of the combination lines (default 3; 2 gives
        the first-order sum and difference lines only, 0 none).

    Returns
    -------
    list of OrderLabel
        One per input frequency, in input order: the nearest line (smallest
        relative error) within ``tolerance``, or ``label=None``. When lines
        are equally close (e.g. ``high`` and ``2 low`` if ``high = 2 low``),
        the simplest wins: speed harmonics and natural frequencies before
        combination lines; among the former the smallest ``numerator +
        denominator`` of the order (a natural frequency counts as order 1,
        and loses a tie with an order-1 speed line); among combinations the
        smallest ``|m| + |n|``.

    Raises
    ------
    ParameterError
        (a ``ValueError``) for non-positive speeds, ratios or tolerance,
        unknown units or non-numeric frequencies.
    """
    units = check_units(units)
    speeds = _check_named(speeds, "speeds", units)
    if not speeds:
        raise ParameterError("speeds={} is empty: expected at least one named rotor speed")
    natural_frequencies = _check_named(natural_frequencies, "natural_frequencies", units)
    tolerance = positive_float(tolerance, "tolerance")
    if isinstance(ratios, (str, numbers.Number)) or not isinstance(ratios, Iterable):
        raise ParameterError(f"ratios={ratios!r} is invalid: expected an iterable of positive orders")
    ratios = [_as_fraction(r) for r in ratios]
    if (
        isinstance(max_combination_order, bool)
        or not isinstance(max_combination_order, numbers.Integral)
        or max_combination_order < 0
    ):
        raise ParameterError(f"max_combination_order={max_combination_order!r} is invalid: expected an integer >= 0")
    lines = _candidate_lines(speeds, natural_frequencies, ratios, int(max_combination_order))
    labels = []
    for frequency in _frequency_values(peaks_or_frequencies, units):
        line, error = _best_line(frequency, lines, tolerance)
        if line is None:
            labels.append(OrderLabel(frequency, None, None, None, None))
        else:
            labels.append(OrderLabel(frequency, line.label, line.ratio, line.reference, float(error)))
    return labels
