"""Post-processing of simulated or measured rotor signals.

:mod:`rotorkit.analysis.signals` holds the signal analysis of vibration
signals: zero-phase high-pass filtering, amplitude spectra, short-time
spectra, peak finding and labelling of frequencies as orders of the rotor
speeds.
"""

from .signals import (
    DEFAULT_RATIOS,
    FREQUENCY_UNITS,
    OrderLabel,
    Peak,
    Spectrum,
    TimeFrequency,
    amplitude_at,
    amplitude_spectrum,
    find_peaks,
    highpass,
    label_orders,
    stft,
)

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
