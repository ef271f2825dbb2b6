"""Regenerate the figures of the rub-impact dual-rotor paper (Figs. 7-16) from the AL-31F preset.

    python examples/paper_figures.py                # all figures into paper-figures/
    python examples/paper_figures.py --figs 7 8 11  # some of them
    python examples/paper_figures.py --out DIR --points 40

Fig. 7  manoeuvre load and gravity on disk 2
Fig. 8  axis orbit of disk 2 without rub
Fig. 9  waterfalls (bending x2, torsion alpha2-alpha5) without rub
Fig. 10-12  waterfalls at k_r = 2e6, 8e6, 1.4e7 N/m
Fig. 13-15  spectrum cascades over k_r (5e5-2e7 N/m), friction (0-0.3), LP speed (500-3000 rad/s)
Fig. 16  waterfalls at omega_low = 1800 rad/s
0        (not in the paper) Campbell diagram over the LP speed, with the 1x LP and HP lines

Each waterfall is also drawn as a 2-D spectrogram (fig*_spectrogram_*.png).

Spectra follow the paper: a zero-phase high-pass (5 Hz) removes the slow
manoeuvre offset; cascades use t in [2.2, 3.8] s; waterfalls are short-time
spectra over the whole run. Order lines mark 1/2, 1, 5/4, 3/2 omega_low,
omega_high and omega_high - omega_low.
"""

import argparse
from pathlib import Path

import numpy as np

import rotorkit as rk
from rotorkit.analysis.loads import maneuver_load
from rotorkit.signals import highpass, stft
from rotorkit.plotting.spectra import plot_cascade, plot_spectrogram, plot_waterfall, speed_orders
from rotorkit.sweep import Cascade, run_sweep

SIGNALS = {"bending": ("x2", 1e6, "x2 (µm)"), "torsion": ("alpha2-alpha5", 1e6, "alpha2 - alpha5 (µrad)")}


def save(fig, path):
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def fig7(out, **_):
    load = maneuver_load(rk.preset("al31f"), 2, np.linspace(0.0, 6.0, 3001))
    ax = load.plot()
    ax.set_title("Fig. 7: manoeuvre load and gravity on disk 2")
    save(ax.figure, out / "fig07_load_disk2.png")


def fig8(out, **_):
    result = rk.simulate(rk.preset("al31f", rub=False).compile(), (0.0, 6.0))
    ax = result.plot_orbit(2)
    ax.set_title("Fig. 8: axis orbit of disk 2, no rub")
    save(ax.figure, out / "fig08_orbit_disk2.png")


def waterfalls(out, name, title, **overrides):
    from matplotlib.figure import Figure

    result = rk.simulate(rk.preset("al31f", **overrides).compile(), (0.0, 6.0))
    speed = overrides.get("lp_speed", 1500.0)
    fig = Figure(figsize=(13, 5.5), layout="constrained")
    flat = Figure(figsize=(13, 4.5), layout="constrained")  # the same as 2-D spectrograms
    for k, (role, (signal, scale, label)) in enumerate(SIGNALS.items()):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        x = highpass(result.t, result[signal], 5.0)
        tf = stft(result.t, x, segment=0.2, overlap=0.5)
        plot_waterfall(tf, ax=ax, orders=speed_orders(speed, 1.8), fmax=5000.0, scale=scale,
                       amplitude_label=label)
        ax.set_title(f"({'ab'[k]}) {role}")
        ax2 = flat.add_subplot(1, 2, k + 1)
        plot_spectrogram(tf, ax=ax2, orders=speed_orders(speed, 1.8), fmax=5000.0, scale=scale,
                         amplitude_label=label)
        ax2.set_title(f"({'ab'[k]}) {role}")
    fig.suptitle(title)
    flat.suptitle(title + " (spectrogram)")
    save(fig, out / name)
    save(flat, out / name.replace("waterfall", "spectrogram"))


def fig9(out, **_):
    waterfalls(out, "fig09_waterfall_no_rub.png", "Fig. 9: no rub", rub=False)


def fig10(out, **_):
    waterfalls(out, "fig10_waterfall_kr2e6.png", "Fig. 10: k_r = 2e6 N/m", rub_stiffness=2e6)


def fig11(out, **_):
    waterfalls(out, "fig11_waterfall_kr8e6.png", "Fig. 11: k_r = 8e6 N/m", rub_stiffness=8e6)


def fig12(out, **_):
    waterfalls(out, "fig12_waterfall_kr1.4e7.png", "Fig. 12: k_r = 1.4e7 N/m", rub_stiffness=1.4e7)


def fig16(out, **_):
    waterfalls(out, "fig16_waterfall_speed1800.png", "Fig. 16: omega_low = 1800 rad/s", lp_speed=1800.0)


def cascades(out, name, title, parameter, values, orders, workers):
    from matplotlib.figure import Figure

    cascade = Cascade.from_dataset(run_sweep("al31f", parameter, values, out_dir=out / f"sweep-{parameter}",
                                             workers=workers, progress=lambda event: print(f"  {event}")))
    fig = Figure(figsize=(13, 5.5), layout="constrained")
    for k, (role, (signal, scale, label)) in enumerate(SIGNALS.items()):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        plot_cascade(cascade, signal, ax=ax, orders=orders, fmax=5000.0, scale=scale, amplitude_label=label)
        ax.set_title(f"({'ab'[k]}) {role}")
    fig.suptitle(title)
    save(fig, out / name)


def fig13(out, points, workers):
    cascades(out, "fig13_cascade_kr.png", "Fig. 13: k_r from 5e5 to 2e7 N/m", "rub_stiffness",
             tuple(np.linspace(5e5, 2e7, points)), speed_orders(1500.0, 1.8), workers)


def fig14(out, points, workers):
    cascades(out, "fig14_cascade_friction.png", "Fig. 14: friction coefficient 0-0.3", "friction_coefficient",
             tuple(np.linspace(0.0, 0.3, max(points // 2, 4))), speed_orders(1500.0, 1.8), workers)


def fig15(out, points, workers):
    cascades(out, "fig15_cascade_speed.png", "Fig. 15: LP speed 500-3000 rad/s", "lp_speed",
             tuple(np.linspace(500.0, 3000.0, points)), lambda w: speed_orders(w, 1.8), workers)


def campbell(out, **_):
    """Campbell and stability diagrams over the LP speed (HP at 1.8 x LP), contacts linearised at each speed.

    The Hertzian intershaft bearing is linearised at every speed (cage
    positions averaged); the rub contact is engaged along the gravity sag, so
    its friction coupling shows in the log decrements.
    """
    from rotorkit.linear.campbell import campbell as campbell_diagram

    diagram = campbell_diagram(rk.preset("al31f"), np.linspace(200.0, 3000.0, 15), n_modes=6, rub_engaged=True)
    print(diagram.table())
    ax = diagram.plot()
    ax.set_title("Campbell diagram, gravity-loaded AL-31F model, rub engaged along the sag", fontsize=9)
    save(ax.figure, out / "campbell.png")
    ax = diagram.plot_stability()
    ax.set_title("Stability diagram, AL-31F model, rub engaged along the sag", fontsize=9)
    save(ax.figure, out / "campbell_stability.png")


FIGURES = {0: campbell, 7: fig7, 8: fig8, 9: fig9, 10: fig10, 11: fig11, 12: fig12, 13: fig13, 14: fig14, 15: fig15, 16: fig16}


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--figs", type=int, nargs="*", default=sorted(FIGURES))
    parser.add_argument("--out", default="paper-figures")
    parser.add_argument("--points", type=int, default=40, help="points of the k_r and speed cascades")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for number in args.figs:
        FIGURES[number](out, points=args.points, workers=args.workers)
