"""Virtual sensors: what a probe or an encoder on the rig would record.

A sensor is a frozen dataclass naming *where* it sits (a station), *what* it
reads and *how* (its own sample rate, noise, resolution, anti-aliasing
filter). :func:`measure` simulates a system once and samples every sensor at
its own instants from the solver's dense output (not by resampling a
coarser grid); :func:`read_sensors` reads them from an existing
:class:`~rotorkit.Result` when, and only when, every instant a sensor needs
is one of the result's samples.

Sensors
-------
:class:`DisplacementProbe`
    An eddy-current probe: ``x cos(angle) + y sin(angle)`` of a station (m),
    optionally through an analog anti-aliasing Butterworth low-pass (emulated
    on an oversampled grid), plus Gaussian noise of a stated standard
    deviation (seeded) and quantisation to a resolution.
:class:`RotaryEncoder`
    The measured shaft speed ``omega = spin + alpha'`` at a station with a
    torsional coordinate (rad/s): instantaneous, or, with
    ``pulses_per_revolution``, counted: the pulses seen in each sample
    interval times ``2 pi / (N dt)`` (a mean speed over the interval).
:class:`Difference`
    A derived signal, ``a - b`` of two sensors with the same rate and unit,
    e.g. the paper's torsion measure ``delta_omega = omega_1 - omega_2``.

Examples
--------
>>> from rotorkit import Model, Rotor, Disk, ElasticSupport
>>> m = Model([Rotor(name="R", stations=(1,), speed=100.0),
...            Disk(station=1, mass=2.0, radius=0.1, eccentricity=1e-5),
...            ElasticSupport(station=1, stiffness=2e4, damping=4.0)])
>>> probe = DisplacementProbe(name="probe_x", station=1, direction="x", sample_rate=1000.0)
>>> out = measure(m.compile(backend="python"), (0.0, 0.1), [probe])
>>> out["probe_x"].values.shape, out["probe_x"].unit
((101,), 'm')
"""

import math
import numbers
from dataclasses import dataclass, field

import numpy as np

from .errors import ParameterError, TopologyError

__all__ = ["DisplacementProbe", "RotaryEncoder", "Difference", "SensorSignal", "Measurement", "measure",
           "read_sensors", "sensor_instants"]

#: a probe direction given by name -> angle from x towards y (rad)
DIRECTIONS = {"x": 0.0, "horizontal": 0.0, "y": math.pi / 2, "vertical": math.pi / 2}


def _rate(owner, value, name="sample_rate"):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{owner}: {name} = {value!r}: expected a rate in Hz (> 0)") from None
    if not (math.isfinite(v) and v > 0):
        raise ParameterError(f"{owner}: {name} = {value!r}: expected a finite rate in Hz (> 0)")
    return v


def _nonnegative(owner, value, name, unit):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{owner}: {name} = {value!r}: expected a number in {unit} (>= 0)") from None
    if not (math.isfinite(v) and v >= 0):
        raise ParameterError(f"{owner}: {name} = {value!r}: expected a finite number in {unit} (>= 0)")
    return v


def _si(owner, value, unit, name):
    if hasattr(value, "magnitude"):
        from .units import to_si

        return to_si(value, unit, f"{owner} {name}")
    return value


def _name(owner, name):
    if not isinstance(name, str) or not name.isidentifier():
        raise ParameterError(f"{owner}: name = {name!r}: expected an identifier, e.g. 'probe_h'")
    return name


def _station_known(sensor, model):
    if sensor.station not in model.stations:
        raise TopologyError(f"{type(sensor).__name__} {sensor.name!r}: station {sensor.station!r} is not a station "
                            f"of the model (stations: {', '.join(map(str, model.stations))})")


@dataclass(frozen=True)
class SensorSignal:
    """One sensor's record: samples at its own rate, with a unit.

    Attributes
    ----------
    name : str
        The sensor's name.
    t : numpy.ndarray
        Sample instants (s), shape (n,), uniform at ``sample_rate``.
    values : numpy.ndarray
        Samples in ``unit``, shape (n,).
    unit : str
        SI unit of ``values`` (``"m"``, ``"rad/s"``).
    sample_rate : float
        Hz.
    """

    name: str
    t: np.ndarray
    values: np.ndarray
    unit: str
    sample_rate: float

    def __post_init__(self):
        for a in (self.t, self.values):
            a.setflags(write=False)

    def highpass(self, cutoff=2.0, order=4):
        """The signal after the zero-phase Butterworth high-pass of :func:`rotorkit.signals.highpass`
        (``cutoff`` in Hz; the paper uses 2 Hz)."""
        from .signals import highpass

        return SensorSignal(self.name, self.t, highpass(self.t, self.values, cutoff, order), self.unit,
                            self.sample_rate)

    def spectrum(self, window=None, highpass=None, units="rad/s"):
        """Amplitude spectrum (in ``self.unit``) over ``window`` (s), after an optional high-pass (Hz)."""
        from .signals import amplitude_spectrum

        x = self if highpass is None else self.highpass(highpass)
        return amplitude_spectrum(x.t, x.values, window=window, units=units)

    def window(self, start, end):
        """The samples with ``start <= t <= end``."""
        keep = (self.t >= start) & (self.t <= end)
        return SensorSignal(self.name, self.t[keep].copy(), self.values[keep].copy(), self.unit, self.sample_rate)

    def to(self, unit):
        """The values converted to ``unit`` (e.g. ``"um"``, ``"rpm"``), a numpy array."""
        from .units import registry

        ureg = registry()
        return (self.values * ureg(self.unit)).to(unit).magnitude


@dataclass(frozen=True, slots=True, kw_only=True)
class DisplacementProbe:
    """A displacement (eddy-current) probe reading ``x cos(angle) + y sin(angle)`` at a station.

    Parameters
    ----------
    name : str
        Signal name.
    station : int or str
        Station the probe looks at.
    sample_rate : float
        Hz.
    direction : {"x", "y", "horizontal", "vertical"}, optional
        Shorthand for ``angle`` 0 or pi/2.
    angle : float or pint.Quantity, optional
        Measuring direction from x towards y (rad).
    noise : float or pint.Quantity
        Standard deviation of additive white Gaussian noise (m), after the filter.
    seed : int, optional
        Seed of the noise generator (same seed, same noise).
    resolution : float or pint.Quantity, optional
        Quantisation step of the recorded value (m).
    anti_aliasing : float or pint.Quantity, optional
        Cut-off (Hz) of an analog Butterworth low-pass of order ``filter_order``
        before sampling, ``|H(f)| = 1 / sqrt(1 + (f / cutoff)^(2 order))``;
        emulated causally on a grid ``oversampling`` times finer than the
        sensor's and then decimated. Must be below the sensor's Nyquist rate.
    filter_order : int
    oversampling : int
    """

    name: str
    station: int | str
    sample_rate: float
    direction: str | None = None
    angle: float | None = None
    noise: float = 0.0
    seed: int | None = None
    resolution: float | None = None
    anti_aliasing: float | None = None
    filter_order: int = 4
    oversampling: int = 8

    unit = "m"

    def __post_init__(self):
        who = f"DisplacementProbe {self.name!r}"
        _name(who, self.name)
        set_ = lambda f, v: object.__setattr__(self, f, v)  # noqa: E731
        set_("sample_rate", _rate(who, _si(who, self.sample_rate, "Hz", "sample_rate")))
        if (self.direction is None) == (self.angle is None):
            raise ParameterError(f"{who}: give exactly one of direction ('x', 'y', 'horizontal', 'vertical') "
                                 "or angle (rad)")
        if self.direction is not None:
            if self.direction not in DIRECTIONS:
                raise ParameterError(f"{who}: direction = {self.direction!r}: expected one of {sorted(DIRECTIONS)}")
            set_("angle", DIRECTIONS[self.direction])
        else:
            angle = _si(who, self.angle, "rad", "angle")
            if not isinstance(angle, numbers.Real) or not math.isfinite(angle):
                raise ParameterError(f"{who}: angle = {self.angle!r}: expected a finite angle in rad")
            set_("angle", float(angle))
        set_("noise", _nonnegative(who, _si(who, self.noise, "m", "noise"), "noise", "m"))
        if self.seed is not None and (not isinstance(self.seed, numbers.Integral) or isinstance(self.seed, bool)):
            raise ParameterError(f"{who}: seed = {self.seed!r}: expected an int or None")
        if self.resolution is not None:
            res = _nonnegative(who, _si(who, self.resolution, "m", "resolution"), "resolution", "m")
            if res == 0:
                raise ParameterError(f"{who}: resolution = 0: expected a step > 0 (m), or None for no quantisation")
            set_("resolution", res)
        for f in ("filter_order", "oversampling"):
            v = getattr(self, f)
            if not isinstance(v, numbers.Integral) or isinstance(v, bool) or not 1 <= v <= 64:
                raise ParameterError(f"{who}: {f} = {v!r}: expected an int in 1..64")
        if self.anti_aliasing is not None:
            fc = _rate(who, _si(who, self.anti_aliasing, "Hz", "anti_aliasing"), "anti_aliasing")
            if fc >= self.sample_rate / 2:
                raise ParameterError(f"{who}: anti_aliasing = {fc:g} Hz: the cut-off must be below the Nyquist "
                                     f"rate {self.sample_rate / 2:g} Hz of sample_rate {self.sample_rate:g} Hz")
            if self.oversampling < 4:
                raise ParameterError(f"{who}: oversampling = {self.oversampling}: the anti-aliasing filter needs "
                                     "at least 4 (8 recommended)")
            set_("anti_aliasing", fc)

    # -- the contract every sensor follows ---------------------------------
    def check(self, model):
        """Raise TopologyError if the model has no such station."""
        _station_known(self, model)

    def needs(self):
        """(rate of the instants this sensor reads, the state names it reads)."""
        rate = self.sample_rate * (self.oversampling if self.anti_aliasing is not None else 1)
        return rate, (f"x{self.station}", f"y{self.station}")

    def record(self, t, states, parameters, model):
        """The :class:`SensorSignal` from the states at the sensor's instants ``t`` (from :meth:`needs`)."""
        x = states[f"x{self.station}"] * math.cos(self.angle) + states[f"y{self.station}"] * math.sin(self.angle)
        if self.anti_aliasing is not None:
            from scipy.signal import butter, sosfilt, sosfilt_zi

            fast = self.sample_rate * self.oversampling
            sos = butter(self.filter_order, self.anti_aliasing, fs=fast, output="sos")
            x, _ = sosfilt(sos, x, zi=sosfilt_zi(sos) * x[0])  # at rest on the first value, like a settled filter
            t, x = t[:: self.oversampling], x[:: self.oversampling]
        if self.noise > 0:
            x = x + np.random.default_rng(self.seed).normal(0.0, self.noise, x.size)
        if self.resolution is not None:
            x = np.round(x / self.resolution) * self.resolution
        return SensorSignal(self.name, np.array(t), np.array(x, dtype=float), self.unit, self.sample_rate)


def _spin(model, parameters, station):
    """Spin speed (rad/s) of the station's rotor from the run's parameters."""
    rotor, factor = model.rotor_of(station), 1.0
    while rotor.speed is None:
        factor *= parameters[f"{rotor.name}_speed_ratio"]
        rotor = model.rotors[rotor.reference]
    return factor * parameters[f"{rotor.name}_speed"]


@dataclass(frozen=True, slots=True, kw_only=True)
class RotaryEncoder:
    """A rotary encoder reading the shaft speed ``omega = spin + alpha'`` (rad/s) at a station.

    Parameters
    ----------
    name : str
    station : int or str
        A station with a torsional coordinate (a ``Disk(torsion=True)``).
    sample_rate : float
        Hz.
    pulses_per_revolution : int, optional
        None: the instantaneous speed at each instant. N: a counting encoder,
        ``omega_k = (c_k - c_{k-1}) 2 pi / (N dt)`` with ``c = floor(N theta / 2 pi)``
        and ``theta = spin t + alpha``: the mean speed over each interval,
        resolved to ``2 pi / (N dt)``; samples start one interval after the start.
    """

    name: str
    station: int | str
    sample_rate: float
    pulses_per_revolution: int | None = None

    unit = "rad/s"

    def __post_init__(self):
        who = f"RotaryEncoder {self.name!r}"
        _name(who, self.name)
        object.__setattr__(self, "sample_rate", _rate(who, _si(who, self.sample_rate, "Hz", "sample_rate")))
        n = self.pulses_per_revolution
        if n is not None and (not isinstance(n, numbers.Integral) or isinstance(n, bool) or n < 1):
            raise ParameterError(f"{who}: pulses_per_revolution = {n!r}: expected an int >= 1, or None "
                                 "(instantaneous speed)")

    def check(self, model):
        """Raise TopologyError unless the station exists and has a torsional coordinate."""
        _station_known(self, model)
        if self.station not in model.torsion_stations:
            have = ", ".join(map(str, model.torsion_stations)) or "none"
            raise TopologyError(f"RotaryEncoder {self.name!r}: station {self.station!r} has no torsional coordinate "
                                f"alpha{self.station} (stations with one: {have}); put the encoder on a station "
                                "with a Disk(torsion=True)")

    def needs(self):
        return self.sample_rate, (f"alpha{self.station}", f"alpha{self.station}_dot")

    def record(self, t, states, parameters, model):
        spin = _spin(model, parameters, self.station)
        if self.pulses_per_revolution is None:
            omega = spin + states[f"alpha{self.station}_dot"]
            return SensorSignal(self.name, np.array(t), np.array(omega, dtype=float), self.unit, self.sample_rate)
        n = self.pulses_per_revolution
        theta = spin * t + states[f"alpha{self.station}"]
        counts = np.floor(theta * n / (2 * math.pi))
        omega = np.diff(counts) * 2 * math.pi / (n * np.diff(t))
        return SensorSignal(self.name, np.array(t[1:]), omega, self.unit, self.sample_rate)


@dataclass(frozen=True, slots=True, kw_only=True)
class Difference:
    """A derived signal ``minuend - subtrahend`` of two sensors of the same rate and unit.

    Examples
    --------
    >>> Difference(name="delta_omega", minuend="omega_1", subtrahend="omega_2").sources
    ('omega_1', 'omega_2')
    """

    name: str
    minuend: str
    subtrahend: str

    def __post_init__(self):
        who = f"Difference {self.name!r}"
        _name(who, self.name)
        for f in ("minuend", "subtrahend"):
            if not isinstance(getattr(self, f), str):
                raise ParameterError(f"{who}: {f} = {getattr(self, f)!r}: expected a sensor name")

    @property
    def sources(self):
        return (self.minuend, self.subtrahend)

    def combine(self, signals):
        missing = [s for s in self.sources if s not in signals]
        if missing:
            raise ParameterError(f"Difference {self.name!r}: no sensor named {missing[0]!r} "
                                 f"(sensors: {', '.join(signals)})")
        a, b = signals[self.minuend], signals[self.subtrahend]
        if a.unit != b.unit or a.sample_rate != b.sample_rate or a.t.shape != b.t.shape:
            raise ParameterError(f"Difference {self.name!r}: {a.name!r} ({a.sample_rate:g} Hz, {a.unit}) and "
                                 f"{b.name!r} ({b.sample_rate:g} Hz, {b.unit}) must share rate and unit")
        return SensorSignal(self.name, a.t, a.values - b.values, a.unit, a.sample_rate)


@dataclass(frozen=True)
class Measurement:
    """What :func:`measure` returns: the sensor signals by name, and the states on a uniform grid.

    Attributes
    ----------
    signals : dict
        Sensor name -> :class:`SensorSignal`.
    result : rotorkit.Result or None
        The states at ``sample_rate`` (when :func:`measure` was given one).
    """

    signals: dict
    result: object = None
    sensors: tuple = field(default=())

    def __getitem__(self, name):
        try:
            return self.signals[name]
        except KeyError:
            raise ParameterError(f"no sensor signal {name!r}; signals: {', '.join(self.signals)}") from None

    def __contains__(self, name):
        return name in self.signals


def _split(sensors):
    direct = [s for s in sensors if not isinstance(s, Difference)]
    derived = [s for s in sensors if isinstance(s, Difference)]
    names = [s.name for s in sensors]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ParameterError(f"two sensors are named {dup[0]!r}; give each a distinct name")
    for s in sensors:
        if not isinstance(s, (DisplacementProbe, RotaryEncoder, Difference)):
            raise ParameterError(f"{s!r} is not a sensor (DisplacementProbe, RotaryEncoder, Difference)")
    return direct, derived


def sensor_instants(sensor, t0, t1):
    """The instants (s) at which ``sensor`` reads the states over ``[t0, t1]``."""
    rate = sensor.needs()[0]
    n = int(math.floor((t1 - t0) * rate * (1 + 1e-12))) + 1
    return t0 + np.arange(n) / rate


def _finish(direct, derived, raw):
    signals = dict(raw)
    for d in derived:
        signals[d.name] = d.combine(signals)
    return {s.name: signals[s.name] for s in (*direct, *derived)}


def measure(system, t_span, sensors, *, sample_rate=None, **options):
    """Simulate ``system`` and record ``sensors``, each sampled at its own instants from dense output.

    Parameters
    ----------
    system : rotorkit.System
    t_span : (float, float)
        s.
    sensors : sequence of DisplacementProbe, RotaryEncoder, Difference
    sample_rate : float, optional
        Also keep the states on this uniform grid (Hz) as ``.result``.
    **options
        Passed to :func:`rotorkit.simulate` (method, rtol, atol, bound, ...).

    Returns
    -------
    Measurement
    """
    from .result import Result
    from .simulate import simulate

    sensors = tuple(sensors)
    direct, derived = _split(sensors)
    for s in direct:
        s.check(system.model)
    try:
        t0, t1 = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise ParameterError(f"t_span={t_span!r}: expected (start, end) in s") from None
    if not t1 > t0:
        raise ParameterError(f"t_span={t_span!r}: the end time must be after the start time")
    grids = [sensor_instants(s, t0, t1) for s in direct]
    if sample_rate is not None:
        from .simulate import uniform_times

        grids.append(uniform_times(t0, t1, _rate("measure", sample_rate)))
    times, inverse = np.unique(np.concatenate(grids), return_inverse=True)
    result = simulate(system, (t0, t1), sample_times=times, **options)
    offsets = np.cumsum([0] + [g.size for g in grids])
    raw = {}
    for k, s in enumerate(direct):
        cols = inverse[offsets[k]:offsets[k + 1]]
        states = {n: result.y[result.state_names.index(n), cols] for n in s.needs()[1]}
        raw[s.name] = s.record(grids[k], states, result.parameters, system.model)
    grid_result = None
    if sample_rate is not None:
        cols = inverse[offsets[-2]:offsets[-1]]
        grid_result = Result(t=grids[-1].copy(), y=result.y[:, cols].copy(), state_names=result.state_names,
                             parameters=result.parameters, stats=result.stats, name=result.name)
    return Measurement(signals=_finish(direct, derived, raw), result=grid_result, sensors=sensors)


def read_sensors(result, sensors, model):
    """Record ``sensors`` from an existing result's samples (no new simulation).

    Every instant a sensor needs must be one of the result's samples (to
    1e-9 s): a result holds no dense output, so rotorkit cannot give a
    sensor more than the result has; use :func:`measure` for that.

    Raises
    ------
    ParameterError
        A sensor's rate (with its oversampling) is above the result's sample
        rate or its instants are not on the result's grid.
    """
    sensors = tuple(sensors)
    direct, derived = _split(sensors)
    t = result.t
    raw = {}
    for s in direct:
        s.check(model)
        need = sensor_instants(s, float(t[0]), float(t[-1]))
        idx = np.clip(np.searchsorted(t, need), 0, t.size - 1)
        left = np.clip(idx - 1, 0, t.size - 1)
        idx = np.where(np.abs(t[left] - need) < np.abs(t[idx] - need), left, idx)
        if np.max(np.abs(t[idx] - need)) > 1e-9:
            rate = s.needs()[0]
            raise ParameterError(
                f"{type(s).__name__} {s.name!r} reads at {rate:g} Hz but the result holds samples at "
                f"{result.sample_rate:g} Hz, not on that sensor's instants: a result has no dense output, so it "
                "cannot give more. Use rotorkit.sensors.measure(system, t_span, sensors), which samples every "
                "sensor from the solver's dense output, or simulate at a sample_rate that is a multiple of "
                f"{rate:g} Hz")
        states = {n: result[n][idx] for n in s.needs()[1]}
        raw[s.name] = s.record(need, states, result.parameters, model)
    return _finish(direct, derived, raw)
