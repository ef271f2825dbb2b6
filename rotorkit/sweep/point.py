"""One sweep point: rebuild the model, simulate, reduce the run to a few arrays.

:func:`run_point` runs in a worker (a local process, a Dask worker or the
calling process). It takes plain data (a :class:`~rotorkit.sweep.scene.Scene`,
the point's parameter values and the sweep's settings) and returns plain
data; it writes nothing: the calling process stores each point as its result
arrives, so a point retried after a worker died is stored once.

Per point: the high-passed amplitude spectra over the window, the amplitude
of chosen orders, once-per-revolution (Poincare) samples, the largest
displacement, the status (``ok``, ``failed``, ``runaway``) with the time and
reason, the solver statistics and the energy-balance residual.
"""

from __future__ import annotations

import functools
import math
import os
import re
import time as _time
from fractions import Fraction

import numpy as np

from ..errors import ParameterError, SimulationError

__all__ = ["run_point", "parse_order", "rotor_speeds", "spectra", "RUNAWAY_FACTOR"]

#: default runaway limit of a rub station (the disk in a stator): this many times its clearance
RUNAWAY_FACTOR = 10.0

_TERM = re.compile(r"\s*([+-]?)\s*(\d+(?:\.\d*)?(?:/\d+)?)?\s*\*?\s*([A-Za-z_]\w*)?\s*")


def rotor_speeds(model):
    """Rotor name -> spin speed (rad/s) of a model's rotors, in model order."""
    from ..elements import Rotor

    rotors = [e for e in model.elements if isinstance(e, Rotor)]
    speeds = {}
    for _ in range(len(rotors)):  # references resolve in at most len(rotors) passes
        for r in rotors:
            if r.name in speeds:
                continue
            if r.speed is not None:
                speeds[r.name] = float(r.speed)
            elif r.reference in speeds:
                speeds[r.name] = float(r.speed_ratio) * speeds[r.reference]
    return {r.name: speeds[r.name] for r in rotors if r.name in speeds}


def parse_order(text, rotors):
    """An order as ``{rotor name: multiple}``: ``"1/2"`` (of the first rotor), ``"HP - LP"``, ``"3/2 LP"``.

    Examples
    --------
    >>> parse_order("HP - 1/2 LP", ["LP", "HP"])
    {'HP': 1.0, 'LP': -0.5}
    >>> parse_order("3/2", ["LP", "HP"])
    {'LP': 1.5}
    """
    rotors = list(rotors)
    if not isinstance(text, str) or not text.strip():
        raise ParameterError(f"order {text!r}: expected e.g. '1/2', '1', '3/2 LP' or 'HP - LP'")
    if not rotors:
        raise ParameterError(f"order {text!r}: the model has no rotor, so it has no speed orders")
    out, pos, first = {}, 0, True
    while pos < len(text):
        m = _TERM.match(text, pos)
        if not m or m.end() == pos or (not first and not m.group(1)) or not (m.group(2) or m.group(3)):
            raise ParameterError(f"order {text!r}: expected terms like '1/2', '3/2 LP' or 'HP - LP' "
                                 f"(rotors: {', '.join(rotors)})")
        sign = -1.0 if m.group(1) == "-" else 1.0
        try:
            factor = float(Fraction(m.group(2))) if m.group(2) else 1.0
        except ZeroDivisionError:
            raise ParameterError(f"order {text!r}: {m.group(2)!r} divides by zero; expected e.g. '1/2'") from None
        name = m.group(3) or rotors[0]
        if name not in rotors:
            raise ParameterError(f"order {text!r}: {name!r} is not a rotor of the model (rotors: {', '.join(rotors)})")
        out[name] = out.get(name, 0.0) + sign * factor
        pos, first = m.end(), False
    if all(k <= 0 for k in out.values()):
        raise ParameterError(f"order {text!r}: the order is not positive; expected e.g. '1', '1/2' or 'HP - LP' "
                             "(a speed order is a positive multiple of a rotor speed, or a difference of speeds)")
    return out


def order_frequency(order, speeds):
    return sum(k * speeds[name] for name, k in order.items())


def _radial(result, station):
    return np.hypot(result[f"x{station}"], result[f"y{station}"])


def _peak_squared_radii(result, stations):
    """Station -> largest ``x**2 + y**2`` over the run (a cheap pass: no radius array per station), or None when a
    state is not finite (the caller then takes the NaN-aware path)."""
    y = result.y
    if not math.isfinite(np.einsum("ij->", y)):  # one pass over all states: also the finiteness check of the run
        return None
    names = result.state_names
    out = {}
    for st in stations:
        x, z = y[names.index(f"x{st}")], y[names.index(f"y{st}")]
        out[st] = float(np.max(x * x + z * z))
    return out


def _runaway_limits(model, limit):
    if limit is not None:
        return [(s, limit) for s in model.stations] if math.isfinite(limit) else []
    from ..elements import RubStator

    return [(e.station, RUNAWAY_FACTOR * e.clearance) for e in model.elements
            if isinstance(e, RubStator) and e.clearance > 0]


def _first_runaway(result, limits, peaks=None):
    """(sample, station, peak radius, limit) of the earliest passing of a runaway limit, or None.

    ``peaks`` (from :func:`_peak_squared_radii`) skips the stations that never pass their limit.
    """
    first = None
    for station, limit in limits:
        if peaks is not None and peaks[station] <= limit * limit:
            continue
        r = np.nan_to_num(_radial(result, station), nan=0.0)
        over = np.flatnonzero(r > limit)
        if over.size and (first is None or over[0] < first[0]):
            first = (int(over[0]), station, float(r.max()), limit)
    return first


@functools.lru_cache(maxsize=8)
def _highpass_sos(cutoff, sample_rate, order=4):
    """The Butterworth sections of :func:`rotorkit.signals.highpass`, designed once per sweep."""
    from scipy.signal import butter

    return butter(order, cutoff, btype="highpass", fs=sample_rate, output="sos")


@functools.lru_cache(maxsize=8)
def _hann(n_samples):
    from ..signals.sampling import taper_weights

    weights = taper_weights("hann", n_samples)[1]
    weights.setflags(write=False)
    return weights


def spectra(result, names, window, highpass_hz):
    """Amplitude spectra of several signals over ``window``: the numbers of :meth:`Result.spectrum
    <rotorkit.result.Result.spectrum>` (Hann taper, zero-phase 4th-order Butterworth high-pass of the whole
    run, rad/s), computed in one pass for all signals, with the filter and the taper made once per sweep.

    Returns
    -------
    list of Spectrum
        One per name, all on the same frequency grid.
    """
    from ..signals.sampling import hz_to, select_window, time_step
    from ..signals.spectra import Spectrum, rfft_amplitude

    t = result.t
    dt = time_step(t)
    x = np.vstack([result[name] for name in names])
    if highpass_hz is not None:
        from scipy.signal import sosfiltfilt

        if highpass_hz >= 0.5 / dt:
            raise ParameterError(f"highpass_hz={highpass_hz!r} is at or above the Nyquist frequency "
                                 f"{0.5 / dt:.6g} Hz of the samples: expected 0 < highpass_hz < Nyquist")
        sample_rate = 1.0 / dt
        padlen = min(t.size - 1, int(math.ceil(3.0 / (highpass_hz * dt))))
        x = sosfiltfilt(_highpass_sos(float(highpass_hz), sample_rate), x, axis=-1, padlen=padlen)
    keep = select_window(t, t, dt, window)  # the window's sample times (checks the window)
    first = int(np.searchsorted(t, keep[0]))
    segments = x[:, first:first + keep.size]
    n = keep.size
    amplitude = rfft_amplitude(segments, _hann(n), n)
    frequency = hz_to(np.fft.rfftfreq(n, dt), "rad/s")
    frequency.setflags(write=False)
    amplitude.setflags(write=False)
    return [Spectrum(frequency, row, "rad/s", "hann", n, n) for row in amplitude]


def _dirichlet(theta, n):
    """``sum_{k<n} exp(-i theta k)`` in closed form (``n`` at ``theta = 0``)."""
    theta = np.asarray(theta, dtype=float)
    half = 0.5 * theta
    small = np.abs(np.sin(half)) < 1e-300
    ratio = np.where(small, float(n), np.sin(n * half) / np.where(small, 1.0, np.sin(half)))
    return np.exp(-1j * half * (n - 1)) * ratio


def taper_response(taper, n_samples, n_fft, delta):
    """``|sum_k w_k exp(-2 pi i delta k / n_fft)| / sum_k w_k``: the taper's response to a tone ``delta`` bins
    off a bin centre (``delta``: array).

    The periodic Hann taper ``w_k = 1/2 - 1/2 cos(2 pi k / n)`` is a sum of three
    complex exponentials, so its response is three Dirichlet kernels (closed
    form, a few operations per ``delta``); any other taper is summed directly.
    """
    delta = np.asarray(delta, dtype=float)
    theta = 2.0 * math.pi * delta / n_fft
    if taper == "hann":
        shift = 2.0 * math.pi / n_samples
        total = (0.5 * _dirichlet(theta, n_samples)
                 - 0.25 * (_dirichlet(theta - shift, n_samples) + _dirichlet(theta + shift, n_samples)))
        return np.abs(total) / (0.5 * n_samples)
    from ..signals.sampling import taper_weights

    _, weights = taper_weights(taper, n_samples)
    k = np.arange(weights.size)
    out = np.empty(delta.size)
    for i, th in enumerate(theta.ravel()):  # one row at a time: no (len(delta), n) matrix
        out[i] = abs(np.dot(weights, np.exp(-1j * th * k)))
    return out.reshape(delta.shape) / weights.sum()


@functools.lru_cache(maxsize=8)
def _tone_table(taper, n_samples, n_fft):
    """(offset in bins, normalised taper response, ratio of the two top bins) on a fine grid, once per shape."""
    delta = np.linspace(0.0, 1.0, 201)
    response = taper_response(taper, n_samples, n_fft, delta)
    half = delta <= 0.5
    ratio = response[::-1][half] / response[half]  # R(1 - d) / R(d)
    return delta[half], response[half], ratio


def _order_amplitude(spectrum, frequency):
    """Amplitude of the tone nearest ``frequency`` within +-max(2 bins, 1 %): the highest bin there, corrected
    for the taper's scalloping loss from its larger neighbour (exact for an isolated tone, as
    :func:`~rotorkit.signals.find_peaks`, from a table of the taper's response); NaN outside the
    spectrum."""
    f, a = spectrum.frequency, np.asarray(spectrum.amplitude, dtype=float)
    target = abs(frequency)
    if f.size < 3 or not (0.0 < target <= f[-1]):
        return np.nan
    half = max(2.0 * (f[1] - f[0]), 0.01 * target)
    band = np.flatnonzero(np.abs(f - target) <= half)
    k = int(band[np.argmax(a[band])])
    if not (0 < k < f.size - 1) or not spectrum.taper or not spectrum.n_samples or not spectrum.n_fft:
        return float(a[k])
    alpha, beta = a[k], max(a[k - 1], a[k + 1])
    if alpha <= 0 or beta > alpha:
        return float(alpha)
    delta, response, ratio = _tone_table(spectrum.taper, int(spectrum.n_samples), int(spectrum.n_fft))
    d = np.interp(beta / alpha, ratio, delta)  # the ratio grows from R(1)/R(0) at d = 0 to 1 at d = 1/2
    return float(alpha / np.interp(d, delta, response))


def poincare_samples(result, name, window, speed, count):
    """``count`` once-per-revolution samples of signal ``name``: the last revolutions of ``window`` (NaN-padded)."""
    out = np.full(count, np.nan)
    if not speed or not math.isfinite(speed) or speed == 0.0:
        return out
    period = 2.0 * math.pi / abs(speed)
    start, end = window
    n = min(count, int(math.floor((end - start) / period)) + 1)
    times = end - period * np.arange(n)[::-1]
    out[count - n:] = np.interp(times, result.t, result[name])
    return out


def _energy_residual(model, result):
    from ..analysis.energy import energy_balance
    from ..errors import RotorkitError

    try:
        return float(energy_balance(model, result).relative_residual)
    except (RotorkitError, ValueError, FloatingPointError, ZeroDivisionError):
        return float("nan")


def _refused(task, message, wall):
    s = task["settings"]
    meta = {"index": task["index"], "point": task["point"], "status": "failed", "time": None,
            "max_displacement": None, "runaway_limit": None, "message": message, "spectrum": None,
            "energy_residual": float("nan"), "stats": {"point_wall_time": _time.perf_counter() - wall}}
    return {"index": task["index"], "meta": meta, "arrays": {
        "frequency": np.empty(0), "amplitude": np.empty((len(s["signals"]), 0)),
        "order_amplitude": np.full((len(s["signals"]), len(s["orders"])), np.nan),
        "poincare": np.full((len(s["poincare_signals"]), s["poincare_revolutions"]), np.nan)}}


def run_point(task):
    """Simulate one point; returns ``{"index", "meta", "arrays"}`` (plain data, nothing written).

    ``task``: ``scene``, ``index``, ``point`` (name -> value) and the sweep
    ``settings`` (see :func:`rotorkit.sweep.run_sweep`).
    """
    wall = _time.perf_counter()
    s = task["settings"]
    try:
        model = task["scene"].build(task["point"])
    except ParameterError as err:  # values this point's model refuses: a result, not a crash
        return _refused(task, f"the model refused the point's parameters: {err}", wall)
    system = model.compile(backend=s["backend"])
    if s.get("reduce"):
        from ..reduction import reduce

        system = reduce(system, **s["reduce"])
    limits = _runaway_limits(model, s["runaway_limit"])
    status, message, when = "ok", "", None
    bound = min((limit for _, limit in limits), default=None)
    from ..simulate import simulate

    sim_start = _time.perf_counter()
    try:
        result, err = simulate(system, (0.0, s["t_end"]), bound=bound, check_convergence=False,
                               **s["simulate_options"]), None  # a point costs one run
    except SimulationError as exc:
        result, err = exc.partial, exc
    if s.get("reduce") and result is not None:
        result = system.expand(result)
    sim_time = _time.perf_counter() - sim_start
    if err is not None:
        status, message, when = "failed", str(err), err.time
        if "run-away" in str(err).splitlines()[0]:
            status = "runaway"
    sampled = result is not None and result.t.size > 0
    max_disp, limit, peaks = None, bound, None
    if sampled:
        peaks = _peak_squared_radii(result, model.stations)
    if peaks is not None:  # every state finite
        max_disp = math.sqrt(max(peaks.values())) if peaks else None
    elif sampled:
        radial = np.vstack([_radial(result, st) for st in model.stations])
        finite = radial[np.isfinite(radial)]
        max_disp = float(finite.max()) if finite.size else None
        if status == "ok" and not np.all(np.isfinite(result.y)):  # (not a finite sum that overflowed)
            bad = int(np.argmax(~np.all(np.isfinite(result.y), axis=0)))
            status, message, when = "failed", f"non-finite states from t = {result.t[bad]:.6g} s", float(result.t[bad])
    runaway = _first_runaway(result, limits, peaks) if sampled else None
    if runaway is not None:
        at, station, peak, limit = runaway
        how = f" before the integration failed ({message.splitlines()[0]})" if status == "failed" else ""
        why = " (10 x its rub clearance)" if s["runaway_limit"] is None else ""
        status, when = "runaway", float(result.t[at])
        message = (f"station {station} passed the runaway limit {limit:.3g} m{why} at t = {when:.4g} s and reached "
                   f"{peak:.3g} m{how}: the response ran away (e.g. dry-friction whirl at high friction); no spectrum")
    signals, orders, n_rev = s["signals"], s["orders"], s["poincare_revolutions"]
    frequency = np.empty(0)
    amplitude = np.empty((len(signals), 0))
    order_amp = np.full((len(signals), len(orders)), np.nan)
    poincare = np.full((len(s["poincare_signals"]), n_rev), np.nan)
    spectrum_info, energy = None, float("nan")
    speeds = rotor_speeds(model)
    if status == "ok":
        rows = []
        freqs = [order_frequency(parse_order(o, list(speeds)), speeds) for o in orders]
        for i, spectrum in enumerate(spectra(result, signals, tuple(s["window"]), s["highpass_hz"])):
            frequency = spectrum.frequency
            rows.append(spectrum.amplitude)
            order_amp[i] = [_order_amplitude(spectrum, f) for f in freqs]
            spectrum_info = {"taper": spectrum.taper, "n_samples": spectrum.n_samples, "n_fft": spectrum.n_fft}
        amplitude = np.vstack(rows)
        reference = speeds[s["poincare_rotor"]] if s["poincare_rotor"] else next(iter(speeds.values()), 0.0)
        for i, name in enumerate(s["poincare_signals"]):
            poincare[i] = poincare_samples(result, name, s["window"], reference, n_rev)
        if s["energy"]:
            energy = _energy_residual(model, result)
    stats = {k: v for k, v in (result.stats if result is not None else {}).items()
             if isinstance(v, (bool, int, float, str)) or v is None}
    stats.update(point_wall_time=_time.perf_counter() - wall, simulate_wall_time=sim_time, pid=os.getpid())
    meta = {"index": task["index"], "point": task["point"], "status": status, "time": when,
            "max_displacement": max_disp, "runaway_limit": limit, "message": message, "spectrum": spectrum_info,
            "energy_residual": energy, "stats": stats}
    return {"index": task["index"], "meta": meta,
            "arrays": {"frequency": frequency, "amplitude": amplitude, "order_amplitude": order_amp,
                       "poincare": poincare}}
