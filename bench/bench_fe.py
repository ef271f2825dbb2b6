"""Cold derive + compile time and RHS cost of beam finite-element rotors of 25, 50 and 100 nodes.

    PYTHONPATH=. python bench/bench_fe.py [--nodes 25 50 100] [--backend python]

A uniform 50 mm steel shaft of 1.5 m in ``nodes - 1`` Timoshenko elements
(4 coordinates per node), two disks and two orthotropic supports. For each
size: derive time (sympy, from a cold process-level cache: the beam
template is derived once per process and counted in the first size), code
generation + compile time (into a fresh cache folder), and the cost of one
RHS evaluation. Times are wall-clock on whatever machine runs it: quote the
command with the numbers.
"""

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "examples"))


def fe_rotor(nodes):
    from two_disk_rotor import OrthotropicBearing

    from rotorkit import Model, Rotor
    from rotorkit.elements import BeamSegment, Disk, Material

    steel = Material.steel()
    stations = tuple(range(1, nodes + 1))
    length = 1.5 / (nodes - 1)
    elements = [Rotor(name="R", stations=stations, speed=300.0)]
    elements += [BeamSegment(start=s, end=s + 1, length=length, outer_diameter=0.05, material=steel)
                 for s in stations[:-1]]
    for s in (stations[nodes // 3], stations[2 * nodes // 3]):
        elements.append(Disk.from_geometry(station=s, width=0.07, inner_diameter=0.05, outer_diameter=0.28,
                                           material=steel, eccentricity=1e-5))
    elements += [OrthotropicBearing(station=s, kxx=1e6, kyy=0.8e6) for s in (1, nodes)]
    return Model(elements, name=f"fe{nodes}")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, nargs="+", default=[25, 50, 100])
    parser.add_argument("--backend", default="auto", help="compile backend (auto, numba, python)")
    args = parser.parse_args(argv)
    import os

    os.environ["ROTORKIT_CACHE_DIR"] = tempfile.mkdtemp(prefix="rk-bench-fe-")
    print(f"{'nodes':>5s} {'coords':>6s} {'derive s':>9s} {'compile s':>9s} {'rhs us':>8s}")
    for nodes in args.nodes:
        model = fe_rotor(nodes)
        t0 = time.perf_counter()
        model.equations()
        t1 = time.perf_counter()
        system = model.compile(backend=args.backend)
        t2 = time.perf_counter()
        y = np.zeros(system.n_states)
        y[: len(model.coordinate_names)] = 1e-6
        system.rhs(0.0, y)
        reps = 2000
        t3 = time.perf_counter()
        for _ in range(reps):
            system.rhs(0.0, y)
        rhs_us = (time.perf_counter() - t3) / reps * 1e6
        print(f"{nodes:5d} {len(model.coordinate_names):6d} {t1 - t0:9.2f} {t2 - t1:9.2f} {rhs_us:8.2f}", flush=True)


if __name__ == "__main__":
    main()
