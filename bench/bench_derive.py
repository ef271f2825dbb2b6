"""How the derivation grows with model size: lumped chains of 8 to 256 stations.

Run: ``python bench/bench_derive.py`` (``--quick``: 8 to 64 stations, one
repeat). For each chain (``bench_core.chain_model``: eccentric disks joined
by shaft segments, two supports; 2 coordinates per station) it derives the
equations with every in-process cache cleared (rotorkit's and sympy's),
``--repeat`` times, and prints the median wall and CPU time. The growth
exponent is the least-squares slope of log(time) against log(stations);
the issue asks for <= 1.1. CPU time is the robust figure on a shared
machine (wall time also counts waiting for a core).
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_core import chain_model  # noqa: E402

import os  # noqa: E402

os.environ.setdefault("ROTORKIT_QUIET", "1")  # the bench times the steps itself
from rotorkit.symbolic import lagrange  # noqa: E402


def time_derive(n_stations, repeat):
    import sympy as sp

    walls, cpus = [], []
    for _ in range(repeat):
        model = chain_model(n_stations)
        lagrange._CACHE.clear()
        sp.core.cache.clear_cache()
        w0, c0 = time.perf_counter(), time.process_time()
        eom = model.equations()
        cpus.append(time.process_time() - c0)
        walls.append(time.perf_counter() - w0)
    return eom.n, statistics.median(walls), statistics.median(cpus)


def slope(x, y):
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="8 to 64 stations, one repeat")
    parser.add_argument("--repeat", type=int, default=3, help="timings per size (median)")
    args = parser.parse_args(argv)
    sizes = (8, 16, 32, 64) if args.quick else (8, 16, 32, 64, 128, 256)
    repeat = 1 if args.quick else args.repeat
    time_derive(4, 1)  # imports and first-use costs out of the way
    print(f"Derivation of lumped chains, median of {repeat} (caches cleared each time):")
    print(f"  {'stations':>8s} {'coords':>6s} {'wall s':>8s} {'cpu s':>8s} {'cpu ms/station':>15s}")
    rows = []
    for n in sizes:
        coords, wall, cpu = time_derive(n, repeat)
        rows.append((n, wall, cpu))
        print(f"  {n:8d} {coords:6d} {wall:8.2f} {cpu:8.2f} {1e3 * cpu / n:15.1f}", flush=True)
    n, wall, cpu = (np.array(c, dtype=float) for c in zip(*rows))
    print(f"growth exponent {sizes[0]}-{sizes[-1]} stations: cpu {slope(n, cpu):.2f}, wall {slope(n, wall):.2f} "
          f"(target <= 1.1); upper half only ({sizes[len(sizes) // 2]}-{sizes[-1]}): "
          f"cpu {slope(n[len(n) // 2:], cpu[len(n) // 2:]):.2f}")


if __name__ == "__main__":
    main()
