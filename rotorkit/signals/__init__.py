"""Signal processing of rotor vibration signals (:mod:`rotorkit.signals`).

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

Modules, by concept:

- :mod:`~rotorkit.signals.sampling`: checks of sample times, windows, tapers, frequency units;
- :mod:`~rotorkit.signals.filtering`: :func:`highpass`;
- :mod:`~rotorkit.signals.spectra`: :func:`amplitude_spectrum`, :func:`stft`;
- :mod:`~rotorkit.signals.peaks`: :func:`find_peaks`, :func:`amplitude_at`;
- :mod:`~rotorkit.signals.orders`: :func:`label_orders`.

Formerly ``rotorkit.analysis.signals`` (that path still works).
"""

from .filtering import highpass
from .orders import DEFAULT_RATIOS, OrderLabel, label_orders
from .peaks import Peak, amplitude_at, find_peaks
from .sampling import FREQUENCY_UNITS
from .spectra import Spectrum, TimeFrequency, amplitude_spectrum, stft

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
