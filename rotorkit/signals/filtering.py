"""Zero-phase high-pass filtering of a sampled signal."""

from __future__ import annotations

import math
import numbers

from ..errors import ParameterError
from .sampling import as_signal, positive_float

__all__ = [
    "highpass",
]


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

    t, x, dt = as_signal(t, x)
    cutoff = positive_float(cutoff, "cutoff", "Hz")
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
