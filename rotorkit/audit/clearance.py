"""API 617 amplitude checks of an unbalance response: the probes' limit ``A_vl`` and the close clearances.

With the unbalance of a mode applied (:mod:`rotorkit.audit.placement`), API
617 (8th ed. 4.8.2.10 and 4.8.2.11; 9th ed. 6.8.2.10 and 6.8.2.11) asks:

- the peak-to-peak amplitude at the vibration probes, within the operating
  range, against ``A_vl = 25.4 sqrt(12000 / N_mc)`` um (at most 25.4 um);
- at every close clearance (seals, bearings), from zero to the trip speed,
  the peak-to-peak amplitude scaled by ``S_cc = A_vl / A_max`` (``A_max``
  the probes' largest amplitude in the operating range; ``S_cc`` held
  within 0.5 and 6) against 75 % of the minimum design diametral running
  clearance.

Amplitudes are taken on the orbit's major axis (``2 (|F| + |B|)`` peak to
peak, from the forward and backward circular components): the largest a
probe of any orientation at that station reads.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError

__all__ = ["ClearanceCheck", "AmplitudeCheck", "amplitude_check", "close_clearances_si", "probe_stations"]


@dataclass(frozen=True, slots=True)
class ClearanceCheck:
    """One close clearance under the scaled unbalance response.

    Attributes
    ----------
    station : str
    clearance : float
        Minimum design diametral running clearance (m).
    limit : float
        75 % of it (m).
    amplitude : float
        Largest scaled peak-to-peak amplitude from zero to the trip speed (m).
    speed : float
        Where it is largest (rad/s).
    """

    station: str
    clearance: float
    limit: float
    amplitude: float
    speed: float

    @property
    def passed(self):
        """The scaled amplitude below 75 % of the clearance."""
        return self.amplitude < self.limit


@dataclass(frozen=True, slots=True)
class AmplitudeCheck:
    """The amplitude checks of one mode's unbalance response.

    Attributes
    ----------
    vibration_limit : float
        ``A_vl`` (m peak to peak).
    probes : tuple of str
        Probe stations.
    max_amplitude : float
        ``A_max``: the largest peak-to-peak amplitude at the probes within
        the operating range (m).
    probe : str
        The probe where it is.
    speed : float
        Where it is (rad/s).
    scale_factor : float
        ``S_cc`` applied to the close clearances.
    clearances : tuple of ClearanceCheck
    """

    vibration_limit: float
    probes: tuple
    max_amplitude: float
    probe: str
    speed: float
    scale_factor: float
    clearances: tuple

    @property
    def probes_passed(self):
        """``A_max`` below ``A_vl``."""
        return self.max_amplitude < self.vibration_limit

    @property
    def passed(self):
        """The probes' limit and every close clearance met."""
        return self.probes_passed and all(c.passed for c in self.clearances)


def probe_stations(probes, stations):
    """Probe stations (str) checked against the model's ``stations``."""
    probes = [probes] if isinstance(probes, (str, int)) else list(probes)
    names = [str(p) for p in probes]
    unknown = [p for p in names if p not in stations]
    if not names or unknown:
        raise ParameterError(f"probes={probes!r}: station(s) {unknown} unknown; expected one or more stations "
                             f"among {list(stations)}")
    return tuple(dict.fromkeys(names))


def close_clearances_si(close_clearances, stations):
    """``{station: diametral clearance m}`` checked: known stations, clearances positive and finite."""
    from ..units import to_si

    if not isinstance(close_clearances, dict) or not close_clearances:
        raise ParameterError(f"close_clearances={close_clearances!r} is invalid: expected a dict station -> minimum "
                             "diametral running clearance (m, or e.g. '0.4 mm')")
    out = {}
    for station, value in close_clearances.items():
        name = str(station)
        if name not in stations:
            raise ParameterError(f"close_clearances: station {station!r} unknown; expected one among "
                                 f"{list(stations)}")
        c = to_si(value, "m", f"close_clearances[{station!r}]")
        if not (math.isfinite(c) and c > 0):
            raise ParameterError(f"close_clearances[{station!r}]={value!r} is invalid: expected a positive "
                                 "diametral running clearance (m)")
        out[name] = c
    return out


def amplitude_check(speeds, amplitudes, probes, operating, trip_speed, max_continuous_speed, close_clearances=None,
                    *, scale_factor_limits=(0.5, 6.0)):
    """The API 617 amplitude checks of one unbalance response.

    Parameters
    ----------
    speeds : array_like, shape (n,)
        Increasing speeds of the response (rad/s); they should include the
        two ends of the operating range.
    amplitudes : dict
        Station -> peak-to-peak amplitude (m) at each speed, shape (n,).
    probes : sequence of str
        Probe stations (keys of ``amplitudes``).
    operating : (float, float)
        Minimum operating and maximum continuous speeds (rad/s).
    trip_speed : float
        The close clearances are checked from zero to it (rad/s).
    max_continuous_speed : float
        ``N_mc`` of ``A_vl`` (rad/s).
    close_clearances : dict, optional
        Station -> minimum diametral running clearance (m).
    scale_factor_limits : (float, float) or None
        Bounds of ``S_cc``.

    Returns
    -------
    AmplitudeCheck
    """
    from .formulas import CLEARANCE_FRACTION, clearance_scale_factor, vibration_limit

    w = np.asarray(speeds, dtype=float)
    low, high = operating
    band = (w >= low * (1 - 1e-12)) & (w <= high * (1 + 1e-12))
    if not np.any(band):
        raise ParameterError(f"amplitude_check: no speed of the response ({w[0]:g} to {w[-1]:g} rad/s) lies in the "
                             f"operating range ({low:g}, {high:g}) rad/s")
    a_vl = vibration_limit(max_continuous_speed)
    peaks = {p: float(np.max(np.asarray(amplitudes[p])[band])) for p in probes}
    probe = max(probes, key=lambda p: peaks[p])
    a_max = peaks[probe]
    at = float(w[band][int(np.argmax(np.asarray(amplitudes[probe])[band]))])
    scc = clearance_scale_factor(a_vl, a_max, scale_factor_limits) if a_max > 0 else (
        scale_factor_limits[1] if scale_factor_limits is not None else math.inf)
    checks = []
    upto = w <= trip_speed * (1 + 1e-12)
    for station, c in (close_clearances or {}).items():
        a = scc * np.asarray(amplitudes[station])[upto]
        k = int(np.argmax(a))
        checks.append(ClearanceCheck(station=station, clearance=c, limit=CLEARANCE_FRACTION * c, amplitude=float(a[k]),
                                     speed=float(w[upto][k])))
    return AmplitudeCheck(vibration_limit=a_vl, probes=tuple(probes), max_amplitude=a_max, probe=probe, speed=at,
                          scale_factor=scc, clearances=tuple(checks))
