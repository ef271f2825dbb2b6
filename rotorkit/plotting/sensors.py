"""Plots of sensor signals (:mod:`rotorkit.sensors`): probe orbit, time histories, waterfalls.

Every function draws on ``ax=`` or, without it, on pyplot's current axes (see :mod:`rotorkit.plotting.basic`)
and returns the Axes.
"""

import numpy as np

from .basic import legend_beside, new_axes

__all__ = ["plot_probe_orbit", "plot_sensor_signals", "plot_sensor_waterfall", "write_sensor_outputs"]

#: display unit and factor per SI unit of a sensor signal
DISPLAY = {"m": ("µm", 1e6), "rad/s": ("rpm", 60 / (2 * np.pi))}


def plot_probe_orbit(horizontal, vertical, ax=None, *, start=None, end=None, clearance=None):
    """The orbit a pair of probes records (vertical against horizontal, µm), as in the paper's Fig. 19.

    Parameters
    ----------
    horizontal, vertical : rotorkit.sensors.SensorSignal
        Two probes of the same rate, 90 degrees apart.
    start, end : float, optional
        Time window (s).
    clearance : float, optional
        Draw the stator clearance circle (m).
    """
    ax = new_axes(ax, figsize=(5.0, 5.0))
    a = horizontal.t[0] if start is None else start
    b = horizontal.t[-1] if end is None else end
    h, v = horizontal.window(a, b), vertical.window(a, b)
    ax.plot(h.values * 1e6, v.values * 1e6, lw=0.4)
    if clearance is not None:
        th = np.linspace(0, 2 * np.pi, 361)
        ax.plot(clearance * 1e6 * np.cos(th), clearance * 1e6 * np.sin(th), "k--", lw=0.8, label="clearance")
        legend_beside(ax)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"{horizontal.name} (µm)")
    ax.set_ylabel(f"{vertical.name} (µm)")
    ax.set_title(f"probe orbit, {a:g}-{b:g} s")
    return ax


def plot_sensor_signals(signals, ax=None, *, highpass=None):
    """Time histories of sensor signals of one unit (shown in µm or rpm), optionally high-passed (Hz)."""
    ax = new_axes(ax, figsize=(8.0, 3.5))
    signals = [signals] if hasattr(signals, "values") else list(signals)
    unit, factor = DISPLAY.get(signals[0].unit, (signals[0].unit, 1.0))
    for s in signals:
        s = s if highpass is None else s.highpass(highpass)
        ax.plot(s.t, s.values * factor, lw=0.5, label=f"{s.name} ({s.sample_rate:g} Hz)")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"{', '.join(s.name for s in signals)} ({unit})")
    legend_beside(ax)  # beside the data
    ax.set_title("sensor signals" + (f" (high-pass {highpass:g} Hz)" if highpass else ""))
    return ax


def plot_sensor_waterfall(signal, ax=None, *, highpass=2.0, segment=0.2, overlap=0.5, orders=None, fmax=None,
                          flat=False):
    """Time-frequency waterfall (or, ``flat=True``, spectrogram) of a sensor signal after the high-pass (Hz)."""
    from ..signals import stft
    from .spectra import plot_spectrogram, plot_waterfall

    s = signal if highpass is None else signal.highpass(highpass)
    unit, factor = DISPLAY.get(s.unit, (s.unit, 1.0))
    tf = stft(s.t, s.values, segment=segment, overlap=overlap)
    draw = plot_spectrogram if flat else plot_waterfall
    ax = draw(tf, ax=ax, orders=orders, fmax=fmax, scale=factor, amplitude_label=f"{s.name} amplitude ({unit})")
    what = "spectrogram" if flat else "short-time spectra"
    ax.set_title(f"{s.name}: {what}, {segment:g} s segments" + (f", high-pass {highpass:g} Hz" if highpass else ""),
                 fontsize=9)
    return ax


def write_sensor_outputs(measurement, outputs, out, save_figure):
    """Write a measurement's signals and the figures a preset's ``OUTPUTS`` asks for; return the paths.

    Keys read: ``orbit_probes`` (two probe names), ``sensor_plots`` (signal names, one figure each),
    ``waterfalls`` (signal names, one waterfall and one spectrogram each), ``highpass_hz``,
    ``clearance_parameter``, ``orders`` (``{label: frequency in rad/s}``), ``fmax`` (rad/s).
    """
    import io

    from ..files import atomic_write_bytes

    written = []
    buf = io.BytesIO()
    arrays = {}
    for name, s in measurement.signals.items():
        arrays[f"{name}_t"], arrays[name] = s.t, s.values
    arrays["units"] = np.array([f"{n}={s.unit}" for n, s in measurement.signals.items()])
    np.savez(buf, **arrays)
    atomic_write_bytes(out / "sensors.npz", buf.getvalue())
    written.append(out / "sensors.npz")
    hp = outputs.get("highpass_hz")
    result = measurement.result
    clearance = None if result is None else result.parameters.get(outputs.get("clearance_parameter", ""))
    probes = outputs.get("orbit_probes")
    if probes:
        ax = plot_probe_orbit(measurement[probes[0]], measurement[probes[1]], clearance=clearance)
        written.append(save_figure(ax.figure, out / "probe_orbit.png"))
    for name in outputs.get("sensor_plots", ()):
        ax = plot_sensor_signals(measurement[name])
        written.append(save_figure(ax.figure, out / f"{name}.png"))
    for name in outputs.get("waterfalls", ()):
        kw = dict(highpass=hp, orders=outputs.get("orders"), fmax=outputs.get("fmax"))
        ax = plot_sensor_waterfall(measurement[name], **kw)
        written.append(save_figure(ax.figure, out / f"waterfall_{name}.png"))
        ax = plot_sensor_waterfall(measurement[name], flat=True, **kw)
        written.append(save_figure(ax.figure, out / f"spectrogram_{name}.png"))
    return written
