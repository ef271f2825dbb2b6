"""Parameter sweeps: one simulation per value, spectra per point, resumable.

A sweep varies one model parameter over a list of values. Every point is
simulated from rest over ``0 .. t_end``; each output signal is high-pass
filtered (to drop the slow manoeuvre offset) and its amplitude spectrum over
a time window is stored. Stacked along the swept parameter, these spectra
are the paper's *spectrum cascades* (Figs. 13-15: spectra over
``t in [2.2, 3.8] s``).

Points run in parallel in local worker processes (``spawn`` start method by
default: the worker is a module-level function taking plain data). The model
of each structure is derived and compiled once in the calling process, so
workers load it from the on-disk model cache instead of deriving it again.

Files in ``out_dir``::

    sweep.json          the manifest: preset, parameter, values, overrides,
                        window, t_end, filter, signals, simulation options
    point_0000.npz      one file per point, written atomically when the
    point_0001.npz      point finishes (format below)
    ...

An interrupted sweep is resumed by calling :func:`run_sweep` again with the
same arguments: points whose file exists and is valid (same sweep, parameter
name, value, window and signals) are not recomputed; missing or damaged ones
are. A folder whose manifest describes another sweep is refused.

Point files are ``.npz`` archives without pickled objects: ``meta`` (a JSON
string: ``format``, ``fingerprint``, ``index``, ``parameter``, ``value``,
``window``, ``highpass_hz``, ``t_end``, ``signals``, ``status``, ``time``,
``max_displacement``, ``runaway_limit``, ``message``, ``spectrum`` (taper
and lengths), ``stats``),
``frequency`` (rad/s, shape (n_freq,)) and ``amplitude`` (shape
(n_signals, n_freq), same unit as each signal). A point whose simulation
failed (:class:`~rotorkit.errors.SimulationError`) or ran away (displacement
past ``runaway_limit``) has status ``"failed"`` or ``"runaway"``, the time it
happened and the largest displacement reached, and empty ``frequency`` and
``amplitude``: it never holds a spectrum of a broken run.

Examples
--------
>>> parse_range("rub_stiffness=5e5:2e7:3")
('rub_stiffness', (500000.0, 10250000.0, 20000000.0))
>>> parse_range("friction_coefficient=0,0.1,0.2")
('friction_coefficient', (0.0, 0.1, 0.2))
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import io
import json
import math
import numbers
import os
import sys
import time as _time
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from .errors import ParameterError, RotorkitError, SimulationError

__all__ = ["parse_range", "run_sweep", "load_sweep", "point_path", "Cascade", "STATUSES", "MANIFEST_NAME"]

#: Point statuses: ``ok`` (spectrum stored), ``failed`` (the integration
#: raised), ``runaway`` (displacement past the runaway limit), ``missing``
#: (no valid file yet; only in :class:`Cascade`).
STATUSES = ("ok", "failed", "runaway", "missing")

MANIFEST_NAME = "sweep.json"
MANIFEST_FORMAT = "rotorkit-sweep-1"
POINT_FORMAT = "rotorkit-sweep-point-1"

#: default runaway limit of a rub station (the disk in a stator): this many times its clearance
RUNAWAY_FACTOR = 10.0

# keyword arguments of rotorkit.simulate a sweep may pass on (plus "backend" for compiling)
_SIMULATE_KEYS = ("method", "rtol", "atol", "sample_rate", "max_step", "engine", "time_limit")


# ---------------------------------------------------------------------------
# Parsing "name=start:stop:n"
# ---------------------------------------------------------------------------


def _number(text, spec, what):
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(f"sweep range {spec!r}: {what} {text.strip()!r} is not a number (SI units)") from None
    if not math.isfinite(value):
        raise ParameterError(f"sweep range {spec!r}: {what} {text.strip()!r} is not finite")
    return value


def parse_range(text):
    """Parse a swept parameter ``name=spec`` into ``(name, values)``.

    Parameters
    ----------
    text : str
        ``name=start:stop:n`` for ``n`` linearly spaced values (both ends
        included), ``name=log:start:stop:n`` for log spacing (``start``,
        ``stop`` > 0), or an explicit list ``name=v1,v2,...``. Values are SI
        numbers (e.g. ``rub_stiffness=5e5:2e7:40``).

    Returns
    -------
    (str, tuple of float)

    Raises
    ------
    ParameterError
        A missing ``=``, a name that is not an identifier, a value that is
        not a finite number, ``n`` not an integer >= 2, equal ends, a log
        range with a non-positive end, an empty list item or duplicates.

    Examples
    --------
    >>> parse_range("rub_stiffness=log:1e6:1e8:3")
    ('rub_stiffness', (1000000.0, 10000000.0, 100000000.0))
    """
    if not isinstance(text, str):
        raise ParameterError(f"sweep range {text!r}: expected a string such as 'rub_stiffness=5e5:2e7:40'")
    if "=" not in text:
        raise ParameterError(
            f"sweep range {text!r}: expected name=start:stop:n, name=log:start:stop:n or name=v1,v2,... "
            "(e.g. rub_stiffness=5e5:2e7:40)"
        )
    name, spec = (s.strip() for s in text.split("=", 1))
    if not name.isidentifier():
        raise ParameterError(f"sweep range {text!r}: {name!r} is not a parameter name")
    if not spec:
        raise ParameterError(f"sweep range {text!r}: no values after '='")
    log = spec.lower().startswith("log:")
    if log or ":" in spec:
        parts = spec[4:].split(":") if log else spec.split(":")
        if len(parts) != 3:
            form = "log:start:stop:n" if log else "start:stop:n"
            raise ParameterError(f"sweep range {text!r}: expected {name}={form} (three fields, got {len(parts)})")
        start = _number(parts[0], text, "start")
        stop = _number(parts[1], text, "stop")
        raw_n = parts[2].strip()
        if not raw_n.isdigit() or int(raw_n) < 2:
            raise ParameterError(
                f"sweep range {text!r}: the number of values {raw_n!r} must be an integer >= 2 "
                f"(for a single value write {name}=<value>)"
            )
        n = int(raw_n)
        if start == stop:
            raise ParameterError(f"sweep range {text!r}: start and stop are equal ({start:g})")
        if log:
            if start <= 0 or stop <= 0:
                raise ParameterError(f"sweep range {text!r}: a log range needs start > 0 and stop > 0")
            values = np.geomspace(start, stop, n)
            values[0], values[-1] = start, stop
        else:
            values = np.linspace(start, stop, n)
        return name, tuple(float(v) for v in values)
    items = spec.split(",")
    if any(not item.strip() for item in items):
        raise ParameterError(f"sweep range {text!r}: empty item in the list of values")
    values = tuple(_number(item, text, "value") for item in items)
    _check_unique(values, f"sweep range {text!r}")
    return name, values


def _check_unique(values, where):
    seen = set()
    for v in values:
        if v in seen:
            raise ParameterError(f"{where}: the value {v:g} appears twice; each value is one point")
        seen.add(v)


# ---------------------------------------------------------------------------
# Results
# ---------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class Cascade:
    """Spectra over a swept parameter (a spectrum cascade).

    Attributes
    ----------
    parameter : str
        The swept parameter (e.g. ``"rub_stiffness"``).
    values : numpy.ndarray, shape (n_values,)
        Its values (SI), in sweep order.
    frequency : numpy.ndarray, shape (n_freq,)
        Frequencies (rad/s); empty if no point succeeded.
    amplitude : mapping of str to numpy.ndarray
        Signal name (``"x2"``, ``"alpha2-alpha5"``) -> amplitudes, shape
        (n_values, n_freq), same unit as the signal (m, rad). Rows of points
        whose status is not ``"ok"`` are NaN.
    status : numpy.ndarray of str, shape (n_values,)
        ``"ok"``, ``"failed"``, ``"runaway"`` or ``"missing"`` per point.
    failure_time : numpy.ndarray, shape (n_values,)
        Time (s) a point failed or ran away; NaN otherwise.
    max_displacement : numpy.ndarray, shape (n_values,)
        Largest radial displacement of any station over the run (m); NaN for
        missing points.
    messages : tuple of str
        Per point: why it failed or ran away (empty when ``ok``).
    preset : str
        Preset name, or ``"module:function"`` of the build function.
    window : (float, float)
        Time window of the spectra (s).
    highpass_hz : float or None
        Cut-off (Hz) of the high-pass filter applied before the spectra.
    units : str
        Units of ``frequency`` (``"rad/s"``).
    extra : mapping
        ``t_end``, ``overrides`` and ``simulate_options`` of the sweep, and
        ``spectrum``: the taper and lengths of the spectra (used by
        :meth:`spectrum` for exact peak interpolation).

    Arrays are read-only.
    """

    parameter: str
    values: np.ndarray
    frequency: np.ndarray
    amplitude: Mapping
    status: np.ndarray
    failure_time: np.ndarray
    max_displacement: np.ndarray
    messages: tuple = ()
    preset: str = ""
    window: tuple = (0.0, 0.0)
    highpass_hz: float | None = None
    units: str = "rad/s"
    extra: Mapping = field(default_factory=dict, repr=False)

    def __post_init__(self):
        for arr in (self.values, self.frequency, self.status, self.failure_time, self.max_displacement,
                    *self.amplitude.values()):
            arr.setflags(write=False)
        object.__setattr__(self, "amplitude", MappingProxyType(dict(self.amplitude)))

    @property
    def signals(self):
        """Names of the signals (tuple of str)."""
        return tuple(self.amplitude)

    @property
    def ok(self):
        """Boolean mask (n_values,) of the points with a spectrum."""
        return self.status == "ok"

    def spectrum(self, signal, index):
        """The :class:`~rotorkit.analysis.signals.Spectrum` of one point (``index`` into ``values``)."""
        from .analysis.signals import Spectrum

        rows = self._rows(signal)
        if self.status[index] != "ok":
            raise ParameterError(
                f"point {index} ({self.parameter} = {self.values[index]:g}) has status "
                f"{str(self.status[index])!r} and no spectrum: {self.messages[index]}"
            )
        info = self.extra.get("spectrum") or {}
        return Spectrum(self.frequency, rows[index], self.units, info.get("taper"), info.get("n_samples"),
                        info.get("n_fft"))

    def _rows(self, signal):
        try:
            return self.amplitude[signal]
        except KeyError:
            raise ParameterError(
                f"the cascade has no signal {signal!r}; signals are {', '.join(self.amplitude)}"
            ) from None

    def plot(self, signal, ax=None, **kwargs):
        """Spectra of ``signal`` stacked along the parameter; see :func:`rotorkit.plotting.spectra.plot_cascade`."""
        from .plotting.spectra import plot_cascade

        return plot_cascade(self, signal, ax=ax, **kwargs)


# ---------------------------------------------------------------------------
# Plain data for workers and manifests
# ---------------------------------------------------------------------------


def _is_quantity(value):
    return hasattr(value, "magnitude") and hasattr(value, "units") and hasattr(value, "dimensionality")


def _plain_override(name, value):
    """An override as JSON-able plain data (pint quantities as magnitude and unit)."""
    if isinstance(value, (bool, str)) or value is None:
        return value
    if isinstance(value, numbers.Real):
        value = value.item() if hasattr(value, "item") else value
        if isinstance(value, float) and not math.isfinite(value):
            raise ParameterError(f"overrides[{name!r}] = {value!r} is not finite")
        return value
    if _is_quantity(value):
        magnitude = value.magnitude
        if not isinstance(magnitude, numbers.Real):
            raise ParameterError(f"overrides[{name!r}] = {value!r}: expected a scalar quantity")
        return {"quantity": float(magnitude), "unit": str(value.units)}
    raise TypeError(
        f"overrides[{name!r}] = {value!r} ({type(value).__name__}): expected a number, bool, string or pint "
        "quantity (overrides are sent to worker processes and saved in sweep.json)"
    )


def _revive_override(value):
    if isinstance(value, dict) and set(value) == {"quantity", "unit"}:
        from .units import registry

        return registry().Quantity(value["quantity"], value["unit"])
    return value


def _describe_target(preset):
    """(target as plain data, display name) for a preset name or a build callable."""
    if isinstance(preset, str):
        from .presets import preset_module

        preset_module(preset)  # unknown names fail here, with suggestions
        return {"preset": preset}, preset
    if not callable(preset):
        raise TypeError(f"preset={preset!r}: expected a preset name (str) or a build(**overrides) -> Model callable")
    module = getattr(preset, "__module__", None)
    qualname = getattr(preset, "__qualname__", None)
    file = getattr(sys.modules.get(module), "__file__", None) if isinstance(module, str) else None
    importable = isinstance(module, str) and isinstance(qualname, str) and "<" not in qualname
    target = {"module": module, "qualname": qualname, "file": file, "importable": importable}
    return target, f"{module}:{qualname}"


def _resolve_target(target, local=None):
    """The build function of a target (in a worker: imported by module name, else from its file)."""
    if local is not None:
        return local
    if "preset" in target:
        from .presets import preset_module

        return preset_module(target["preset"]).build
    module = None
    try:
        module = importlib.import_module(target["module"])
        if target["file"] and Path(getattr(module, "__file__", "") or "").resolve() != Path(target["file"]).resolve():
            module = None
    except ImportError:
        module = None
    if module is None:
        if not target["file"]:
            raise ImportError(f"cannot import the build function {target['module']}:{target['qualname']}")
        digest = hashlib.sha256(target["file"].encode()).hexdigest()[:12]
        name = f"_rotorkit_sweep_build_{digest}"
        module = _load_file_module(name, target["file"])
    obj = module
    for part in target["qualname"].split("."):
        obj = getattr(obj, part)
    return obj


def _load_file_module(name, file):
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, file)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


# ---------------------------------------------------------------------------
# One point (runs in a worker process)
# ---------------------------------------------------------------------------


def point_path(out_dir, index):
    """Path of the file of point ``index`` in ``out_dir``."""
    return Path(out_dir) / f"point_{int(index):04d}.npz"


def _radial(result, station):
    """Radial displacement of a station (m), shape (n_samples,)."""
    return np.hypot(result[f"x{station}"], result[f"y{station}"])


def _runaway_limits(model, limit):
    """[(station, limit in m)]: every station at ``limit``, or by default each rub station at 10 x its clearance."""
    if limit is not None:
        return [(s, limit) for s in model.stations] if math.isfinite(limit) else []
    from .elements import RubStator

    return [(e.station, RUNAWAY_FACTOR * e.clearance) for e in model.elements
            if isinstance(e, RubStator) and e.clearance > 0]


def _first_runaway(result, limits):
    """(sample index, station, largest displacement, limit) of the earliest excursion past a limit, or None."""
    first = None
    for station, limit in limits:
        r = np.nan_to_num(_radial(result, station), nan=0.0)
        over = np.flatnonzero(r > limit)
        if over.size and (first is None or over[0] < first[0]):
            first = (int(over[0]), station, float(r.max()), limit)
    return first


def _json_default(value):
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return str(value)


def _write_point(path, meta, frequency, amplitude):
    from .files import atomic_write_bytes

    buf = io.BytesIO()
    np.savez(buf, meta=np.array(json.dumps(meta, default=_json_default)),
             frequency=np.asarray(frequency, dtype=float), amplitude=np.asarray(amplitude, dtype=float))
    atomic_write_bytes(path, buf.getvalue())


def _simulate_watched(system, t_end, options, limits):
    """Simulate 0..t_end; :func:`~rotorkit.simulate` stops a run-away past the smallest limit.

    Returns ``(result, error)``: the samples (a Result, or None) and the
    SimulationError that stopped the run, or None.
    """
    from .simulate import simulate

    bound = min((limit for _, limit in limits), default=None)
    try:
        return simulate(system, (0.0, t_end), bound=bound, **options), None
    except SimulationError as err:
        return err.partial, err


def _run_point(task, build=None):
    """Simulate one point and write its file; returns ``{index, value, status}``.

    ``task`` is plain data (see :func:`run_sweep`); ``build`` the build
    function when running in the calling process.
    """

    wall = _time.perf_counter()
    build = _resolve_target(task["target"], build)
    overrides = {k: _revive_override(v) for k, v in task["overrides"].items()}
    model = build(**overrides, **{task["parameter"]: task["value"]})
    system = model.compile(backend=task["backend"])
    limits = _runaway_limits(model, task["runaway_limit"])
    status, message, when = "ok", "", None
    result, err = _simulate_watched(system, task["t_end"], task["simulate_options"], limits)
    if err is not None:
        status, message, when = "failed", str(err), err.time
        if "run-away" in str(err).splitlines()[0]:
            status = "runaway"
    sampled = result is not None and result.t.size > 0
    max_disp, limit = None, min((lim for _, lim in limits), default=None)
    if sampled:
        radial = np.vstack([_radial(result, s) for s in model.stations])
        finite = radial[np.isfinite(radial)]
        max_disp = float(finite.max()) if finite.size else None
        if status == "ok" and not np.all(np.isfinite(result.y)):
            bad = int(np.argmax(~np.all(np.isfinite(result.y), axis=0)))
            status, message, when = "failed", f"non-finite states from t = {result.t[bad]:.6g} s", float(result.t[bad])
    runaway = _first_runaway(result, limits) if sampled else None
    if runaway is not None:
        index, station, peak, limit = runaway
        how = f" before the integration failed ({message.splitlines()[0]})" if status == "failed" else ""
        why = " (10 x its rub clearance)" if task["runaway_limit"] is None else ""
        status, when = "runaway", float(result.t[index])
        message = (f"station {station} passed the runaway limit {limit:.3g} m{why} at t = {when:.4g} s and reached "
                   f"{peak:.3g} m{how}: the response ran away (e.g. dry-friction whirl at high friction); no spectrum")
    frequency, amplitude, spectrum_info = np.empty(0), np.empty((len(task["signals"]), 0)), None
    if status == "ok":
        rows = []
        for name in task["signals"]:
            spectrum = result.spectrum(name, tuple(task["window"]), task["highpass_hz"])
            frequency = spectrum.frequency
            rows.append(spectrum.amplitude)
            spectrum_info = {"taper": spectrum.taper, "n_samples": spectrum.n_samples, "n_fft": spectrum.n_fft}
        amplitude = np.vstack(rows)
    stats = dict(result.stats) if result is not None else {}
    stats["point_wall_time"] = _time.perf_counter() - wall
    stats["pid"] = os.getpid()
    meta = {key: task[key] for key in ("fingerprint", "index", "parameter", "value", "window", "highpass_hz",
                                       "t_end", "signals")}
    meta.update(format=POINT_FORMAT, status=status, time=when, max_displacement=max_disp, runaway_limit=limit,
                message=message, spectrum=spectrum_info, stats=stats)
    _write_point(task["path"], meta, frequency, amplitude)
    return {"index": task["index"], "value": task["value"], "status": status}


def _read_point(path):
    """(meta, frequency, amplitude) of a point file, or None if missing or damaged."""
    try:
        with np.load(path, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            frequency = np.array(data["frequency"], dtype=float)
            amplitude = np.array(data["amplitude"], dtype=float)
    except Exception:  # missing, truncated or foreign: whatever it is, the point is recomputed
        return None
    if not isinstance(meta, dict) or meta.get("format") != POINT_FORMAT:
        return None
    status = meta.get("status")
    signals = meta.get("signals")
    if status not in STATUSES[:3] or not isinstance(signals, list) or amplitude.ndim != 2:
        return None
    if amplitude.shape != (len(signals), frequency.size):
        return None
    if status == "ok" and (frequency.size < 2 or not np.all(np.isfinite(amplitude))):
        return None
    return meta, frequency, amplitude


def _point_matches(meta, expected):
    for key in ("fingerprint", "parameter", "signals", "index"):
        if meta.get(key) != expected[key]:
            return False
    try:
        same_value = math.isclose(float(meta["value"]), expected["value"], rel_tol=1e-12, abs_tol=0.0)
        window = [float(v) for v in meta["window"]]
    except (KeyError, TypeError, ValueError):
        return False
    same_window = all(math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-15) for a, b in zip(window, expected["window"]))
    return same_value and same_window and len(window) == 2


# ---------------------------------------------------------------------------
# The sweep
# ---------------------------------------------------------------------------


def _check_values(name, values):
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        raise ParameterError(f"values={values!r}: expected a sequence of numbers for {name!r}")
    out = []
    for v in np.asarray(list(values), dtype=object).ravel():
        if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(float(v)):
            raise ParameterError(f"values for {name!r} contain {v!r}: expected finite numbers (SI)")
        out.append(float(v))
    if not out:
        raise ParameterError(f"values for {name!r} are empty: expected at least one value")
    _check_unique(out, f"values for {name!r}")
    return tuple(out)


def _check_window(window):
    try:
        start, end = (float(v) for v in window)
    except (TypeError, ValueError):
        raise ParameterError(f"window={window!r}: expected (t_start, t_end) in s") from None
    if not (math.isfinite(start) and math.isfinite(end) and 0.0 <= start < end):
        raise ParameterError(f"window={window!r}: expected 0 <= t_start < t_end (s)")
    return [start, end]


def _check_simulate_options(options, window):
    """(simulate keyword arguments as plain data, compile back end); the window must hold enough samples."""
    if options is None:
        options = {}
    if not isinstance(options, Mapping):
        raise TypeError(f"simulate_options={options!r}: expected a dict of rotorkit.simulate keyword arguments")
    unknown = sorted(set(options) - set(_SIMULATE_KEYS) - {"backend"})
    if unknown:
        raise TypeError(
            f"simulate_options has unknown keys {unknown}; allowed: {', '.join(_SIMULATE_KEYS)} and backend"
        )
    sample_rate = options.get("sample_rate", 10_000.0)
    if isinstance(sample_rate, numbers.Real) and (window[1] - window[0]) * sample_rate < 16:
        raise ParameterError(
            f"window={tuple(window)} holds fewer than 16 samples at sample_rate={sample_rate:g} Hz; "
            "widen the window or raise the sample rate"
        )
    options = dict(options)
    backend = options.pop("backend", "auto")
    return json.loads(json.dumps(options, default=_json_default)), backend


def _signal_parts(signal):
    return [s.strip() for s in signal.split("-", 1)] if "-" in signal else [signal]


def _check_signals(signals, default, model, who):
    states = set(model.coordinate_names) | {f"{c}_dot" for c in model.coordinate_names}
    if signals is None:
        if not default:
            raise ParameterError(f"{who} names no default output signals; pass signals=['x1', ...]")
        usable = [s for s in default if all(p in states for p in _signal_parts(s))]
        if not usable:
            raise ParameterError(f"none of the default signals {default} is a state of the model; pass signals=")
        return usable
    if isinstance(signals, str):
        signals = [signals]
    signals = list(signals)
    if not signals or len(set(signals)) != len(signals):
        raise ParameterError(f"signals={signals!r}: expected distinct signal names such as 'x2' or 'alpha2-alpha5'")
    for s in signals:
        if not isinstance(s, str) or not all(p in states for p in _signal_parts(s)):
            raise ParameterError(
                f"signal {s!r} is not a state of the model (or a difference 'a-b' of two): "
                f"states are {', '.join(sorted(states))}"
            )
    return signals


def _manifest_differences(old, new):
    out = []
    for key in sorted(set(old) | set(new)):
        if old.get(key) != new.get(key):
            a, b = json.dumps(old.get(key)), json.dumps(new.get(key))
            a, b = (s if len(s) < 80 else s[:77] + "..." for s in (a, b))
            out.append(f"{key}: {a} there, {b} here")
    return out


def _fingerprint(manifest):
    """Hash of everything but the values: a point file belongs to the sweep with this fingerprint."""
    text = json.dumps({k: v for k, v in manifest.items() if k != "values"}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def _check_manifest(out_dir, manifest):
    """True if ``out_dir`` holds this sweep's manifest, False if none; raises for another sweep's."""
    path = Path(out_dir) / MANIFEST_NAME
    if path.exists():
        try:
            old = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, ValueError) as exc:
            raise ParameterError(
                f"{path} is unreadable ({exc}); delete it (or the folder) to start the sweep over"
            ) from None
        if old != manifest:
            diffs = "; ".join(_manifest_differences(old if isinstance(old, dict) else {}, manifest))
            raise ParameterError(
                f"{out_dir} holds a different sweep ({diffs}); resuming needs the same preset, parameter, values, "
                "overrides, window, t_end, filter, signals and options. Use another out_dir, or delete the "
                "folder to start over"
            )
        return True
    return False


def _warm_up(model, backend, options):
    """Derive, generate and JIT-compile a structure once here, so workers load it from the disk caches."""
    from .simulate import simulate

    system = model.compile(backend=backend)
    try:
        simulate(system, (0.0, 1e-4), **{**options, "sample_rate": 1e5})
    except SimulationError:
        pass


def run_sweep(preset, name, values, *, out_dir, overrides=None, t_end=None, window=(2.2, 3.8), highpass_hz=5.0,
              signals=None, workers=2, progress=None, simulate_options=None, runaway_limit=None,
              start_method="spawn"):
    """Simulate a model at each value of one parameter and store the spectra per point.

    Parameters
    ----------
    preset : str or callable
        A preset name (``"al31f"``, see :func:`rotorkit.list_presets`), or a
        function ``build(**overrides) -> Model``. With ``workers > 1`` the
        function must be defined at module level (workers import it by
        module and name, or from the module's file). Defaults (``t_end``,
        ``bending`` and ``torsion`` signals) come from an ``OUTPUTS`` dict
        attribute of the function, else of its module (as in a preset file).
    name : str
        The swept parameter, passed to the build function (``rub_stiffness``).
    values : sequence of float, shape (n_values,)
        Its values (SI), distinct; e.g. from :func:`parse_range`.
    out_dir : str or pathlib.Path
        Folder of the manifest and the point files (created if missing).
    overrides : dict, optional
        Other build parameters, the same for every point (numbers, bools or
        pint quantities).
    t_end : float, optional
        Simulated time 0..t_end (s); default the preset's ``OUTPUTS["t_end"]``,
        else the window's end.
    window : (float, float)
        Time window of the spectra (s), inside ``[0, t_end]``; default the
        paper's ``(2.2, 3.8)``.
    highpass_hz : float or None
        Cut-off (Hz) of the zero-phase high-pass filter applied to the whole
        run before the window is taken; None for no filter.
    signals : sequence of str, optional
        Output signals (``"x2"``, ``"alpha2-alpha5"``); default the preset's
        ``OUTPUTS`` ``bending`` and ``torsion`` signals (those the model has).
    workers : int
        Worker processes (``1``: run in this process, one point after another).
    progress : callable, optional
        Called as ``progress(done, total, value, status)`` as each point
        finishes; ``status`` is ``"cached"`` for a point found valid on disk,
        else ``"ok"``, ``"failed"`` or ``"runaway"``.
    simulate_options : dict, optional
        Keyword arguments of :func:`rotorkit.simulate` (``method``, ``rtol``,
        ``atol``, ``sample_rate``, ``max_step``, ``engine``, ``time_limit``)
        and ``backend`` (of :meth:`Model.compile`).
    runaway_limit : float, optional
        Displacement (m) past which a point counts as run away; default: 10
        times the smallest rub clearance (no check without rub stators).
        ``math.inf`` disables the check. The integration stops there
        (``simulate(bound=...)``) instead of grinding on with a diverging
        response, which can take minutes.
    start_method : {"spawn", "forkserver", "fork"}
        How worker processes start. ``"spawn"`` (default) is safe everywhere;
        ``"fork"`` (POSIX) skips the workers' imports and JIT-cache loading,
        a few seconds per sweep, but is unsafe if the calling process runs
        threads.

    Returns
    -------
    Cascade
        :func:`load_sweep` of ``out_dir``.

    Raises
    ------
    ParameterError
        Bad arguments (checked, and every point's model built, before anything
        runs), or ``out_dir`` holding a different sweep.
    RotorkitError
        A point raised something other than a simulation failure (a bug), or
        a worker process died; finished points are kept for a resume.

    Notes
    -----
    A point whose integration fails or runs away does not stop the sweep:
    it is stored with its status, time and largest displacement. With the
    ``spawn`` start method, a script calling this must guard its entry point
    with ``if __name__ == "__main__":``.
    """
    out_dir = Path(out_dir)
    target, display, build, outputs = _build_target(preset, workers)
    if not isinstance(name, str) or not name.isidentifier():
        raise ParameterError(f"name={name!r}: expected the name of a parameter, e.g. 'rub_stiffness'")
    values = _check_values(name, values)
    plain_overrides = _check_overrides(overrides, name)
    window = _check_window(window)
    t_end = _positive(outputs.get("t_end", window[1]) if t_end is None else t_end, "t_end", "a duration > 0 (s)")
    if window[1] > t_end:
        raise ParameterError(f"window={tuple(window)} ends after t_end={t_end:g} s; the window must lie in [0, t_end]")
    if highpass_hz is not None:
        highpass_hz = _positive(highpass_hz, "highpass_hz", "a cut-off > 0 (Hz) or None")
    if isinstance(workers, bool) or not isinstance(workers, numbers.Integral) or workers < 1:
        raise ParameterError(f"workers={workers!r}: expected an integer >= 1")
    if progress is not None and not callable(progress):
        raise TypeError(f"progress={progress!r}: expected a callable progress(done, total, value, status)")
    options, backend = _check_simulate_options(simulate_options, window)
    if runaway_limit is not None:
        runaway_limit = _positive(runaway_limit, "runaway_limit", "a displacement > 0 (m) or None")
    _check_start_method(start_method, workers)

    # Every point's model, built here: bad names and values fail before anything runs.
    live = {k: _revive_override(v) for k, v in plain_overrides.items()}
    models = []
    for v in values:
        try:
            models.append(build(**live, **{name: v}))
        except ParameterError as err:
            raise type(err)(f"sweep point {name} = {v:g}: {err}") from err
    default_signals = [outputs[k] for k in ("bending", "torsion") if outputs.get(k)]
    signals = _check_signals(signals, default_signals, models[0], f"preset {display!r}")

    manifest = json.loads(json.dumps({
        "format": MANIFEST_FORMAT, "preset": display, "parameter": name, "values": list(values),
        "overrides": plain_overrides, "window": window, "t_end": t_end, "highpass_hz": highpass_hz,
        "signals": signals, "simulate_options": options, "backend": backend, "runaway_limit": runaway_limit,
    }))
    has_manifest = _check_manifest(out_dir, manifest)
    common = {"target": target, "fingerprint": _fingerprint(manifest), "parameter": name,
              **{k: manifest[k] for k in ("overrides", "t_end", "window", "highpass_hz", "signals",
                                          "simulate_options", "backend", "runaway_limit")}}

    total, done, tasks = len(values), 0, []
    for index, v in enumerate(values):
        task = {**common, "value": v, "index": index, "path": str(point_path(out_dir, index))}
        existing = _read_point(task["path"])
        if existing is not None and _point_matches(existing[0], task):
            done += 1
            if progress is not None:
                progress(done, total, v, "cached")
        else:
            tasks.append(task)

    seen = set()
    for task in tasks:  # derive and compile each structure once, here: workers load it from the disk caches
        model = models[task["index"]]
        if model.structure_key not in seen:
            seen.add(model.structure_key)
            _warm_up(model, backend, options)
    if not has_manifest:
        from .files import atomic_write_text

        atomic_write_text(out_dir / MANIFEST_NAME, json.dumps(manifest, indent=2) + "\n")
    if workers == 1 or len(tasks) == 1:
        local = None if "preset" in target else preset
        for task in tasks:
            summary = _guarded(_run_point, task, name, local)
            done += 1
            if progress is not None:
                progress(done, total, summary["value"], summary["status"])
    elif tasks:
        _run_pool(tasks, name, min(workers, len(tasks)), done, total, progress, start_method)
    return load_sweep(out_dir)


def _positive(value, name, expected):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value) or value <= 0:
        raise ParameterError(f"{name}={value!r}: expected {expected}")
    return float(value)


def _build_target(preset, workers):
    """(target as plain data, display name, build function, OUTPUTS) of a preset name or build callable."""
    target, display = _describe_target(preset)
    if "preset" in target:
        from .presets import preset_module

        module = preset_module(preset)
        outputs = getattr(module, "OUTPUTS", None)
        build = module.build
    else:
        outputs = getattr(preset, "OUTPUTS", None) or getattr(sys.modules.get(target["module"]), "OUTPUTS", None)
        build = preset
        if isinstance(workers, numbers.Integral) and workers > 1 and not target["importable"]:
            raise TypeError(
                f"preset={preset!r}: worker processes cannot import {display} (a lambda or a nested function); "
                "define the build function at module level, or use workers=1"
            )
    return target, display, build, outputs if isinstance(outputs, Mapping) else {}


def _check_overrides(overrides, name):
    if overrides is None:
        return {}
    if not isinstance(overrides, Mapping):
        raise TypeError(f"overrides={overrides!r}: expected a dict of build parameters")
    if name in overrides:
        raise ParameterError(f"{name!r} is both swept and in overrides; remove it from overrides")
    return {str(k): _plain_override(k, v) for k, v in overrides.items()}


def _check_start_method(start_method, workers):
    import multiprocessing

    methods = multiprocessing.get_all_start_methods()
    if start_method not in methods:
        raise ParameterError(f"start_method={start_method!r}: expected one of {', '.join(methods)}")
    main_file = getattr(sys.modules.get("__main__"), "__file__", None)
    if workers > 1 and start_method != "fork" and main_file and not os.path.exists(main_file):
        raise ParameterError(
            f"worker processes ({start_method!r} start) re-import the main module, and {main_file!r} is not a file "
            "(code run from stdin?); run it from a script file, or use workers=1 or start_method='fork'"
        )


def _guarded(func, task, name, local=None):
    try:
        return func(task, local)
    except Exception as exc:
        raise RotorkitError(
            f"sweep point {task['index']} ({name} = {task['value']:g}) raised {type(exc).__name__}: {exc}; "
            "the finished points are kept, run the sweep again to resume"
        ) from exc


def _run_pool(tasks, name, workers, done, total, progress, start_method):
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    pool = ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(start_method))
    try:
        futures = {pool.submit(_run_point, task): task for task in tasks}
        for future in as_completed(futures):
            task = futures[future]
            try:
                summary = future.result()
            except BrokenProcessPool as exc:
                raise RotorkitError(
                    f"a sweep worker process died (while computing {name} = {task['value']:g} or another point; "
                    "a script using worker processes must guard its entry point with "
                    "if __name__ == '__main__':); the finished points are kept, run the sweep again to resume"
                ) from exc
            except Exception as exc:
                raise RotorkitError(
                    f"sweep point {task['index']} ({name} = {task['value']:g}) raised {type(exc).__name__}: "
                    f"{exc}; the finished points are kept, run the sweep again to resume"
                ) from exc
            done += 1
            if progress is not None:
                progress(done, total, summary["value"], summary["status"])
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def load_sweep(out_dir):
    """Read a sweep folder written by :func:`run_sweep` into a :class:`Cascade`.

    Points without a valid file (not computed yet, or damaged) have status
    ``"missing"``; their rows, like those of failed points, are NaN.

    Raises
    ------
    ParameterError
        No readable ``sweep.json`` in ``out_dir``, or points whose spectra
        have different frequency grids.
    """
    out_dir = Path(out_dir)
    path = out_dir / MANIFEST_NAME
    try:
        manifest = json.loads(path.read_text(encoding="utf-8"))
        values = [float(v) for v in manifest["values"]]
        signals = list(manifest["signals"])
        parameter, window = manifest["parameter"], tuple(float(v) for v in manifest["window"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ParameterError(f"{out_dir} is not a sweep folder: cannot read {MANIFEST_NAME} ({exc})") from None
    if manifest.get("format") != MANIFEST_FORMAT:
        raise ParameterError(f"{path}: not a rotorkit sweep manifest (format {manifest.get('format')!r})")
    fingerprint = _fingerprint(manifest)
    n = len(values)
    status = np.full(n, "missing", dtype="<U8")
    failure_time = np.full(n, np.nan)
    max_disp = np.full(n, np.nan)
    messages = ["no valid point file yet"] * n
    frequency, rows, spectrum_info = None, {}, None
    for i, v in enumerate(values):
        point = _read_point(point_path(out_dir, i))
        expected = {"fingerprint": fingerprint, "parameter": parameter, "signals": signals, "index": i,
                    "value": v, "window": list(window)}
        if point is None or not _point_matches(point[0], expected):
            continue
        meta, freq, amp = point
        status[i] = meta["status"]
        messages[i] = meta.get("message") or ""
        if meta.get("time") is not None:
            failure_time[i] = float(meta["time"])
        if meta.get("max_displacement") is not None:
            max_disp[i] = float(meta["max_displacement"])
        if meta["status"] != "ok":
            continue
        if frequency is None:
            frequency, spectrum_info = freq, meta.get("spectrum")
        elif freq.shape != frequency.shape or not np.allclose(freq, frequency, rtol=1e-9, atol=0.0):
            raise ParameterError(
                f"{point_path(out_dir, i)}: its frequency grid differs from the other points' "
                f"({freq.size} vs {frequency.size} bins); all points must share the sample rate and window"
            )
        rows[i] = amp
    if frequency is None:
        frequency = np.empty(0)
    amplitude = {}
    for k, signal in enumerate(signals):
        table = np.full((n, frequency.size), np.nan)
        for i, amp in rows.items():
            table[i] = amp[k]
        amplitude[signal] = table
    return Cascade(parameter=parameter, values=np.array(values), frequency=np.array(frequency, dtype=float),
                   amplitude=amplitude, status=status, failure_time=failure_time, max_displacement=max_disp,
                   messages=tuple(messages), preset=str(manifest.get("preset", "")), window=window,
                   highpass_hz=manifest.get("highpass_hz"),
                   extra={**{k: manifest.get(k) for k in ("t_end", "overrides", "simulate_options")},
                          "spectrum": spectrum_info})
