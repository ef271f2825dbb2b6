"""The textbook two-disk rotor as beam finite elements: Campbell diagram and first modes.

A 1.5 m steel shaft of 50 mm diameter in 6 equal Timoshenko elements, two
disks (70 mm wide, 50/280 mm inner/outer diameter) at 0.5 m and 1.0 m, and
bearings at both ends with kxx = 1 MN/m, kyy = 0.8 MN/m (undamped); the
example of Friswell et al., *Dynamics of Rotating Machines* (2010), ch. 5-6.

    python examples/two_disk_rotor.py --out figures/

prints the whirl frequencies against speed and writes ``campbell.png`` and
``modes.png``. The bearings are ``LinearBearing``s with the direct
stiffnesses only (the cross-coupled and damping coefficients left out add
no terms).
"""

import argparse
from pathlib import Path

import numpy as np
import sympy as sp

from rotorkit import Model, Rotor
from rotorkit.elements import BeamSegment, Disk, LinearBearing, Material


def two_disk_rotor(speed=0.0):
    """Stations 1..7 every 0.25 m; disks at 3 (0.5 m) and 5 (1.0 m); bearings at 1 and 7."""
    steel = Material.steel()
    stations = tuple(range(1, 8))
    elements = [Rotor(name="R", stations=stations, speed=speed)]
    elements += [BeamSegment(start=s, end=s + 1, length=0.25, outer_diameter=0.05, material=steel,
                             theory="timoshenko") for s in stations[:-1]]
    elements += [Disk.from_geometry(station=s, width=0.07, inner_diameter=0.05, outer_diameter=0.28, material=steel)
                 for s in (3, 5)]
    elements += [LinearBearing(station=s, kxx=1e6, kyy=0.8e6) for s in (1, 7)]
    return Model(elements, name="two_disk_rotor")


def linear_matrices(model):
    """Functions of the rotor speed giving (M, K, G) of ``M q'' + G q' + K q = 0``."""
    eom = model.equations()
    speed = next(p for p in eom.parameters if str(p) == "R_speed")
    others = [p for p in eom.parameters if p is not speed]
    values = [model.parameters[str(p)] for p in others]
    zero = {s: 0 for s in eom.coordinates + eom.speeds}
    f = eom.forcing.subs(eom.t, 0)
    M = np.array(sp.lambdify(others, sp.Matrix(eom.mass_matrix).subs(zero))(*values), dtype=float)
    K = -np.array(sp.lambdify(others + [speed], f.jacobian(eom.coordinates).subs(zero))(*values, 0.0), dtype=float)
    G_of = sp.lambdify(others + [speed], -f.jacobian(eom.speeds).subs(zero))
    return M, K, lambda w: np.array(G_of(*values, w), dtype=float)


def whirl(M, K, G, n_modes=6):
    """(frequencies rad/s, forward?) of the first modes: eigenvalues of the first-order form."""
    n = len(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K), -np.linalg.solve(M, G)]])
    lam, vec = np.linalg.eig(A)
    keep = np.argsort(lam.imag)
    keep = [i for i in keep if lam[i].imag > 1e-6][:n_modes]
    return lam[keep].imag, vec[:n, keep]


def forward(model, shape):
    """Forward whirl at the node of largest motion? (x leads y by 90 deg: x = cos wt, y = sin wt).

    The mode shape v of the eigenvalue i w means q = Re(v e^{i w t}); forward
    whirl has v_y = -i v_x, i.e. Im(conj(v_x) v_y) < 0.
    """
    names = model.coordinate_names
    best, sense = 0.0, 0.0
    for s in model.stations:
        x, y = shape[names.index(f"x{s}")], shape[names.index(f"y{s}")]
        amplitude = abs(x) + abs(y)
        if amplitude > best:
            best, sense = amplitude, np.imag(np.conj(x) * y)
    return sense < 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path("two_disk_rotor_figures"), help="folder for the figures")
    parser.add_argument("--max-rpm", type=float, default=4000.0, help="highest speed of the Campbell diagram (rpm)")
    args = parser.parse_args(argv)
    model = two_disk_rotor()
    print(model)
    M, K, G_of = linear_matrices(model)
    rpm = np.linspace(0.0, args.max_rpm, 41)
    table = []
    for r in rpm:
        w, shapes = whirl(M, K, G_of(r * np.pi / 30))
        table.append((w / (2 * np.pi), [forward(model, shapes[:, i]) for i in range(len(w))]))
    print("speed (rpm) | whirl frequencies (Hz), F forward / B backward")
    for r, (f, fw) in zip(rpm[::10], table[::10]):
        print(f"{r:10.0f} | " + "  ".join(f"{v:7.2f}{'F' if d else 'B'}" for v, d in zip(f, fw)))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    args.out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(6, 4.5))
    freqs = np.array([f for f, _ in table])
    dirs = np.array([d for _, d in table])
    for j in range(freqs.shape[1]):
        ax.scatter(rpm, freqs[:, j], c=np.where(dirs[:, j], "C3", "C0"), s=8)
    ax.plot(rpm, rpm / 60, "k--", lw=0.8, label="1x")
    ax.scatter([], [], c="C3", s=8, label="forward")
    ax.scatter([], [], c="C0", s=8, label="backward")
    ax.set(xlabel="rotor speed (rpm)", ylabel="whirl frequency (Hz)", title="Two-disk rotor: Campbell diagram")
    ax.legend()
    fig.savefig(args.out / "campbell.png", dpi=120, bbox_inches="tight")
    print("wrote", args.out / "campbell.png")

    w, shapes = whirl(M, K, G_of(0.0))
    z = 0.25 * np.arange(7)
    fig, axes = plt.subplots(2, 2, figsize=(8, 5), sharex=True)
    names = model.coordinate_names
    for i, ax in enumerate(axes.flat):
        shape = shapes[:, i]
        x = np.array([shape[names.index(f"x{s}")] for s in model.stations])
        y = np.array([shape[names.index(f"y{s}")] for s in model.stations])
        main_axis = x if np.max(np.abs(x)) > np.max(np.abs(y)) else y
        phase = main_axis[np.argmax(np.abs(main_axis))]
        ax.plot(z, np.real(x / phase), "o-", label="x")
        ax.plot(z, np.real(y / phase), "s--", label="y")
        ax.set_title(f"mode {i + 1}: {w[i] / (2 * np.pi):.2f} Hz at 0 rpm")
        ax.axhline(0, color="k", lw=0.5)
    axes[0, 0].legend()
    for ax in axes[1]:
        ax.set_xlabel("axial position (m)")
    fig.tight_layout()
    fig.savefig(args.out / "modes.png", dpi=120, bbox_inches="tight")
    print("wrote", args.out / "modes.png")


if __name__ == "__main__":
    main()
