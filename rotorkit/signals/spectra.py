"""Signal analysis of rotor vibration signals.

Everything works on plain numpy arrays: a uniformly sampled signal ``x``
(1-D) and its sample times ``t`` (1-D, s). Functions that return frequencies
take ``units="rad/s"`` (default, the convention of rotordynamics, where
frequencies are read as orders of the rotor speeds) or ``units="Hz"``.

Typical use::

    xf = highpass(t, x, cutoff=5.0)                  # drop the manoeuvre offset
    spec = amplitude_spectrum(t, xf, window=(2.2, 3.8))
    peaks = find_peaks(spec, min_relative_height=0.02)
    labels = label_orders(peaks, {"low": 1500.0, "high": 2700.0},
                          natural_frequencies={"omega_b": 336.0})

Amplitude normalisation: a sine ``A sin(w t)`` whose frequency falls on a bin
shows a peak of exactly ``A`` whatever the taper (the taper's coherent gain is
divided out); :func:`find_peaks` also corrects the scalloping loss of tones
between bins.

Bad input raises :class:`rotorkit.errors.ParameterError`, a ``ValueError``.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from ..errors import ParameterError

__all__ = [
    "DEFAULT_RATIOS",
    "FREQUENCY_UNITS",
    "Spectrum",
    "TimeFrequency",
    "Peak",
    "OrderLabel",
    "highpass",
    "amplitude_spectrum",
    "stft",
    "find_peaks",
    "label_orders",
    "amplitude_at",
]

#: Orders of each rotor speed tried by :func:`label_orders`.
DEFAULT_RATIOS = tuple(
    Fraction(r)
    for r in ("1/4", "1/3", "1/2", "2/3", "3/4", "1", "5/4", "4/3", "3/2", "5/3", "7/4", "2", "5/2", "3")
)

#: Frequency units accepted by the ``units`` arguments.
FREQUENCY_UNITS = ("rad/s", "Hz")

# Relative tolerance on the spread of the time steps of a "uniform" time vector.
_UNIFORM_RTOL = 1e-5
# Two candidate lines whose relative errors differ by less than this are "equally close".
_TIE_RTOL = 1e-9
# Fewest samples accepted in a spectrum window or an STFT segment.
_MIN_SAMPLES = 8


# ---------------------------------------------------------------------------
# Result types
# ---------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, eq=False)
class Spectrum:
    """Single-sided amplitude spectrum.

    Attributes
    ----------
    frequency : numpy.ndarray, shape (n_freq,)
        Bin frequencies, in ``units``, from 0 to the Nyquist frequency.
    amplitude : numpy.ndarray, shape (n_freq,)
        Amplitude (same unit as the signal): a sine of amplitude ``A`` at a
        bin frequency shows ``A``.
    units : str
        ``"rad/s"`` or ``"Hz"``.
    taper : str, tuple or None
        The taper (scipy window name) applied, or None if unknown. Used by
        :func:`find_peaks` for exact between-bin interpolation.
    n_samples : int or None
        Number of signal samples analysed (before zero padding), or None.
    n_fft : int or None
        FFT length (``>= n_samples`` with zero padding), or None.

    Notes
    -----
    The arrays are read-only. ``eq=False``: spectra compare by identity.
    """

    frequency: np.ndarray
    amplitude: np.ndarray
    units: str = "rad/s"
    taper: str | tuple | None = None
    n_samples: int | None = None
    n_fft: int | None = None

    @property
    def resolution(self):
        """Frequency resolution (float, in ``units``): sampling rate / ``n_samples``.

        Without ``n_samples`` this is the bin spacing.
        """
        spacing = float(self.frequency[1] - self.frequency[0])
        if self.n_samples is None or self.n_fft is None:
            return spacing
        return spacing * self.n_fft / self.n_samples


@dataclass(frozen=True, slots=True, eq=False)
class TimeFrequency:
    """Short-time amplitude spectra (spectrogram of amplitudes).

    Attributes
    ----------
    time : numpy.ndarray, shape (n_time,)
        Centre time of each segment (s).
    frequency : numpy.ndarray, shape (n_freq,)
        Bin frequencies, in ``units``.
    amplitude : numpy.ndarray, shape (n_freq, n_time)
        Amplitude spectrum of each segment, normalised as in :class:`Spectrum`.
    units : str
        ``"rad/s"`` or ``"Hz"``.
    """

    time: np.ndarray
    frequency: np.ndarray
    amplitude: np.ndarray
    units: str = "rad/s"


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


# ---------------------------------------------------------------------------
# Validation helpers
# ---------------------------------------------------------------------------


def _check_units(units, name="units"):
    if not isinstance(units, str) or units not in FREQUENCY_UNITS:
        raise ParameterError(f"{name}={units!r} is not supported: expected one of {FREQUENCY_UNITS}")
    return units


def _hz_to(values_hz, units):
    """Convert frequencies in Hz to ``units``."""
    return values_hz * (2.0 * math.pi) if units == "rad/s" else values_hz


def _convert(value, from_units, to_units):
    """Convert a frequency between ``"rad/s"`` and ``"Hz"``."""
    if from_units == to_units:
        return value
    return value * (2.0 * math.pi) if to_units == "rad/s" else value / (2.0 * math.pi)


def _positive_float(value, name, unit=""):
    ok = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if not ok or not math.isfinite(value) or value <= 0:
        shown = f" ({unit})" if unit else ""
        raise ParameterError(f"{name}={value!r} is invalid: expected a finite number > 0{shown}")
    return float(value)


def _as_signal(t, x):
    """Check ``t``, ``x`` and return them as float arrays with the time step (s)."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise ParameterError(f"t has shape {t.shape}: expected a 1-D array of at least 2 sample times (s)")
    if x.shape != t.shape:
        raise ParameterError(f"x has shape {x.shape}: expected a 1-D array of the same shape as t {t.shape}")
    if not np.all(np.isfinite(t)):
        raise ParameterError("t contains NaN or inf: expected finite sample times (s)")
    if not np.all(np.isfinite(x)):
        raise ParameterError("x contains NaN or inf: expected finite samples")
    return t, x, _time_step(t)


def _time_step(t):
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0))
        raise ParameterError(
            f"t is not strictly increasing (t[{i}]={t[i]!r}, t[{i + 1}]={t[i + 1]!r}): "
            "expected uniformly sampled, increasing times (s)"
        )
    dt = (t[-1] - t[0]) / (t.size - 1)
    spread = float(np.max(np.abs(steps - dt)) / dt)
    if spread > _UNIFORM_RTOL:
        raise ParameterError(
            f"t is not uniformly sampled: time steps range from {steps.min():.6g} to "
            f"{steps.max():.6g} s (relative spread {spread:.3g}); expected a constant step "
            f"(relative tolerance {_UNIFORM_RTOL:g}); resample the signal first"
        )
    return float(dt)


def _select_window(t, x, dt, window):
    """Return the samples of ``x`` with ``t`` in ``window`` (whole signal if None)."""
    if window is None:
        return x
    try:
        t_start, t_end = (float(v) for v in window)
    except (TypeError, ValueError) as exc:
        raise ParameterError(f"window={window!r} is invalid: expected (t_start, t_end) in s or None") from exc
    slack = 0.5 * dt
    if not (t_start < t_end):
        raise ParameterError(f"window={window!r} is invalid: expected t_start < t_end (s)")
    if t_start < t[0] - slack or t_end > t[-1] + slack:
        raise ParameterError(
            f"window={window!r} is outside the signal: expected t_start >= {t[0]:.6g} s "
            f"and t_end <= {t[-1]:.6g} s"
        )
    mask = (t >= t_start - 1e-9 * dt) & (t <= t_end + 1e-9 * dt)
    n = int(np.count_nonzero(mask))
    if n < _MIN_SAMPLES:
        raise ParameterError(
            f"window={window!r} holds {n} samples: expected at least {_MIN_SAMPLES} "
            f"(time step {dt:.6g} s)"
        )
    return x[mask]


def _taper_weights(taper, n):
    """The taper of length ``n`` (periodic form); None or "boxcar" means none."""
    from scipy.signal import get_window

    if taper is None:
        taper = "boxcar"
    try:
        w = get_window(taper, n, fftbins=True)
    except (ValueError, TypeError) as exc:
        raise ParameterError(
            f"taper={taper!r} is not a known window: expected a scipy.signal.get_window "
            "name such as 'hann', 'hamming', 'blackmanharris', 'flattop' or 'boxcar', or None"
        ) from exc
    return taper, np.asarray(w, dtype=float)


def _readonly(array):
    array = np.ascontiguousarray(array)
    array.setflags(write=False)
    return array


# ---------------------------------------------------------------------------
# Filtering and spectra
# ---------------------------------------------------------------------------


def highpass(t, x, cutoff, order=4):
    """Zero-phase Butterworth high-pass filter.

    The filter is applied forward and backward (``sosfiltfilt``), so it has
    no phase shift (no time delay) and its magnitude response is the square
    of the Butterworth one (-6 dB at ``cutoff``). Used to remove the slow
    (about 0.5-5 Hz) manoeuvre offset from vibration signals.

    Parameters
    ----------
    t : array_like, shape (n,)
        Uniformly spaced sample times (s).
    x : array_like, shape (n,)
        Signal samples.
    cutoff : float
        Cut-off frequency, in **Hz**, ``0 < cutoff < 1 / (2 dt)``.
    order : int, optional
        Butterworth order of one pass (default 4).

    Returns
    -------
    numpy.ndarray, shape (n,)
        The filtered signal.

    Raises
    ------
    ParameterError
        (a ``ValueError``) for non-uniform ``t``, mismatched shapes, a cut-off
        outside ``(0, Nyquist)`` or a bad order.

    Notes
    -----
    The signal is extended at both ends by an odd reflection of about three
    periods of the cut-off frequency (at most the whole signal) to limit the
    start and end transients.
    """
    from scipy.signal import butter, sosfiltfilt

    t, x, dt = _as_signal(t, x)
    cutoff = _positive_float(cutoff, "cutoff", "Hz")
    nyquist = 0.5 / dt
    if cutoff >= nyquist:
        raise ParameterError(
            f"cutoff={cutoff!r} Hz is at or above the Nyquist frequency {nyquist:.6g} Hz: "
            "expected 0 < cutoff < Nyquist"
        )
    if isinstance(order, bool) or not isinstance(order, numbers.Integral) or not 1 <= order <= 20:
        raise ParameterError(f"order={order!r} is invalid: expected an integer from 1 to 20")
    sos = butter(int(order), cutoff, btype="highpass", fs=1.0 / dt, output="sos")
    padlen = min(x.size - 1, int(math.ceil(3.0 / (cutoff * dt))))
    return sosfiltfilt(sos, x, padlen=padlen)


def _rfft_amplitude(segments, weights, n_fft):
    """Single-sided amplitude of tapered, mean-removed segments (last axis)."""
    centred = segments - segments.mean(axis=-1, keepdims=True)
    spectrum = np.abs(np.fft.rfft(centred * weights, n=n_fft, axis=-1))
    spectrum *= 2.0 / weights.sum()
    spectrum[..., 0] *= 0.5
    if n_fft % 2 == 0:
        spectrum[..., -1] *= 0.5
    return spectrum


def amplitude_spectrum(t, x, window=None, taper="hann", units="rad/s", pad_to=None):
    """Single-sided amplitude spectrum of a signal or of a time window of it.

    Parameters
    ----------
    t : array_like, shape (n,)
        Uniformly spaced sample times (s).
    x : array_like, shape (n,)
        Signal samples.
    window : (float, float) or None, optional
        ``(t_start, t_end)`` in s: analyse only the samples with
        ``t_start <= t <= t_end``; None (default) for the whole signal.
    taper : str, tuple or None, optional
        A ``scipy.signal.get_window`` window (default ``"hann"``); None or
        ``"boxcar"`` for none.
    units : {"rad/s", "Hz"}, optional
        Units of the returned frequencies.
    pad_to : int or None, optional
        Zero-pad the analysed samples to this FFT length (>= their number)
        for a finer frequency grid; the resolution does not improve.

    Returns
    -------
    Spectrum
        ``frequency`` shape (n_fft // 2 + 1,) in ``units``; ``amplitude`` of
        the same shape. The mean is removed first; the amplitude is
        ``2 |X_k| / sum(w)`` (``|X_k| / sum(w)`` at DC and Nyquist), so a sine
        of amplitude ``A`` on a bin reads ``A`` for every taper.

    Raises
    ------
    ParameterError
        (a ``ValueError``) for non-uniform ``t``, a window outside the
        signal, unknown ``units`` or ``taper``, or a too small ``pad_to``.
    """
    units = _check_units(units)
    t, x, dt = _as_signal(t, x)
    segment = _select_window(t, x, dt, window)
    n = segment.size
    if pad_to is None:
        n_fft = n
    elif isinstance(pad_to, bool) or not isinstance(pad_to, numbers.Integral) or pad_to < n:
        raise ParameterError(f"pad_to={pad_to!r} is invalid: expected None or an integer >= {n} (samples analysed)")
    else:
        n_fft = int(pad_to)
    taper, weights = _taper_weights(taper, n)
    amplitude = _rfft_amplitude(segment, weights, n_fft)
    frequency = _hz_to(np.fft.rfftfreq(n_fft, dt), units)
    return Spectrum(_readonly(frequency), _readonly(amplitude), units, taper, n, n_fft)


def stft(t, x, segment=0.1, overlap=0.5, taper="hann", units="rad/s"):
    """Short-time amplitude spectra (a time-frequency map).

    Parameters
    ----------
    t : array_like, shape (n,)
        Uniformly spaced sample times (s).
    x : array_like, shape (n,)
        Signal samples.
    segment : float, optional
        Segment duration (s), default 0.1; the frequency resolution is about
        ``1 / segment`` Hz.
    overlap : float, optional
        Overlap of consecutive segments as a fraction of ``segment``,
        ``0 <= overlap < 1`` (default 0.5).
    taper : str, tuple or None, optional
        ``scipy.signal.get_window`` window applied to each segment.
    units : {"rad/s", "Hz"}, optional
        Units of the returned frequencies.

    Returns
    -------
    TimeFrequency
        ``time`` shape (n_time,): segment centres (s); ``frequency`` shape
        (n_freq,) in ``units``; ``amplitude`` shape (n_freq, n_time),
        normalised as in :func:`amplitude_spectrum` (mean of each segment
        removed). Samples after the last full segment are not analysed.

    Raises
    ------
    ParameterError
        (a ``ValueError``) for bad ``t``/``x``, a segment shorter than 8
        samples or longer than the signal, an overlap outside ``[0, 1)``,
        unknown ``units`` or ``taper``.
    """
    units = _check_units(units)
    t, x, dt = _as_signal(t, x)
    segment = _positive_float(segment, "segment", "s")
    n_seg = int(round(segment / dt))
    if n_seg < _MIN_SAMPLES or n_seg > x.size:
        raise ParameterError(
            f"segment={segment!r} s holds {n_seg} samples: expected from {_MIN_SAMPLES} "
            f"to {x.size} samples (signal duration {t[-1] - t[0]:.6g} s)"
        )
    ok = isinstance(overlap, numbers.Real) and not isinstance(overlap, bool)
    if not ok or not 0.0 <= overlap < 1.0:
        raise ParameterError(f"overlap={overlap!r} is invalid: expected a fraction 0 <= overlap < 1")
    hop = max(1, int(round(n_seg * (1.0 - overlap))))
    _, weights = _taper_weights(taper, n_seg)
    frames = np.lib.stride_tricks.sliding_window_view(x, n_seg)[::hop]
    amplitude = _rfft_amplitude(frames, weights, n_seg).T
    starts = np.arange(frames.shape[0]) * hop
    time = t[starts] + 0.5 * (n_seg - 1) * dt
    frequency = _hz_to(np.fft.rfftfreq(n_seg, dt), units)
    return TimeFrequency(_readonly(time), _readonly(frequency), _readonly(amplitude), units)


# ---------------------------------------------------------------------------
# Peaks
# ---------------------------------------------------------------------------


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
        min_snr = _positive_float(min_snr, "min_snr")

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
        _, weights = _taper_weights(spectrum.taper, spectrum.n_samples)
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
    units = spectrum.units if units is None else _check_units(units)
    frequency = _convert(_positive_float(frequency, "frequency", units), units, spectrum.units)
    rel_band = _positive_float(rel_band, "rel_band")
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


# ---------------------------------------------------------------------------
# Order labelling
# ---------------------------------------------------------------------------


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
        checked[key] = _positive_float(value, f"{name}[{key!r}]", units)
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
            values.append(_convert(float(item.frequency), _check_units(item.units, "Peak.units"), units))
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
    units = _check_units(units)
    speeds = _check_named(speeds, "speeds", units)
    if not speeds:
        raise ParameterError("speeds={} is empty: expected at least one named rotor speed")
    natural_frequencies = _check_named(natural_frequencies, "natural_frequencies", units)
    tolerance = _positive_float(tolerance, "tolerance")
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
