"""Amplitude spectra and short-time spectra of a sampled signal.

Amplitude normalisation: a sine ``A sin(w t)`` whose frequency falls on a bin
shows a peak of exactly ``A`` whatever the taper (the taper's coherent gain is
divided out).
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .sampling import (
    MIN_SAMPLES,
    as_signal,
    check_units,
    hz_to,
    positive_float,
    readonly,
    select_window,
    taper_weights,
)

__all__ = [
    "Spectrum",
    "TimeFrequency",
    "amplitude_spectrum",
    "stft",
    "rfft_amplitude",
]


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


def rfft_amplitude(segments, weights, n_fft):
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
    units = check_units(units)
    t, x, dt = as_signal(t, x)
    segment = select_window(t, x, dt, window)
    n = segment.size
    if pad_to is None:
        n_fft = n
    elif isinstance(pad_to, bool) or not isinstance(pad_to, numbers.Integral) or pad_to < n:
        raise ParameterError(f"pad_to={pad_to!r} is invalid: expected None or an integer >= {n} (samples analysed)")
    else:
        n_fft = int(pad_to)
    taper, weights = taper_weights(taper, n)
    amplitude = rfft_amplitude(segment, weights, n_fft)
    frequency = hz_to(np.fft.rfftfreq(n_fft, dt), units)
    return Spectrum(readonly(frequency), readonly(amplitude), units, taper, n, n_fft)


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
    units = check_units(units)
    t, x, dt = as_signal(t, x)
    segment = positive_float(segment, "segment", "s")
    n_seg = int(round(segment / dt))
    if n_seg < MIN_SAMPLES or n_seg > x.size:
        raise ParameterError(
            f"segment={segment!r} s holds {n_seg} samples: expected from {MIN_SAMPLES} "
            f"to {x.size} samples (signal duration {t[-1] - t[0]:.6g} s)"
        )
    ok = isinstance(overlap, numbers.Real) and not isinstance(overlap, bool)
    if not ok or not 0.0 <= overlap < 1.0:
        raise ParameterError(f"overlap={overlap!r} is invalid: expected a fraction 0 <= overlap < 1")
    hop = max(1, int(round(n_seg * (1.0 - overlap))))
    _, weights = taper_weights(taper, n_seg)
    frames = np.lib.stride_tricks.sliding_window_view(x, n_seg)[::hop]
    amplitude = rfft_amplitude(frames, weights, n_seg).T
    starts = np.arange(frames.shape[0]) * hop
    time = t[starts] + 0.5 * (n_seg - 1) * dt
    frequency = hz_to(np.fft.rfftfreq(n_seg, dt), units)
    return TimeFrequency(readonly(time), readonly(frequency), readonly(amplitude), units)
