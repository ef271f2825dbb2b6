"""Regenerate the analogues of the paper's experimental Figs. 19-22 from the `rig` preset and its sensors.

    python examples/rig_figures.py                  # all figures into rig-figures/
    python examples/rig_figures.py --out DIR
    python examples/rig_figures.py --clearance      # re-measure how the clearance was chosen

Fig. 19  probe orbit (probe_v against probe_h), before, during and after the roll
Fig. 20  time histories: (a) bending (probe_v), (b) torsion (delta_omega = omega_1 - omega_2)
Fig. 21  waterfalls of (a) probe_v and (b) delta_omega, > 2 Hz high-pass (and 2-D spectrograms)
Fig. 22  spectra of delta_omega over 1.0-1.2 s (steady) and 2.5-2.7 s (roll), in rpm

Every signal is what the rig's virtual sensors record (rotorkit.sensors): the
probes at 2,000 Hz, the encoders at 12,800 Hz, each sampled from the solver's
dense output at its own instants; the paper's 2 Hz high-pass comes before
every spectrum.
"""

import argparse
from pathlib import Path

import numpy as np

import rotorkit as rk
from rotorkit.plotting.sensors import plot_probe_orbit, plot_sensor_signals, plot_sensor_waterfall
from rotorkit.plotting.spectra import plot_spectrum
from rotorkit.presets import preset_module
from rotorkit.sensors import measure
from rotorkit.validation import initial_state

RPM = 60 / (2 * np.pi)


def save(fig, path):
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def run(**overrides):
    module = preset_module("rig")
    system = rk.preset("rig", **overrides).compile()
    return measure(system, (0.0, 6.0), module.SENSORS, sample_rate=2000.0, y0=initial_state(system, "equilibrium"))


def clearance_check():
    """The disk's largest radial displacement without the stator: steady (0-2 s) and during the roll (2-4 s)."""
    system = rk.preset("rig", rub=False).compile()
    result = rk.simulate(system, (0.0, 6.0), sample_rate=4000.0, y0=initial_state(system, "equilibrium"))
    r = np.hypot(result["x2"], result["y2"])
    for a, b, what in ((0.0, 2.0, "steady"), (2.0, 4.0, "roll"), (4.0, 6.0, "after the roll")):
        keep = (result.t >= a) & (result.t < b)
        print(f"no stator, {what:15s} {a:g}-{b:g} s: largest radial displacement of the disk "
              f"{1e3 * r[keep].max():.4f} mm")
    print(f"clearance of the preset: {1e3 * preset_module('rig').DEFAULTS['rub_clearance']:.3g} mm")


def figures(out):
    from matplotlib.figure import Figure

    module = preset_module("rig")
    m = run()
    clearance = module.DEFAULTS["rub_clearance"]
    speed = module.DEFAULTS["speed"]
    orders = {"1/2 omega": speed / 2, "omega": speed, "2 omega": 2 * speed}

    fig = Figure(figsize=(13, 4.5), layout="constrained")
    for k, (a, b, what) in enumerate(((0.0, 2.0, "steady, 0-2 s"), (2.0, 4.0, "roll, 2-4 s"),
                                      (4.0, 6.0, "steady again, 4-6 s"))):
        ax = plot_probe_orbit(m["probe_h"], m["probe_v"], ax=fig.add_subplot(1, 3, k + 1), start=a, end=b,
                              clearance=clearance)
        ax.set_title(what)
    fig.suptitle("Fig. 19 analogue: probe orbit of the rig (eddy-current probes at the disk, 2,000 Hz)")
    save(fig, out / "fig19_probe_orbit.png")

    fig = Figure(figsize=(10, 6), layout="constrained")
    ax = plot_sensor_signals(m["probe_v"], ax=fig.add_subplot(2, 1, 1))
    ax.set_title("(a) bending: vertical probe")
    ax = plot_sensor_signals(m["delta_omega"], ax=fig.add_subplot(2, 1, 2), highpass=2.0)
    ax.set_title("(b) torsion: delta_omega = omega_1 - omega_2 (> 2 Hz)")
    fig.suptitle("Fig. 20 analogue: time histories")
    save(fig, out / "fig20_time_histories.png")

    for flat, name in ((False, "fig21_waterfalls.png"), (True, "fig21_spectrograms.png")):
        fig = Figure(figsize=(13, 5.5 if not flat else 4.5), layout="constrained")
        for k, (signal, title) in enumerate((("probe_v", "(a) bending"), ("delta_omega", "(b) torsion"))):
            ax = fig.add_subplot(1, 2, k + 1, **({} if flat else {"projection": "3d"}))
            plot_sensor_waterfall(m[signal], ax=ax, highpass=2.0, orders=orders, fmax=1000.0, flat=flat)
            ax.set_title(f"{title}: {signal}")
        fig.suptitle("Fig. 21 analogue: time-frequency " + ("spectrograms" if flat else "waterfalls"))
        save(fig, out / name)

    fig = Figure(figsize=(11, 4), layout="constrained")
    d = m["delta_omega"].highpass(2.0)
    for k, (span, what) in enumerate((((1.0, 1.2), "(a) steady, 1.0-1.2 s"), ((2.5, 2.7), "(b) roll, 2.5-2.7 s"))):
        spectrum = d.spectrum(span)
        ax = plot_spectrum(spectrum, ax=fig.add_subplot(1, 2, k + 1), orders=orders, fmax=1000.0, scale=RPM,
                           amplitude_label="delta_omega (rpm)")
        near = np.abs(spectrum.frequency - speed) <= 0.02 * speed
        ax.set_title(f"{what}: omega at {RPM * spectrum.amplitude[near].max():.3g} rpm")
        print(f"delta_omega spectrum {span[0]:g}-{span[1]:g} s: omega at {RPM * spectrum.amplitude[near].max():.3g} rpm")
    fig.suptitle("Fig. 22 analogue: spectra of the torsional response (paper: 1.016 -> 8.328 rpm)")
    save(fig, out / "fig22_delta_omega_spectra.png")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="rig-figures", help="output folder")
    parser.add_argument("--clearance", action="store_true", help="only re-measure the clearance choice")
    args = parser.parse_args(argv)
    if args.clearance:
        clearance_check()
        return
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    figures(out)


if __name__ == "__main__":
    main()
