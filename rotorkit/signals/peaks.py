"""Peaks of an amplitude spectrum: tones between bins corrected for the taper's scalloping loss."""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .sampling import check_units, convert, positive_float, taper_weights
from .spectra import Spectrum

__all__ = [
    "Peak",
    "find_peaks",
    "amplitude_at",
]


@dataclass(frozen=True, slots=True)
class Peak:
    """A spectral peak.

    Attributes
    ----------
    frequency : float
        Interpolated peak frequency, in ``units``.
    amplitude : float
        Interpolated peak amplitude (same unit as the signal).
    units : str
        Units of ``frequency``: ``"rad/s"`` or ``"Hz"``.
    """

    frequency: float
    amplitude: float
    units: str = "rad/s"


def _kernel(weights, n_fft):
    """Normalised taper response ``|W(delta)| / W(0)``, ``delta`` in FFT bins."""
    phase = -2.0j * math.pi * np.arange(weights.size) / n_fft
    total = weights.sum()

    def response(delta):
        return abs(np.dot(weights, np.exp(phase * delta))) / total

    return response


def _offset_from_kernel(response, alpha, beta):
    """Offset (bins, in [0, 0.5]) of a tone from its peak bin given the two largest bins."""
    from scipy.optimize import brentq

    def mismatch(delta):
        return response(delta) * beta - response(1.0 - delta) * alpha

    if mismatch(0.0) <= 0.0:
        return 0.0
    if mismatch(0.5) >= 0.0:
        return 0.5
    return brentq(mismatch, 0.0, 0.5, xtol=1e-10)


def _interpolate_with_taper(amplitude, k, response):
    """Tone frequency offset (signed bins) and amplitude at peak bin ``k``."""
    left, right = amplitude[k - 1], amplitude[k + 1]
    side = 1 if right >= left else -1
    alpha, beta = amplitude[k], max(left, right)
    delta = _offset_from_kernel(response, alpha, beta)
    return side * delta, alpha / response(delta)


def _interpolate_log_parabola(amplitude, k):
    """Offset (signed bins) and amplitude from a parabola through log amplitudes."""
    tiny = np.finfo(float).tiny
    y_l, y_0, y_r = np.log(np.maximum(amplitude[k - 1 : k + 2], tiny))
    curvature = y_l - 2.0 * y_0 + y_r
    if curvature >= 0.0:
        return 0.0, float(amplitude[k])
    offset = 0.5 * (y_l - y_r) / curvature
    return offset, float(np.exp(y_0 - 0.25 * (y_l - y_r) * offset))


def find_peaks(spectrum, min_relative_height=0.01, max_peaks=20, min_snr=None):
    """Find the peaks of an amplitude spectrum, interpolated between bins.

    Parameters
    ----------
    spectrum : Spectrum
        From :func:`amplitude_spectrum`.
    min_relative_height : float, optional
        Keep peaks whose bin amplitude is at least this fraction of the
        largest amplitude of the spectrum (default 0.01).
    max_peaks : int, optional
        Keep at most this many peaks, the highest ones (default 20).
    min_snr : float or None, optional
        Also require a bin amplitude of at least ``min_snr`` times the median
        amplitude of the spectrum (a robust noise-floor estimate). With
        white noise only, ``min_snr=5`` leaves no peak. None (default): no
        such condition.

    Returns
    -------
    list of Peak
        Sorted by increasing frequency, in ``spectrum.units``.

    Notes
    -----
    When the spectrum knows its taper and lengths (as those of
    :func:`amplitude_spectrum` do), the frequency and amplitude of an isolated
    tone are recovered exactly from the peak bin and its larger neighbour
    with the taper's own frequency response (no scalloping loss). Otherwise a
    parabola through the log amplitudes of the three top bins is used (bias
    a few % in amplitude, a few hundredths of a bin in frequency for Hann).

    Zero-padded spectra show the taper's sidelobes as local maxima (Hann:
    -31.5 dB, i.e. 0.027 of the main peak); raise ``min_relative_height``
    above that level to skip them.

    Raises
    ------
    ParameterError
        (a ``ValueError``) for bad thresholds or ``max_peaks``.
    """
    from scipy.signal import find_peaks as scipy_find_peaks

    if not isinstance(spectrum, Spectrum):
        raise ParameterError(f"spectrum={type(spectrum).__name__} is invalid: expected a Spectrum")
    ok = isinstance(min_relative_height, numbers.Real) and not isinstance(min_relative_height, bool)
    if not ok or not 0.0 <= min_relative_height <= 1.0:
        raise ParameterError(
            f"min_relative_height={min_relative_height!r} is invalid: expected a fraction from 0 to 1"
        )
    if isinstance(max_peaks, bool) or not isinstance(max_peaks, numbers.Integral) or max_peaks < 1:
        raise ParameterError(f"max_peaks={max_peaks!r} is invalid: expected an integer >= 1")
    if min_snr is not None:
        min_snr = positive_float(min_snr, "min_snr")

    amplitude = np.asarray(spectrum.amplitude, dtype=float)
    frequency = np.asarray(spectrum.frequency, dtype=float)
    if amplitude.size < 3 or not np.any(amplitude > 0):
        return []
    threshold = min_relative_height * amplitude.max()
    if min_snr is not None:
        threshold = max(threshold, min_snr * float(np.median(amplitude)))
    indices, _ = scipy_find_peaks(amplitude, height=threshold if threshold > 0 else None)
    indices = sorted(indices, key=lambda i: amplitude[i], reverse=True)[: int(max_peaks)]

    response = None
    if spectrum.taper is not None and spectrum.n_samples and spectrum.n_fft:
        _, weights = taper_weights(spectrum.taper, spectrum.n_samples)
        response = _kernel(weights, spectrum.n_fft)
    bin_width = float(frequency[1] - frequency[0])
    peaks = []
    for k in sorted(indices):
        if response is not None:
            offset, peak_amplitude = _interpolate_with_taper(amplitude, k, response)
        else:
            offset, peak_amplitude = _interpolate_log_parabola(amplitude, k)
        peaks.append(Peak(float(frequency[k] + offset * bin_width), float(peak_amplitude), spectrum.units))
    return peaks


def amplitude_at(spectrum, frequency, rel_band=0.02, units=None):
    """Largest spectrum amplitude within a relative band around a frequency.

    Parameters
    ----------
    spectrum : Spectrum
        From :func:`amplitude_spectrum`.
    frequency : float
        Centre frequency (> 0), in ``units``.
    rel_band : float, optional
        Half-width of the band relative to ``frequency`` (default 0.02): the
        band is ``frequency * (1 - rel_band)`` to ``frequency * (1 + rel_band)``.
        If no bin falls in the band, the nearest bin is used.
    units : {"rad/s", "Hz"} or None, optional
        Units of ``frequency``; None (default) for ``spectrum.units``.

    Returns
    -------
    float
        The maximum bin amplitude in the band (same unit as the signal).
        Not corrected for scalloping: a tone between bins may read up to
        15 % (Hann) low; use :func:`find_peaks` for exact amplitudes.

    Raises
    ------
    ParameterError
        (a ``ValueError``) for a bad frequency, band or units, or a band
        outside the spectrum's frequency range.
    """
    if not isinstance(spectrum, Spectrum):
        raise ParameterError(f"spectrum={type(spectrum).__name__} is invalid: expected a Spectrum")
    units = spectrum.units if units is None else check_units(units)
    frequency = convert(positive_float(frequency, "frequency", units), units, spectrum.units)
    rel_band = positive_float(rel_band, "rel_band")
    if rel_band >= 1.0:
        raise ParameterError(f"rel_band={rel_band!r} is invalid: expected a fraction 0 < rel_band < 1")
    grid = np.asarray(spectrum.frequency, dtype=float)
    low, high = frequency * (1.0 - rel_band), frequency * (1.0 + rel_band)
    if low > grid[-1]:
        raise ParameterError(
            f"frequency={frequency!r} {spectrum.units} is outside the spectrum: expected a band "
            f"below the Nyquist frequency {grid[-1]:.6g} {spectrum.units}"
        )
    in_band = (grid >= low) & (grid <= high)
    if not np.any(in_band):
        return float(spectrum.amplitude[int(np.argmin(np.abs(grid - frequency)))])
    return float(np.max(np.asarray(spectrum.amplitude)[in_band]))
