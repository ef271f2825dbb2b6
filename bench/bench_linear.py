"""Linear analyses on a 400-coordinate beam rotor: modes at a speed, a 100-speed Campbell diagram,
an unbalance response over 1,000 speeds. Medians of repeated timings, measured in one run.

Run: ``python bench/bench_linear.py`` (``--repeat N``, default 5).

A last block times a Campbell diagram of a compiled finite-element system
(the two-disk rotor of ``examples/two_disk_rotor.py``): its matrices
evaluated from the derived symbolic ones at each speed, against
re-linearising the system at each speed (``relinearize=True``).

The rotor: a steel shaft (d = 50 mm, 1.5 m) of 99 Euler-Bernoulli beam
elements (consistent mass, four coordinates per node: x, y, tilt about x,
tilt about y), two disks with their gyroscopic coupling, two bearings of
1e7 N/m and 500 N s/m: 100 nodes, 400 coordinates, assembled with numpy
here (rotorkit's own beam elements, issue 8, will replace this builder).

These machines are shared by several engineers running tests at the same
time: absolute times vary by 2-5x between runs; the medians and the
ratios printed in one run are what to compare.
"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

# one BLAS thread: on a shared 2-core machine, threaded BLAS calls oversubscribe and
# ran a dense 800 x 800 eigen-solution 10x slower than one thread did (measured here)
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from rotorkit.linear.campbell import campbell  # noqa: E402
from rotorkit.linear.linear_model import LinearModel  # noqa: E402
from rotorkit.linear.unbalance import Unbalance, unbalance_response  # noqa: E402


def beam_rotor(nodes=100, length=1.5, diameter=0.05, E=2.1e11, rho=7800.0):
    """LinearModel of a beam rotor with two disks and two bearings (4 coordinates per node)."""
    n = 4 * nodes
    le = length / (nodes - 1)
    area, inertia = np.pi * diameter**2 / 4, np.pi * diameter**4 / 64
    k = E * inertia / le**3 * np.array([[12, 6 * le, -12, 6 * le], [6 * le, 4 * le**2, -6 * le, 2 * le**2],
                                        [-12, -6 * le, 12, -6 * le], [6 * le, 2 * le**2, -6 * le, 4 * le**2]])
    m = rho * area * le / 420 * np.array([[156, 22 * le, 54, -13 * le], [22 * le, 4 * le**2, 13 * le, -3 * le**2],
                                          [54, 13 * le, 156, -22 * le], [-13 * le, -3 * le**2, -22 * le, 4 * le**2]])
    K, M, C, G = (np.zeros((n, n)) for _ in range(4))
    for e in range(nodes - 1):
        a, b = 4 * e, 4 * (e + 1)
        # x-z plane: (x, theta_y); y-z plane: (y, -theta_x)
        ix = [a, a + 3, b, b + 3]
        iy = [a + 1, a + 2, b + 1, b + 2]
        sign = np.diag([1.0, -1.0, 1.0, -1.0])
        K[np.ix_(ix, ix)] += k
        M[np.ix_(ix, ix)] += m
        K[np.ix_(iy, iy)] += sign @ k @ sign
        M[np.ix_(iy, iy)] += sign @ m @ sign
    for node, (md, ip, idt) in ((30, (20.0, 0.4, 0.2)), (70, (15.0, 0.3, 0.15))):
        a = 4 * node
        M[a, a] += md
        M[a + 1, a + 1] += md
        M[a + 2, a + 2] += idt
        M[a + 3, a + 3] += idt
        G[a + 2, a + 3], G[a + 3, a + 2] = ip, -ip
    for node in (5, 94):
        a = 4 * node
        for i in (a, a + 1):
            K[i, i] += 1e7
            C[i, i] += 500.0
    names = [f"{c}{i + 1}" for i in range(nodes) for c in ("x", "y", "tx", "ty")]
    positions = {str(i + 1): i * le for i in range(nodes)}
    return LinearModel(mass=M, damping=C, stiffness=K, gyroscopic=G, coordinate_names=names,
                       station_positions=positions)


def median_time(fn, repeat):
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return statistics.median(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--skip-system", action="store_true", help="skip the compiled two-disk rotor rows")
    args = parser.parse_args()
    model = beam_rotor()
    print(f"beam rotor: {model.n} coordinates; medians of {args.repeat} runs (shared, loaded machine)")
    unb = [Unbalance(31, 1e-4), Unbalance(71, 1e-4, 1.5)]
    rows = [
        ("modes at one speed, 10 lowest (sparse shift-invert)", lambda: model.modes(1000.0, n_modes=10)),
        ("modes at one speed, all (dense, left + right)", lambda: model.modes(1000.0)),
        ("Campbell, 100 speeds, 8 modes tracked + root finding",
         lambda: campbell(model, np.linspace(0.0, 3000.0, 100), n_modes=8)),
        ("unbalance response, 1000 speeds (banded solve)",
         lambda: unbalance_response(model, unb, np.linspace(10.0, 3000.0, 1000))),
        ("unbalance response, 1000 speeds (dense batched solve)",
         lambda: unbalance_response(model, unb, np.linspace(10.0, 3000.0, 1000), method="dense")),
    ]
    results = []
    for label, fn in rows:
        repeat = args.repeat if "dense" not in label and "Campbell" not in label else max(1, args.repeat // 3)
        t = median_time(fn, repeat)
        results.append(t)
        print(f"  {label:<58} {t:9.4f} s", flush=True)
    print(f"ratios: dense/sparse modes {results[1] / results[0]:.1f}, "
          f"dense/banded unbalance {results[4] / results[3]:.1f}")
    print("targets (issue 9): modal < 0.1 s, Campbell < 5 s, unbalance < 1 s")
    if not args.skip_system:
        system_rows(args.repeat)


def system_rows(repeat):
    """Campbell of a compiled FE system: matrices from the symbolic ones per speed vs re-linearising per speed."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))
    from two_disk_rotor import two_disk_rotor

    system = two_disk_rotor(speed=0.0).compile()
    speeds = np.linspace(0.0, 450.0, 41)
    campbell(system, speeds[:2], n_modes=6)  # build the matrix evaluator once, outside the timing
    fast = median_time(lambda: campbell(system, speeds, n_modes=6), repeat)
    slow = median_time(lambda: campbell(system, speeds, n_modes=6, relinearize=True), max(1, repeat // 3))
    print(f"two-disk FE rotor ({len(system.coordinate_names)} coordinates), Campbell over {speeds.size} speeds:")
    print(f"  {'symbolic matrices evaluated per speed':<58} {fast:9.4f} s")
    print(f"  {'re-linearised per speed (relinearize=True)':<58} {slow:9.4f} s")
    print(f"ratio: re-linearised/symbolic {slow / fast:.1f}")


if __name__ == "__main__":
    main()
