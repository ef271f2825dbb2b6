"""Per-point overhead of a sweep, and throughput of 2 local workers against 1.

Overhead of a point = everything a sweep adds to the simulation itself:
rebuilding the model from its scene, loading the compiled system from the
model cache, the spectra, order amplitudes and Poincare samples (in the
worker), and storing the point file and reporting progress (in the calling
process). It is measured per point as ``point wall time - simulate wall
time`` (both recorded in each point's stats) plus the calling process's time
outside the points, and printed as a fraction of the simulation time.

    PYTHONPATH=. python bench/sweep_overhead.py                 # AL-31F, 3 points of t_end = 6 s, 1 worker
    PYTHONPATH=. python bench/sweep_overhead.py --t-end 2 --points 4 --throughput

``--throughput`` runs the same points with 1 and with 2 workers and prints
the speed-up (this machine's 2 cores give about 1.5x for two independent
processes: the script prints that reference too, from two plain
simulations run in parallel). Run it on a quiet machine: the figures are
only as steady as the load.
"""

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def sweep(out, values, t_end, workers, window):
    from rotorkit.sweep import load_sweep, point_path, run_sweep

    start = time.perf_counter()
    run_sweep("al31f", "rub_stiffness", values, out_dir=out, t_end=t_end, window=window, workers=workers,
              orders=["1/2 LP", "LP", "3/2 LP", "HP - LP"])
    wall = time.perf_counter() - start
    stats = []
    for i in range(len(values)):
        with np.load(point_path(out, i), allow_pickle=False) as data:
            stats.append(json.loads(str(data["meta"]))["stats"])
    load_sweep(out)
    return wall, stats


def _plain(args):
    from rotorkit import preset, simulate

    t_end, k = args
    system = preset("al31f", rub_stiffness=k).compile()
    start = time.perf_counter()
    simulate(system, (0.0, t_end))
    return time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=6.0)
    parser.add_argument("--points", type=int, default=3)
    parser.add_argument("--throughput", action="store_true")
    args = parser.parse_args(argv)
    values = list(np.linspace(2e6, 8e6, args.points))
    window = (max(0.0, args.t_end - 1.6), args.t_end)
    with tempfile.TemporaryDirectory() as tmp:
        sweep(Path(tmp) / "warm", values[:1], 0.05, 1, (0.0, 0.05))  # derive and compile once, outside the timing
        wall, stats = sweep(Path(tmp) / "one", values, args.t_end, 1, window)
        sim = sum(s["simulate_wall_time"] for s in stats)
        point = sum(s["point_wall_time"] for s in stats)
        print(f"AL-31F, {len(values)} points of t_end = {args.t_end:g} s, 1 worker (in this process)")
        print(f"  simulation            {sim / len(values):8.3f} s per point")
        print(f"  in-worker overhead    {(point - sim) / len(values):8.3f} s per point "
              f"({100 * (point - sim) / sim:.2f} % of the simulation)")
        print(f"  calling-process extra {(wall - point) / len(values):8.3f} s per point "
              f"({100 * (wall - point) / sim:.2f} %; includes the warm-up check of the cache)")
        print(f"  total overhead        {100 * (wall - sim) / sim:.2f} % of the simulation time")
        extra = sorted((s["point_wall_time"] - s["simulate_wall_time"]) / s["simulate_wall_time"] for s in stats)
        print(f"  in-worker overhead, median point: {100 * extra[len(extra) // 2]:.2f} % (the first point of a "
              "process also builds the taper table and loads the compiled model)")
        if args.throughput:
            from concurrent.futures import ProcessPoolExecutor

            with ProcessPoolExecutor(2) as pool:
                list(pool.map(_plain, [(0.05, values[0])] * 2))  # start and load both
                start = time.perf_counter()
                list(pool.map(_plain, [(args.t_end, v) for v in values[:2]]))
                two = time.perf_counter() - start
            single = sum(_plain((args.t_end, v)) for v in values[:2])
            wall2, _ = sweep(Path(tmp) / "two", values, args.t_end, 2, window)
            print(f"  plain simulations, 2 processes against 1: {single / two:.2f}x (the machine's ceiling)")
            print(f"  sweep, 2 workers against 1: {wall / wall2:.2f}x "
                  f"({100 * (wall / wall2 - 1) / max(single / two - 1, 1e-9):.0f} % of the ceiling's gain)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
