"""Per-point overhead of a sweep, and throughput of 2 local workers against 1.

Overhead of a point = everything a sweep adds to the simulation itself:

- in the worker: rebuilding the model from its scene, loading the compiled
  system from the model cache, the spectra, order amplitudes, Poincare
  samples, largest displacement and run-away check; measured per point as
  ``point wall time - simulate wall time`` (both recorded in each point's
  stats);
- in the calling process: storing the point file and reporting progress,
  measured as the growth of ``sweep wall time - sum of point wall times``
  between a sweep of N points and one of 2N points (so the fixed cost of a
  sweep, i.e. warm-up check, manifest, ``sweep.nc``, is separated out and
  printed on its own).

Both are printed as a fraction of the simulation time of a preset point
(AL-31F, t_end = 6 s, the preset's own run; the target of issue 10 is < 5 %).

    PYTHONPATH=. python bench/sweep_overhead.py                    # 3 + 6 points, 1 worker (~1 min)
    PYTHONPATH=. python bench/sweep_overhead.py --throughput       # + 2 workers against 1 (~2 min more)
    PYTHONPATH=. python bench/sweep_overhead.py --t-end 4 --window 2.2 3.8   # the map's points

``--throughput`` runs the same points with 1 and with 2 local worker
processes and prints the speed-up, both over the whole sweep (including the
start of the worker processes, which load the compiled model once each) and
in the steady state (points per second between the first and the last
point to finish). This machine's 2 cores give about 1.5x for two independent
processes: the script measures that ceiling too, from plain simulations run
two at a time, and says what fraction of its gain the sweep reaches. The
load average is printed at the start and the end: the figures are only as
steady as the load (run it on a quiet machine).
"""

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ORDERS = ["1/2 LP", "LP", "3/2 LP", "HP - LP"]


def sweep(out, values, t_end, window, workers):
    """Run a 1-D rub-stiffness sweep; returns (wall, per-point stats, progress times)."""
    from rotorkit.sweep import point_path, run_sweep

    times = []
    start = time.perf_counter()
    run_sweep("al31f", "rub_stiffness", values, out_dir=out, t_end=t_end, window=window, workers=workers,
              orders=ORDERS, progress=lambda event: times.append(event.elapsed))
    wall = time.perf_counter() - start
    stats = []
    for i in range(len(values)):
        with np.load(point_path(out, i), allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
        assert meta["status"] == "ok", meta["message"]
        stats.append(meta["stats"])
    return wall, stats, times


def _plain(args):
    from rotorkit import preset, simulate

    t_end, k = args
    system = preset("al31f", rub_stiffness=k).compile()
    start = time.perf_counter()
    simulate(system, (0.0, t_end))
    return time.perf_counter() - start


def _steady_rate(times):
    """Points per second between the first and the last point to finish."""
    return (len(times) - 1) / (times[-1] - times[0]) if len(times) > 1 and times[-1] > times[0] else float("nan")


def load():
    return "load average %.2f %.2f %.2f" % os.getloadavg()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--t-end", type=float, default=6.0, help="simulated time of a point (s), default 6")
    parser.add_argument("--window", type=float, nargs=2, default=None,
                        help="spectrum window (s), default the last 1.6 s")
    parser.add_argument("--points", type=int, default=3, help="N: sweeps of N and 2N points (default 3)")
    parser.add_argument("--throughput", action="store_true", help="also 2 workers against 1")
    parser.add_argument("--throughput-points", type=int, default=8, help="points of the throughput sweeps")
    args = parser.parse_args(argv)
    window = tuple(args.window) if args.window else (max(0.0, args.t_end - 1.6), args.t_end)
    n = args.points
    values = list(np.linspace(2e6, 8e6, 3 * n))  # distinct values: no point is found on disk
    print(f"start: {load()}")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        sweep(tmp / "warm", values[:1], 0.05, (0.0, 0.05), 1)  # derive and compile once, outside the timing
        runs = {}
        for label, vals in (("N", values[:n]), ("2N", values[n:])):
            runs[label] = sweep(tmp / label, vals, args.t_end, window, 1)
        all_stats = runs["N"][1] + runs["2N"][1]
        sim = [s["simulate_wall_time"] for s in all_stats]
        extra = [s["point_wall_time"] - s["simulate_wall_time"] for s in all_stats]
        per_sim = statistics.median(sim)
        outside = {k: wall - sum(s["point_wall_time"] for s in stats) for k, (wall, stats, _) in runs.items()}
        caller = (outside["2N"] - outside["N"]) / n
        fixed = outside["N"] - n * caller
        worker = sum(extra) / len(extra)
        print(f"AL-31F, t_end = {args.t_end:g} s, window {window[0]:g}-{window[1]:g} s, orders {', '.join(ORDERS)}; "
              f"sweeps of {n} and {2 * n} points, 1 worker (in this process)")
        print(f"  simulation                  {per_sim:8.3f} s per point (median)")
        print(f"  in-worker overhead          {1000 * worker:8.1f} ms per point ({100 * sum(extra) / sum(sim):.2f} %; "
              f"median point {100 * statistics.median(e / s for e, s in zip(extra, sim)):.2f} %)")
        print(f"  calling process, per point  {1000 * caller:8.1f} ms per point ({100 * caller / per_sim:.2f} %; "
              "storing the point file, progress)")
        print(f"  per-point overhead          {100 * (sum(extra) / sum(sim) + caller / per_sim):.2f} % of the simulation "
              "(target < 5 %)")
        print(f"  fixed cost of a sweep       {fixed:8.2f} s (warm-up check, manifest, sweep.nc): "
              f"{100 * fixed / (1000 * per_sim):.2f} % of a 1,000-point sweep")
        if args.throughput:
            from concurrent.futures import ProcessPoolExecutor

            tvals = list(np.linspace(2.1e6, 7.9e6, args.throughput_points))
            with ProcessPoolExecutor(2) as pool:
                list(pool.map(_plain, [(0.05, tvals[0])] * 2))  # start both and load the compiled model
                start = time.perf_counter()
                list(pool.map(_plain, [(args.t_end, v) for v in tvals[:4]]))
                two = time.perf_counter() - start
            single = sum(_plain((args.t_end, v)) for v in tvals[:4])
            ceiling = single / two
            wall1, _, times1 = sweep(tmp / "one", tvals, args.t_end, window, 1)
            wall2, _, times2 = sweep(tmp / "two", tvals, args.t_end, window, 2)
            gain = lambda r: 100 * (r - 1) / (ceiling - 1) if ceiling > 1.0 else float("nan")  # noqa: E731
            whole, steady = wall1 / wall2, _steady_rate(times2) / _steady_rate(times1)
            print(f"throughput, {len(tvals)} points:")
            print(f"  plain simulations, 2 processes against 1: {ceiling:.2f}x (the machine's ceiling now)")
            print(f"  sweep, 2 workers against 1, whole sweep:  {whole:.2f}x ({gain(whole):.0f} % of the ceiling's "
                  f"gain; includes starting 2 worker processes: {wall1:.1f} s against {wall2:.1f} s)")
            print(f"  sweep, 2 workers against 1, steady state: {steady:.2f}x ({gain(steady):.0f} % of the ceiling's "
                  "gain; points per second between the first and the last point)")
    print(f"end: {load()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
