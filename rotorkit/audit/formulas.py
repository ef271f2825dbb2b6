"""The API 617 formulas of an audit: unbalance magnitude, amplification factor, separation margins, ``Q_A``.

Sources: API Standard 617, *Axial and Centrifugal Compressors and
Expander-compressors*, 8th edition (2014), 4.8 (lateral analysis:
unbalance response, amplification factor, separation margins; Level I
stability); API RP 684, *Tutorial on the API Standard Paragraphs Covering
Rotor Dynamics*, 2nd edition (2005), for the half-power method and the
Wachel estimate of the aerodynamic cross-coupling. Every function takes SI
floats, pint quantities or strings (``"10000 rpm"``) and returns SI floats.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["UNBALANCE_CONSTANT", "UNBALANCE_SPEED_LIMIT_RPM", "ANALYSIS_UNBALANCE_MULTIPLE", "unbalance_magnitude",
           "analysis_unbalance", "AmplificationFactor", "amplification_factor", "required_separation_margin",
           "separation_margin", "wachel_cross_coupling", "CRITICALLY_DAMPED_AF", "SEPARATION_MARGIN_CAPS",
           "vibration_limit", "CLEARANCE_FRACTION", "SCALE_FACTOR_LIMITS", "clearance_scale_factor"]

#: the 6350 of ``U_r = 6350 W / N`` (g mm, with W in kg and N in rpm): 4 W/N in oz in, the API "4W/N" rule
UNBALANCE_CONSTANT = 6350.0

#: ``N`` of ``U_r = 6350 W / N`` is the maximum continuous speed, but at most 25000 rpm
UNBALANCE_SPEED_LIMIT_RPM = 25000.0

#: the unbalance response analysis applies twice the residual unbalance ``U_r`` (API 617 7th ed. 2.6.2.7,
#: 8th ed. 4.8.2.7, 9th ed. 6.8.2.7; editions before the 7th applied four times ``U_r``)
ANALYSIS_UNBALANCE_MULTIPLE = 2.0

#: ceilings (percent) of the required separation margin below and above the operating range
SEPARATION_MARGIN_CAPS = (16.0, 26.0)

#: close-clearance limit: 75 % of the minimum design diametral running clearance
CLEARANCE_FRACTION = 0.75

#: the scale factor ``S_cc = A_vl / A_max`` is clipped to these bounds
SCALE_FACTOR_LIMITS = (0.5, 6.0)

#: a mode whose amplification factor is below this is critically damped: no separation margin is required
CRITICALLY_DAMPED_AF = 2.5


def _positive(value, unit, name):
    from ..units import to_si

    v = to_si(value, unit, name)
    if not (math.isfinite(v) and v > 0):
        raise ParameterError(f"{name}={value!r} is invalid: expected a positive finite value ({unit})")
    return v


def unbalance_magnitude(journal_load, max_continuous_speed):
    """API 617 residual unbalance ``U_r = 6350 W / N`` (g mm), returned in kg m.

    Parameters
    ----------
    journal_load : float, str or pint.Quantity
        ``W``: the journal static load as a mass (kg): the sum of the
        journals' loads for a first (translatory) mode, the load of the
        nearest journal for each unbalance of a higher mode, the mass
        outboard of the bearing for an overhung end.
    max_continuous_speed : float, str or pint.Quantity
        ``N``: maximum continuous speed (rad/s, or e.g. ``"10000 rpm"``);
        above 25000 rpm, 25000 rpm is used
        (:data:`UNBALANCE_SPEED_LIMIT_RPM`).

    Returns
    -------
    float
        ``U_r`` in kg m (``1 g mm = 1e-6 kg m``). The unbalance response
        analysis applies :func:`analysis_unbalance`, twice this.

    Examples
    --------
    >>> round(unbalance_magnitude("1000 kg", "10000 rpm") * 1e6, 6)   # g mm: 6350 x 1000 / 10000
    635.0
    >>> round(unbalance_magnitude("1000 kg", "30000 rpm") * 1e6, 6)   # N held at 25000 rpm
    254.0
    """
    w = _positive(journal_load, "kg", "journal_load")
    n_rpm = _positive(max_continuous_speed, "rad/s", "max_continuous_speed") * 30.0 / math.pi
    return UNBALANCE_CONSTANT * w / min(n_rpm, UNBALANCE_SPEED_LIMIT_RPM) * 1e-6


def analysis_unbalance(journal_load, max_continuous_speed, multiple=ANALYSIS_UNBALANCE_MULTIPLE):
    """The unbalance of the API 617 response analysis, ``multiple x U_r`` (kg m); ``multiple`` 2 by the standard.

    Examples
    --------
    >>> round(analysis_unbalance("1000 kg", "10000 rpm") * 1e6, 6)   # 2 x 6350 x 1000 / 10000 g mm
    1270.0
    """
    m = float(multiple)
    if not (math.isfinite(m) and m > 0):
        raise ParameterError(f"multiple={multiple!r} is invalid: expected a positive multiple of U_r "
                             f"(the standard's is {ANALYSIS_UNBALANCE_MULTIPLE:g})")
    return m * unbalance_magnitude(journal_load, max_continuous_speed)


@dataclass(frozen=True, slots=True)
class AmplificationFactor:
    """Amplification factor of one resonance peak by the half-power bandwidth (API 617, API 684).

    Attributes
    ----------
    critical_speed : float
        ``N_c1``, the speed (rad/s) of the peak response.
    peak : float
        Peak amplitude (m).
    lower, upper : float
        ``N_1``, ``N_2`` (rad/s): where the amplitude is ``peak / sqrt(2)``
        (NaN where the sweep ends first; the bandwidth is then twice the
        one-sided width).
    factor : float
        ``AF = N_c1 / (N_2 - N_1)``; 0 when there is no peak (a
        critically damped response).
    """

    critical_speed: float
    peak: float
    lower: float
    upper: float
    factor: float

    @property
    def critically_damped(self):
        """``AF < 2.5``: API 617 asks no separation margin of such a mode."""
        return self.factor < CRITICALLY_DAMPED_AF


def _crossing(x0, x1, a0, a1, level):
    return x0 + (level - a0) * (x1 - x0) / (a1 - a0)


def amplification_factor(speeds, amplitude, window=None):
    """``AF = N_c1 / (N_2 - N_1)`` of the highest peak of ``amplitude`` (within ``window``).

    Parameters
    ----------
    speeds : array_like, shape (n,)
        Increasing speeds (rad/s).
    amplitude : array_like, shape (n,)
        Response amplitude (any unit) at each speed.
    window : (float, float), optional
        Speeds (rad/s) the peak is searched in (default: the whole sweep);
        the half-power points may lie outside it.

    Returns
    -------
    AmplificationFactor
        ``factor = 0`` (critically damped) when the largest amplitude in the
        window is at its edge (no resonance peak) or never falls to
        ``peak / sqrt(2)`` on either side.

    Notes
    -----
    For a single degree of freedom with damping ratio ``zeta`` the
    half-power bandwidth is ``2 zeta`` of the resonance and ``AF = 1 / (2 zeta)``
    to first order in ``zeta`` (API 684).
    """
    w = np.asarray(speeds, dtype=float).reshape(-1)
    a = np.asarray(amplitude, dtype=float).reshape(-1)
    if w.size < 3 or a.shape != w.shape or not np.all(np.diff(w) > 0) or not np.all(np.isfinite(a)):
        raise ParameterError(f"speeds and amplitude: expected {w.size} >= 3 increasing speeds and as many finite "
                             f"amplitudes, got shapes {np.shape(speeds)} and {np.shape(amplitude)}")
    lo, hi = (w[0], w[-1]) if window is None else (float(window[0]), float(window[1]))
    inside = np.flatnonzero((w >= lo) & (w <= hi))
    if inside.size == 0:
        raise ParameterError(f"window={window!r} holds no speed of the sweep ({w[0]:g} to {w[-1]:g} rad/s)")
    k = int(inside[np.argmax(a[inside])])
    none = AmplificationFactor(critical_speed=float(w[k]), peak=float(a[k]), lower=math.nan, upper=math.nan,
                               factor=0.0)
    if k in (inside[0], inside[-1]) or k in (0, w.size - 1):
        return none
    # refine the peak by a parabola through the three samples around it
    x, y = w[k - 1:k + 2], a[k - 1:k + 2]
    c = np.polyfit(x, y, 2)
    peak_speed, peak = w[k], a[k]
    if c[0] < 0:
        top = -c[1] / (2 * c[0])
        if x[0] < top < x[2]:
            peak_speed, peak = float(top), float(np.polyval(c, top))
    level = peak / math.sqrt(2.0)
    lower = upper = math.nan
    for i in range(k, 0, -1):
        if a[i - 1] <= level < a[i]:
            lower = _crossing(w[i - 1], w[i], a[i - 1], a[i], level)
            break
        if a[i - 1] > a[i] and a[i] > level:  # climbing again: another peak before the half-power point
            break
    for i in range(k, w.size - 1):
        if a[i + 1] <= level < a[i]:
            upper = _crossing(w[i], w[i + 1], a[i], a[i + 1], level)
            break
        if a[i + 1] > a[i] and a[i] > level:
            break
    if math.isnan(lower) and math.isnan(upper):
        return none
    width = (upper - lower) if not (math.isnan(lower) or math.isnan(upper)) else (
        2 * (upper - peak_speed) if math.isnan(lower) else 2 * (peak_speed - lower))
    return AmplificationFactor(critical_speed=float(peak_speed), peak=float(peak), lower=float(lower),
                               upper=float(upper), factor=float(peak_speed / width))


def required_separation_margin(factor, above):
    """Separation margin (percent) API 617 requires of a mode with amplification factor ``factor``.

    ``AF < 2.5``: none (0). Otherwise ``SM = min(16, 17 (1 - 1 / (AF - 1.5)))``
    for a mode below the minimum operating speed and
    ``SM = min(26, 10 + 17 (1 - 1 / (AF - 1.5)))`` for one above the maximum
    continuous speed (API 617 8th ed. 4.8.2.10; API 684 SP6.8.2.10; the
    ceilings :data:`SEPARATION_MARGIN_CAPS` bind from ``AF = 18.5``).

    Parameters
    ----------
    factor : float
        Amplification factor (>= 0).
    above : bool
        True for a mode above the operating range.
    """
    af = float(factor)
    if not (math.isfinite(af) and af >= 0):
        raise ParameterError(f"factor={factor!r} is invalid: expected an amplification factor >= 0")
    if af < CRITICALLY_DAMPED_AF:
        return 0.0
    margin = 17.0 * (1.0 - 1.0 / (af - 1.5))
    below_cap, above_cap = SEPARATION_MARGIN_CAPS
    return min(margin + 10.0, above_cap) if above else min(margin, below_cap)


def vibration_limit(max_continuous_speed):
    """``A_vl = 25.4 sqrt(12000 / N_mc)`` um peak to peak, at most 25.4 um; returned in m.

    The limit of the unbalance response at the vibration probes within the
    operating range (API 617 8th ed. 4.8.2.10, 9th ed. 6.8.2.10; the
    mechanical running test's limit), ``N_mc`` the maximum continuous speed
    in rpm.

    Examples
    --------
    >>> round(vibration_limit("20000 rpm") * 1e6, 4)   # 25.4 sqrt(0.6) um
    19.6748
    >>> round(vibration_limit("6000 rpm") * 1e6, 4)    # capped below 12000 rpm
    25.4
    """
    n_rpm = _positive(max_continuous_speed, "rad/s", "max_continuous_speed") * 30.0 / math.pi
    return 25.4e-6 * min(1.0, math.sqrt(12000.0 / n_rpm))


def clearance_scale_factor(limit, max_amplitude, limits=SCALE_FACTOR_LIMITS):
    """``S_cc = A_vl / A_max`` clipped to ``limits`` (API 617 8th ed. 4.8.2.11).

    The unbalance response at the close clearances is multiplied by it: the
    rotor is taken to vibrate at the probes as much as the limit allows.

    Parameters
    ----------
    limit : float
        ``A_vl`` (m peak to peak), :func:`vibration_limit`.
    max_amplitude : float
        ``A_max``: the largest peak-to-peak amplitude at the probes within
        the operating range (m).
    limits : (float, float) or None
        Bounds of ``S_cc`` (default 0.5 and 6); None: not clipped.

    Examples
    --------
    >>> clearance_scale_factor(25.4e-6, 12.7e-6)
    2.0
    >>> clearance_scale_factor(25.4e-6, 1e-6)     # 25.4, clipped to 6
    6.0
    """
    a_vl, a_max = float(limit), float(max_amplitude)
    if not (math.isfinite(a_vl) and a_vl > 0):
        raise ParameterError(f"limit={limit!r} is invalid: expected A_vl > 0 (m peak to peak)")
    if not (math.isfinite(a_max) and a_max > 0):
        raise ParameterError(f"max_amplitude={max_amplitude!r} is invalid: expected the probes' largest "
                             "amplitude in the operating range, > 0 (m peak to peak)")
    scc = a_vl / a_max
    if limits is not None:
        lo, hi = (float(v) for v in limits)
        if not 0 < lo <= hi:
            raise ParameterError(f"limits={limits!r} is invalid: expected (low, high) with 0 < low <= high")
        scc = min(max(scc, lo), hi)
    return scc


def separation_margin(critical_speed, operating_range):
    """``(margin percent, above)`` of a critical speed from the operating range ``(N_min, N_mc)``.

    Below: ``100 (N_min - N_c) / N_min``; above: ``100 (N_c - N_mc) / N_mc``;
    inside the range the margin is negative (minus the smaller distance, in
    percent of the nearer end) and ``above`` says which end is nearer.
    """
    from ..units import to_si

    nc = to_si(critical_speed, "rad/s", "critical_speed")
    low, high = operating_bounds(operating_range)
    if nc <= low:
        return 100.0 * (low - nc) / low, False
    if nc >= high:
        return 100.0 * (nc - high) / high, True
    below, over = 100.0 * (nc - low) / low, 100.0 * (high - nc) / high
    return (-below, False) if below <= over else (-over, True)


def operating_bounds(operating_range):
    """``(low, high)`` of an operating speed range (rad/s) from two speeds (floats, pint or strings)."""
    from ..units import to_si_array

    try:
        bounds = to_si_array(operating_range, "rad/s", "operating_range").reshape(-1)
    except ParameterError:
        raise
    except (TypeError, ValueError):  # not a pair of numbers or quantities
        bounds = np.array([])
    if bounds.size != 2 or not np.all(np.isfinite(bounds)) or not 0 < bounds[0] <= bounds[1]:
        raise ParameterError(f"operating_range={operating_range!r} is invalid: expected (minimum operating speed, "
                             "maximum continuous speed) with 0 < minimum <= maximum (rad/s or e.g. "
                             "('8000 rpm', '10500 rpm'))")
    return float(bounds[0]), float(bounds[1])


def wachel_cross_coupling(power, impeller_diameter, restrictive_width, speed, density_ratio=1.0, *,
                          stage_factor=3.0):
    """Anticipated aerodynamic cross-coupling ``q_A`` (N/m) of each impeller, and ``Q_A`` their sum (Wachel).

    ``q_A = B_c C P / (D_c H_c N) (rho_d / rho_s)`` (API 617 8th ed., 4.8,
    Level I stability; API 684): ``P`` the rated power of the impeller, ``D_c`` its
    diameter, ``H_c`` the smaller of the diffuser and the impeller discharge
    widths, ``N`` the speed, ``rho_d / rho_s`` the discharge to suction gas
    density ratio across it and ``B_c = 3`` for centrifugal impellers
    (``B_t = 1.5`` with ``rho_d / rho_s = 1`` for axial stages and
    turbines). ``C`` turns ``P / N`` into a torque: ``C = 60 / (2 pi) = 9.55``
    with ``N`` in rpm and SI base units (the value printed in the standard;
    63 with hp, in and klbf/in). Here ``N`` is an angular speed and the
    formula is evaluated as ``B_c P / (D_c H_c Omega) (rho_d / rho_s)``.

    Parameters
    ----------
    power : float, str, pint.Quantity or sequence of them
        Rated power per impeller (W).
    impeller_diameter, restrictive_width : float, str, pint.Quantity or sequence
        ``D_c`` and ``H_c`` per impeller (m).
    speed : float, str or pint.Quantity
        Operating speed (rad/s or e.g. ``"10000 rpm"``).
    density_ratio : float or sequence
        ``rho_d / rho_s`` per impeller (>= 1 for a compressor stage).
    stage_factor : float
        ``B_c`` (3 for centrifugal compressors; 1.5 for axial or turbine stages).

    Returns
    -------
    (numpy.ndarray, float)
        ``q_A`` per impeller (N/m) and ``Q_A`` (N/m).

    Examples
    --------
    >>> q, Q = wachel_cross_coupling("1 MW", "400 mm", "20 mm", "10000 rpm", 1.2)
    >>> round(Q)    # 3 x 1e6 W / (0.4 m x 0.02 m x 1047.2 rad/s) x 1.2
    429718
    """
    from ..units import to_si

    def per_impeller(value, unit, name):
        values = value if isinstance(value, (list, tuple, np.ndarray)) else [value]
        return np.array([_positive(v, unit, f"{name}[{i}]") for i, v in enumerate(values)], dtype=float)

    p = per_impeller(power, "W", "power")
    d = per_impeller(impeller_diameter, "m", "impeller_diameter")
    h = per_impeller(restrictive_width, "m", "restrictive_width")
    ratio = per_impeller(density_ratio, "", "density_ratio")
    sizes = {p.size, d.size, h.size, ratio.size} - {1}
    if len(sizes) > 1:
        raise ParameterError(f"power, impeller_diameter, restrictive_width and density_ratio give {p.size}, "
                             f"{d.size}, {h.size} and {ratio.size} impellers: expected one value each, or lists "
                             "of one length")
    omega = _positive(speed, "rad/s", "speed")
    b = float(to_si(stage_factor, "", "stage_factor"))
    if not (math.isfinite(b) and b > 0):
        raise ParameterError(f"stage_factor={stage_factor!r} is invalid: expected B_c > 0 (3 centrifugal, 1.5 axial)")
    q = b * p / (d * h * omega) * ratio
    return q, float(q.sum())
