"""The textbook two-disk rotor as beam finite elements: Campbell diagram and first modes.

A 1.5 m steel shaft of 50 mm diameter in 6 equal Timoshenko elements, two
disks (70 mm wide, 50/280 mm inner/outer diameter) at 0.5 m and 1.0 m, and
bearings at both ends with kxx = 1 MN/m, kyy = 0.8 MN/m (undamped); the
example of Friswell et al., *Dynamics of Rotating Machines* (2010), ch. 5-6.

    python examples/two_disk_rotor.py --out figures/

prints the whirl frequencies against speed and writes ``campbell.png`` and
``modes.png``, calling the library's ``campbell`` and ``linear_model``. The
bearings are ``LinearBearing``s with the direct stiffnesses only (the cross-coupled and damping coefficients left out add
no terms).
"""

import argparse
from pathlib import Path

import numpy as np

import rotorkit as rk


def two_disk_rotor(speed=0.0):
    """Stations 1..7 every 0.25 m; disks at 3 (0.5 m) and 5 (1.0 m); bearings at 1 and 7."""
    steel = rk.Material.steel()
    stations = tuple(range(1, 8))
    elements = [rk.Rotor(name="R", stations=stations, speed=speed)]
    elements += [rk.BeamSegment(start=s, end=s + 1, length=0.25, outer_diameter=0.05, material=steel,
                                theory="timoshenko") for s in stations[:-1]]
    elements += [rk.Disk.from_geometry(station=s, width=0.07, inner_diameter=0.05, outer_diameter=0.28,
                                       material=steel) for s in (3, 5)]
    elements += [rk.LinearBearing(station=s, kxx=1e6, kyy=0.8e6) for s in (1, 7)]
    return rk.Model(elements, name="two_disk_rotor")


LABEL = {"forward": "F", "backward": "B", "linear": "L", "mixed": "M"}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("two_disk_rotor_figures"), help="folder for the figures")
    parser.add_argument("--max-rpm", type=float, default=4000.0, help="highest speed of the Campbell diagram (rpm)")
    args = parser.parse_args(argv)
    model = two_disk_rotor()
    print(model)
    rpm = np.linspace(0.0, args.max_rpm, 41)
    diagram = rk.campbell(model, rpm * np.pi / 30, n_modes=6)  # the library's Campbell diagram (rad/s)
    print("speed (rpm) | whirl frequencies (Hz), F forward / B backward (L: linear whirl at rest)")
    for i in range(0, rpm.size, 10):
        cells = [f"{f / (2 * np.pi):7.2f}{LABEL[w]}" for f, w in zip(diagram.frequencies[i], diagram.whirl[i])]
        print(f"{rpm[i]:10.0f} | " + "  ".join(cells))
    print(diagram.table(units="rpm"))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    args.out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    diagram.plot(ax=ax, units="rpm", frequency_units="Hz")
    ax.set_title("Two-disk rotor: Campbell diagram")
    fig.savefig(args.out / "campbell.png", dpi=120, bbox_inches="tight")
    print("wrote", args.out / "campbell.png")

    linear = rk.linear_model(model.compile())
    modes = linear.modes(0.0, n_modes=4)
    z = 0.25 * np.arange(7)
    fig, axes = plt.subplots(2, 2, figsize=(8, 5), sharex=True)
    names = model.coordinate_names
    for i, ax in enumerate(axes.flat):
        shape = modes.shapes[:, i]
        x = np.array([shape[names.index(f"x{s}")] for s in model.stations])
        y = np.array([shape[names.index(f"y{s}")] for s in model.stations])
        main_axis = x if np.max(np.abs(x)) > np.max(np.abs(y)) else y
        phase = main_axis[np.argmax(np.abs(main_axis))]
        ax.plot(z, np.real(x / phase), "o-", label="x")
        ax.plot(z, np.real(y / phase), "s--", label="y")
        ax.set_title(f"mode {i + 1}: {modes.frequencies[i] / (2 * np.pi):.2f} Hz at 0 rpm")
        ax.axhline(0, color="k", lw=0.5)
    axes[0, 0].legend()
    for ax in axes[1]:
        ax.set_xlabel("axial position (m)")
    fig.tight_layout()
    fig.savefig(args.out / "modes.png", dpi=120, bbox_inches="tight")
    print("wrote", args.out / "modes.png")


if __name__ == "__main__":
    main()
