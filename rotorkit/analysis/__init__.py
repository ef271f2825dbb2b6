"""Analyses of models and of simulated or measured rotor signals.

- :mod:`rotorkit.analysis.signals`: zero-phase high-pass filtering,
  amplitude spectra, short-time spectra, peak finding and labelling of
  frequencies as orders of the rotor speeds;
- :mod:`rotorkit.analysis.modes`: modal analysis of a compiled system
  (re-exports :mod:`~rotorkit.analysis.linearize`, :mod:`~rotorkit.analysis.modal`);
- :mod:`rotorkit.analysis.linear_model`: ``M, C + W G, K + W H`` from
  matrices or linearised; :mod:`rotorkit.analysis.whirl`: orbits and whirl;
- :mod:`rotorkit.analysis.campbell`: Campbell and stability diagrams;
- :mod:`rotorkit.analysis.unbalance`, :mod:`rotorkit.analysis.frf`
  (solved by :mod:`rotorkit.analysis.harmonic`): unbalance response, FRFs;
- :mod:`rotorkit.analysis.static`, :mod:`rotorkit.analysis.critical_map`:
  static deflection and reactions, critical speed map;
- :mod:`rotorkit.analysis.stiffness`: time scales and the method that fits;
- :mod:`rotorkit.analysis.loads`: the manoeuvre load on a station;
- :mod:`rotorkit.analysis.energy`: energy balance along a run.

Only the signal functions are imported here; the others load on use.
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
