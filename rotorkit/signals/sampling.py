"""Sampled signals: checks of sample times and windows, tapers and frequency units.

Shared by the filtering, spectra, peak and order modules of :mod:`rotorkit.signals`.
Bad input raises :class:`rotorkit.errors.ParameterError`, a ``ValueError``.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import ParameterError

__all__ = [
    "FREQUENCY_UNITS",
    "UNIFORM_RTOL",
    "MIN_SAMPLES",
    "check_units",
    "hz_to",
    "convert",
    "positive_float",
    "as_signal",
    "time_step",
    "select_window",
    "taper_weights",
    "readonly",
]


#: Frequency units accepted by the ``units`` arguments.
FREQUENCY_UNITS = ("rad/s", "Hz")

# Relative tolerance on the spread of the time steps of a "uniform" time vector.
UNIFORM_RTOL = 1e-5
# Fewest samples accepted in a spectrum window or an STFT segment.
MIN_SAMPLES = 8



def check_units(units, name="units"):
    if not isinstance(units, str) or units not in FREQUENCY_UNITS:
        raise ParameterError(f"{name}={units!r} is not supported: expected one of {FREQUENCY_UNITS}")
    return units


def hz_to(values_hz, units):
    """Convert frequencies in Hz to ``units``."""
    return values_hz * (2.0 * math.pi) if units == "rad/s" else values_hz


def convert(value, from_units, to_units):
    """Convert a frequency between ``"rad/s"`` and ``"Hz"``."""
    if from_units == to_units:
        return value
    return value * (2.0 * math.pi) if to_units == "rad/s" else value / (2.0 * math.pi)


def positive_float(value, name, unit=""):
    ok = isinstance(value, numbers.Real) and not isinstance(value, bool)
    if not ok or not math.isfinite(value) or value <= 0:
        shown = f" ({unit})" if unit else ""
        raise ParameterError(f"{name}={value!r} is invalid: expected a finite number > 0{shown}")
    return float(value)


def as_signal(t, x):
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
    return t, x, time_step(t)


def time_step(t):
    steps = np.diff(t)
    if np.any(steps <= 0):
        i = int(np.argmax(steps <= 0))
        raise ParameterError(
            f"t is not strictly increasing (t[{i}]={t[i]!r}, t[{i + 1}]={t[i + 1]!r}): "
            "expected uniformly sampled, increasing times (s)"
        )
    dt = (t[-1] - t[0]) / (t.size - 1)
    spread = float(np.max(np.abs(steps - dt)) / dt)
    if spread > UNIFORM_RTOL:
        raise ParameterError(
            f"t is not uniformly sampled: time steps range from {steps.min():.6g} to "
            f"{steps.max():.6g} s (relative spread {spread:.3g}); expected a constant step "
            f"(relative tolerance {UNIFORM_RTOL:g}); resample the signal first"
        )
    return float(dt)


def select_window(t, x, dt, window):
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
    if n < MIN_SAMPLES:
        raise ParameterError(
            f"window={window!r} holds {n} samples: expected at least {MIN_SAMPLES} "
            f"(time step {dt:.6g} s)"
        )
    return x[mask]


def taper_weights(taper, n):
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


def readonly(array):
    array = np.ascontiguousarray(array)
    array.setflags(write=False)
    return array
