"""Tests of rotorkit.analysis.signals on synthetic signals with known answers."""

import dataclasses
import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.signal import get_window

from rotorkit.analysis.signals import (
    OrderLabel,
    Peak,
    Spectrum,
    amplitude_at,
    amplitude_spectrum,
    find_peaks,
    highpass,
    label_orders,
    stft,
)

FS = 20_000.0  # Hz
DURATION = 1.6  # s
SPEEDS = {"low": 1500.0, "high": 2700.0}  # rad/s
# (frequency rad/s, amplitude, phase rad); 2700 rad/s lies 0.55 bin off the grid
TONES = [(750.0, 1.0, 0.3), (1500.0, 0.5, 1.1), (2700.0, 0.25, -0.8)]


def _time(duration=DURATION, fs=FS):
    return np.arange(int(round(duration * fs))) / fs


def _tones(t, tones=TONES):
    return sum(a * np.sin(w * t + phi) for w, a, phi in tones)


@pytest.fixture(scope="module")
def sines():
    t = _time()
    return t, _tones(t)


# --- sum of sines: peaks, amplitudes, labels -------------------------------


def test_sum_of_sines_peaks_have_right_frequency_and_amplitude(sines):
    t, x = sines
    spectrum = amplitude_spectrum(t, x)
    bin_width = 2 * math.pi / DURATION  # rad/s
    assert spectrum.units == "rad/s"
    assert spectrum.frequency[1] - spectrum.frequency[0] == pytest.approx(bin_width, rel=1e-12)

    peaks = find_peaks(spectrum, min_relative_height=0.05)
    assert len(peaks) == 3
    for peak, (w, a, _) in zip(peaks, TONES):
        assert abs(peak.frequency - w) < 0.01 * bin_width
        assert peak.amplitude == pytest.approx(a, rel=0.005)
        assert peak.units == "rad/s"


def test_off_bin_tone_needs_interpolation(sines):
    """The raw bins of the 2700 rad/s tone read low (scalloping); find_peaks corrects it."""
    t, x = sines
    spectrum = amplitude_spectrum(t, x)
    raw = amplitude_at(spectrum, 2700.0)
    assert 0.80 * 0.25 < raw < 0.92 * 0.25
    # a spectrum without taper information falls back to a log-parabola: coarser but close
    bare = Spectrum(spectrum.frequency, spectrum.amplitude, spectrum.units)
    peaks = find_peaks(bare, min_relative_height=0.05)
    bin_width = 2 * math.pi / DURATION
    assert [abs(p.frequency - w) < 0.05 * bin_width for p, (w, _, _) in zip(peaks, TONES)] == [True] * 3
    assert [p.amplitude / a for p, (_, a, _) in zip(peaks, TONES)] == pytest.approx([1, 1, 1], rel=0.05)


def test_sum_of_sines_labels(sines):
    t, x = sines
    peaks = find_peaks(amplitude_spectrum(t, x), min_relative_height=0.05)
    labels = label_orders(peaks, SPEEDS)
    assert [lab.label for lab in labels] == ["1/2 low", "low", "high"]
    assert [lab.ratio for lab in labels] == [Fraction(1, 2), Fraction(1), Fraction(1)]
    assert [lab.reference for lab in labels] == ["low", "low", "high"]
    assert all(abs(lab.error) < 1e-4 for lab in labels)


def test_hz_units_are_consistent(sines):
    t, x = sines
    rad = amplitude_spectrum(t, x)
    hz = amplitude_spectrum(t, x, units="Hz")
    assert hz.units == "Hz"
    np.testing.assert_allclose(hz.frequency * 2 * math.pi, rad.frequency, rtol=1e-12)
    np.testing.assert_array_equal(hz.amplitude, rad.amplitude)
    peaks_hz = find_peaks(hz, min_relative_height=0.05)
    assert [p.units for p in peaks_hz] == ["Hz"] * 3
    assert [p.frequency for p in peaks_hz] == pytest.approx([w / (2 * math.pi) for w, _, _ in TONES], rel=1e-6)
    # Hz peaks against rad/s speeds: the peaks are converted
    assert [lab.label for lab in label_orders(peaks_hz, SPEEDS)] == ["1/2 low", "low", "high"]
    # everything in Hz
    speeds_hz = {k: v / (2 * math.pi) for k, v in SPEEDS.items()}
    labels = label_orders([p.frequency for p in peaks_hz], speeds_hz, units="Hz")
    assert [lab.label for lab in labels] == ["1/2 low", "low", "high"]
    assert labels[0].frequency == pytest.approx(750 / (2 * math.pi), rel=1e-6)
    # amplitude_at in the other unit
    assert amplitude_at(rad, 1500 / (2 * math.pi), units="Hz") == amplitude_at(hz, 1500 / (2 * math.pi))


@pytest.mark.parametrize("taper", ["hann", None, "hamming", "flattop", ("kaiser", 8.0)])
@pytest.mark.parametrize("pad", [1, 3])
def test_bin_tone_amplitude_independent_of_taper(taper, pad):
    t = _time(0.5, 4000.0)
    x = 2.5 * np.sin(2 * math.pi * 100.0 * t + 0.4) + 7.0  # 100 Hz: bin 50; offset removed
    spectrum = amplitude_spectrum(t, x, taper=taper, units="Hz", pad_to=pad * t.size)
    k = int(np.argmin(np.abs(spectrum.frequency - 100.0)))
    assert spectrum.frequency[k] == pytest.approx(100.0, abs=1e-9)
    assert spectrum.amplitude[k] == pytest.approx(2.5, rel=1e-5)  # leakage of the image at -100 Hz
    assert np.max(spectrum.amplitude) == pytest.approx(2.5, rel=3e-4)  # flat-top ripple 2e-4
    assert spectrum.amplitude[0] < 1e-4  # the offset of 7 is removed (tone leakage ~1e-5)


# --- high-pass ---------------------------------------------------------------


def test_highpass_removes_slow_offset_and_keeps_200hz_phase():
    t = _time(2.0)
    slow = 50.0 * np.sin(2 * math.pi * 1.0 * t + 0.4)
    fast = 1.0 * np.sin(2 * math.pi * 200.0 * t + 0.7)
    y = highpass(t, slow + fast, cutoff=5.0)
    residual = y - fast
    interior = (t > 0.25) & (t < 1.75)
    # the 50-amplitude offset is attenuated > 2000 times away from the ends, > 50 times near them
    assert np.max(np.abs(residual[interior])) < 0.025
    assert np.max(np.abs(residual)) < 1.0
    # amplitude and phase of the 200 Hz component (least squares on the interior)
    basis = np.column_stack([np.sin(2 * math.pi * 200 * t[interior]), np.cos(2 * math.pi * 200 * t[interior])])
    s, c = np.linalg.lstsq(basis, y[interior], rcond=None)[0]
    assert math.hypot(s, c) == pytest.approx(1.0, rel=1e-3)
    assert math.atan2(c, s) == pytest.approx(0.7, abs=1e-3)  # rad: no time shift (< 1 us)
    # a causal (one-pass) filter would shift it: make sure the test can tell
    from scipy.signal import butter, sosfilt

    causal = sosfilt(butter(4, 5.0, btype="highpass", fs=FS, output="sos"), slow + fast)
    s, c = np.linalg.lstsq(basis, causal[interior], rcond=None)[0]
    assert abs(math.atan2(c, s) - 0.7) > 0.02


# --- STFT --------------------------------------------------------------------


def test_stft_ridge_follows_linear_chirp():
    fs, f0, rate = 5000.0, 43.0, 170.0  # Hz, Hz, Hz/s
    t = _time(2.0, fs)
    x = np.sin(2 * math.pi * (f0 * t + 0.5 * rate * t**2))
    tf = stft(t, x, segment=0.1, overlap=0.5, units="Hz")
    n_seg, hop = 500, 250
    assert tf.amplitude.shape == (n_seg // 2 + 1, (t.size - n_seg) // hop + 1)
    assert tf.time[0] == pytest.approx((n_seg - 1) / (2 * fs))
    assert np.diff(tf.time) == pytest.approx(np.full(tf.time.size - 1, hop / fs))
    resolution = 1 / 0.1  # Hz
    ridge = tf.frequency[np.argmax(tf.amplitude, axis=0)]
    instantaneous = f0 + rate * tf.time
    # bin quantisation alone gives up to half a bin (measured 4.98 Hz)
    assert np.max(np.abs(ridge - instantaneous)) <= 0.6 * resolution
    assert np.max(ridge) > 350  # the ridge really moves
    # amplitude 1, read on the bins: at most the Hann scalloping loss (15 %) plus sweep smearing
    ridge_amplitude = np.max(tf.amplitude, axis=0)
    assert np.all((ridge_amplitude > 0.8) & (ridge_amplitude < 1.01))
    # rad/s
    tf_rad = stft(t, x, segment=0.1, overlap=0.5)
    np.testing.assert_allclose(tf_rad.frequency, 2 * math.pi * tf.frequency)


# --- white noise -------------------------------------------------------------


def test_white_noise_spectrum_is_flat_at_theoretical_level():
    sigma = 0.3
    t = _time()
    x = np.random.default_rng(12345).normal(0.0, sigma, t.size)
    spectrum = amplitude_spectrum(t, x)
    # E|X_k|^2 = sigma^2 sum(w^2); |X_k| is Rayleigh: E[A_k] = sqrt(pi) sigma sqrt(sum w^2) / sum w
    w = get_window("hann", t.size)
    level = math.sqrt(math.pi) * sigma * math.sqrt(np.sum(w**2)) / np.sum(w)
    inner = spectrum.amplitude[5:-5]
    assert inner.mean() == pytest.approx(level, rel=0.03)
    for band in np.array_split(inner, 8):  # flat: every eighth of the band at the same level
        assert band.mean() == pytest.approx(level, rel=0.08)
    # no peak stands out of the noise floor; a modest tone would
    assert find_peaks(spectrum, min_snr=5.0) == []
    assert label_orders([p.frequency for p in find_peaks(spectrum, min_snr=5.0)], SPEEDS) == []
    tone = 8 * level * np.sin(1500.0 * t)
    peaks = find_peaks(amplitude_spectrum(t, x + tone), min_snr=5.0)
    assert [lab.label for lab in label_orders(peaks, SPEEDS)] == ["low"]


def test_noise_peaks_are_capped_and_mostly_unlabelled():
    t = _time()
    x = np.random.default_rng(7).normal(0.0, 1.0, t.size)
    peaks = find_peaks(amplitude_spectrum(t, x), max_peaks=5)
    assert len(peaks) == 5
    assert all(a.frequency < b.frequency for a, b in zip(peaks, peaks[1:]))


# --- time window ---------------------------------------------------------------


def test_window_shows_only_second_frequency():
    fs = 5000.0
    t = _time(4.0, fs)
    w1, w2 = 900.0, 1700.0  # rad/s
    x = np.where(t < 2.0, np.sin(w1 * t), 0.8 * np.sin(w2 * t))
    late = amplitude_spectrum(t, x, window=(2.2, 3.8))
    assert late.n_samples == int(round(1.6 * fs)) + 1
    peaks = find_peaks(late, min_relative_height=0.05)
    assert len(peaks) == 1
    assert peaks[0].frequency == pytest.approx(w2, abs=0.05 * late.resolution)
    assert peaks[0].amplitude == pytest.approx(0.8, rel=0.01)
    assert amplitude_at(late, w1) < 1e-3
    # the whole signal shows both
    whole = amplitude_spectrum(t, x)
    assert amplitude_at(whole, w1) > 0.3
    early = amplitude_spectrum(t, x, window=(0.1, 1.9))
    assert amplitude_at(early, w2) < 1e-3


# --- order labelling -------------------------------------------------------------


def test_label_combinations_natural_frequencies_and_misses():
    low, high = SPEEDS["low"], SPEEDS["high"]
    freqs = [high - low, high + low, 2 * low - high, 336.0 * 1.01, 1.25 * low, 5 * high, 0.0]
    labels = label_orders(freqs, SPEEDS, natural_frequencies={"omega_b": 336.0})
    assert [lab.label for lab in labels] == [
        "high - low",
        "high + low",
        "2 low - high",
        "omega_b",
        "5/4 low",
        None,
        None,
    ]
    assert labels[3].error == pytest.approx(0.01)
    assert labels[3].ratio == Fraction(1) and labels[3].reference == "omega_b"
    assert labels[0].ratio is None and labels[0].reference == "high - low"
    assert labels[5] == OrderLabel(5 * high, None, None, None, None)
    assert not labels[5].matched and labels[4].matched


def test_label_tolerance_and_nearest():
    # 2% tolerance: 1.019 low is "low", 1.021 low is not a line (1 < 1.021 < 5/4 ...)
    assert label_orders(1.019 * 1500.0, {"low": 1500.0})[0].label == "low"
    assert label_orders(1.021 * 1500.0, {"low": 1500.0})[0].label is None
    assert label_orders(1.021 * 1500.0, {"low": 1500.0}, tolerance=0.05)[0].label == "low"
    # nearest wins: 0.26 low is closer to 1/4 low (4%) than to 1/3 low: outside 2% anyway
    assert label_orders(0.255 * 1500.0, {"low": 1500.0})[0].label == "1/4 low"


def test_label_prefers_simplest_ratio_on_ties():
    speeds = {"low": 1500.0, "high": 3000.0}  # high = 2 low: several lines coincide
    labels = label_orders([3000.0, 1500.0, 4500.0, 750.0], speeds, max_combination_order=3)
    # 4500 = 3 low = 3/2 high = high + low: the simplest single-speed order wins
    assert [lab.label for lab in labels] == ["high", "low", "3 low", "1/2 low"]
    # 1500 = high - low as well, 750 = 1/4 high: harmonics of one speed beat combinations
    assert [lab.reference for lab in labels] == ["high", "low", "low", "low"]


def test_label_custom_ratios_and_input_forms():
    labels = label_orders(np.array([600.0, 700.0]), {"s": 1000.0}, ratios=["3/5", 0.7])
    assert [lab.label for lab in labels] == ["3/5 s", "7/10 s"]
    single = label_orders(Peak(1000.0 / (2 * math.pi), 1.0, "Hz"), {"s": 1000.0})
    assert single[0].label == "s" and single[0].frequency == pytest.approx(1000.0)


def test_amplitude_at_detects_half_order():
    t = _time()
    with_half = np.sin(1500.0 * t) + 0.05 * np.sin(750.0 * t)
    without = np.sin(1500.0 * t) + 0.05 * np.sin(1000.0 * t)
    level_with = amplitude_at(amplitude_spectrum(t, with_half), 0.5 * 1500.0)
    level_without = amplitude_at(amplitude_spectrum(t, without), 0.5 * 1500.0)
    assert level_with == pytest.approx(0.05, rel=0.02)
    assert level_without < 1e-4


# --- results are frozen ------------------------------------------------------------


def test_results_are_immutable(sines):
    t, x = sines
    spectrum = amplitude_spectrum(t, x)
    with pytest.raises(dataclasses.FrozenInstanceError):
        spectrum.units = "Hz"
    with pytest.raises(ValueError):
        spectrum.amplitude[0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        find_peaks(spectrum)[0].amplitude = 0.0


# --- bad input -----------------------------------------------------------------------


def _bad_time():
    t = _time(0.1)
    t[10] += 0.3 / FS
    return t


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda t, x: highpass(_bad_time(), x, 5.0), r"t is not uniformly sampled"),
        (lambda t, x: amplitude_spectrum(_bad_time(), x), r"t is not uniformly sampled"),
        (lambda t, x: stft(t[::-1], x), r"t is not strictly increasing"),
        (lambda t, x: highpass(t, x, 10_000.0), r"cutoff=10000.0 Hz is at or above the Nyquist frequency 10000 Hz"),
        (lambda t, x: highpass(t, x, 12_000.0), r"cutoff=12000.0 .*Nyquist"),
        (lambda t, x: highpass(t, x, -1.0), r"cutoff=-1.0 is invalid: expected a finite number > 0"),
        (lambda t, x: highpass(t, x, 5.0, order=0), r"order=0"),
        (lambda t, x: amplitude_spectrum(t, x, window=(0.05, 0.2)), r"window=\(0.05, 0.2\) is outside the signal"),
        (lambda t, x: amplitude_spectrum(t, x, window=(-0.01, 0.05)), r"window=.* is outside the signal"),
        (lambda t, x: amplitude_spectrum(t, x, window=(0.05, 0.02)), r"t_start < t_end"),
        (lambda t, x: amplitude_spectrum(t, x, window=(0.05, 0.05001)), r"expected at least 8"),
        (lambda t, x: amplitude_spectrum(t, x, units="kHz"), r"units='kHz' is not supported.*'rad/s', 'Hz'"),
        (lambda t, x: stft(t, x, units="rpm"), r"units='rpm' is not supported"),
        (lambda t, x: label_orders([1.0], SPEEDS, units="hz"), r"units='hz' is not supported"),
        (lambda t, x: amplitude_spectrum(t, x, taper="nonsense"), r"taper='nonsense' is not a known window"),
        (lambda t, x: amplitude_spectrum(t, x, pad_to=10), r"pad_to=10 is invalid"),
        (lambda t, x: amplitude_spectrum(t, x[:-1]), r"x has shape \(1999,\)"),
        (lambda t, x: stft(t, x, segment=1.0), r"segment=1.0 s holds 20000 samples"),
        (lambda t, x: stft(t, x, overlap=1.0), r"overlap=1.0 is invalid"),
        (lambda t, x: label_orders([1.0], {"low": -3.0}), r"speeds\['low'\]=-3.0 is invalid"),
        (lambda t, x: label_orders([1.0], SPEEDS, ratios=[0]), r"ratios contains 0"),
        (lambda t, x: label_orders(["a"], SPEEDS), r"peaks_or_frequencies contains 'a'"),
        (lambda t, x: find_peaks(amplitude_spectrum(t, x), max_peaks=0), r"max_peaks=0"),
        (lambda t, x: amplitude_at(amplitude_spectrum(t, x), 1e6), r"frequency=1000000.0 rad/s is outside"),
    ],
)
def test_bad_input_raises_value_error(call, match):
    t = _time(0.1)
    x = np.sin(1500.0 * t)
    with pytest.raises(ValueError, match=match):
        call(t, x)
