"""The 1,000-point rub-stiffness x LP-speed map of the AL-31F preset (not run in the tests).

40 rub stiffnesses (log, 5e5-2e7 N/m) x 25 LP speeds (500-3000 rad/s), each
point a 4 s run of the preset (spectra and orders over 2.2-3.8 s). Stores the
1/2, 1 and 3/2 LP orders and HP - LP, 32 once-per-revolution samples of x2,
and draws the map of the 1/2-order amplitude of x2 beside the status map
(where the response ran away), plus each on its own.

    PYTHONPATH=. python bench/al31f_rub_map.py OUT                      # the full map, 2 local workers
    PYTHONPATH=. python bench/al31f_rub_map.py OUT --scheduler tcp://HOST:8786   # on a Dask cluster
    PYTHONPATH=. python bench/al31f_rub_map.py OUT --stiffnesses 8 --speeds 6    # a 48-point map

The figure of docs/sweeps.md is the 48-point map, made with
``--stiffnesses 8 --speeds 6 --figures docs/figures/sweeps``.

Cost: points x the cost of one point (``bench/sweep_overhead.py --t-end 4
--window 2.2 3.8`` prints it for this machine), divided by the workers'
throughput; the script prints the wall time, the median point and the load
average. On a cluster it divides by the number of workers (the per-point
overhead of the sweep is a few per cent, the fixed cost of a sweep well under
a second, and each worker loads the compiled model once, a few seconds).
Interrupt it at will: a rerun resumes (only the missing points run).
"""

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

SIGNAL, ORDER = "x2", "1/2 LP"


def figures(ds, out, folder=None):
    """The map of the 1/2-order amplitude beside the status map (in ``folder``, default ``out``), and each alone
    (in ``out``); returns the paths."""
    from matplotlib.figure import Figure

    from rotorkit.plotting.maps import plot_order_map, plot_status_map

    folder = folder or out
    folder.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(12.0, 4.8), layout="constrained")
    left, right = fig.subplots(1, 2)
    plot_order_map(ds, ORDER, SIGNAL, ax=left, logy=True, log=True)
    plot_status_map(ds, ax=right, logy=True)
    fig.suptitle(f"AL-31F preset, {ds.status.size} points of 4 s: rub stiffness x LP speed", fontsize=10)
    written = [(folder / "al31f_rub_map.png", fig),
               (out / "map_half_order.png", plot_order_map(ds, ORDER, SIGNAL, logy=True, log=True).figure),
               (out / "status_map.png", plot_status_map(ds, logy=True).figure)]
    for path, figure in written:
        figure.savefig(path, dpi=110)
    return [path for path, _ in written]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="sweep folder (a rerun resumes)")
    parser.add_argument("--scheduler", help="Dask scheduler address, e.g. tcp://host:8786")
    parser.add_argument("--workers", type=int, default=2, help="local worker processes (default 2)")
    parser.add_argument("--stiffnesses", type=int, default=40, help="rub stiffnesses (default 40)")
    parser.add_argument("--speeds", type=int, default=25, help="LP speeds (default 25)")
    parser.add_argument("--figures", type=Path, help="folder of the two-panel figure (default: OUT)")
    args = parser.parse_args(argv)

    from rotorkit.sweep import Grid, run_sweep

    space = Grid({"rub_stiffness": np.geomspace(5e5, 2e7, args.stiffnesses),
                  "lp_speed": np.linspace(500.0, 3000.0, args.speeds)})
    print("start: load average %.2f %.2f %.2f" % os.getloadavg(), flush=True)
    cached = []

    def progress(event):
        print(event, flush=True)
        if event.status == "cached":
            cached.append(event.index)

    start = time.perf_counter()
    ds = run_sweep("al31f", space, out_dir=args.out, t_end=4.0, window=(2.2, 3.8), workers=args.workers,
                   scheduler=args.scheduler, orders=[ORDER, "LP", "3/2 LP", "HP - LP"], poincare=[SIGNAL],
                   poincare_revolutions=32, progress=progress)
    wall = time.perf_counter() - start
    for path in figures(ds, args.out, args.figures):
        print(f"wrote {path}")
    status = ds.status.values.ravel()
    computed = np.isfinite(ds.wall_time.values.ravel())
    counts = ", ".join(f"{k} {int(np.sum(status == k))}" for k in ("ok", "failed", "runaway", "missing"))
    print(f"{status.size} points ({counts}); wall time {wall:.1f} s in this run "
          f"({args.scheduler or f'{args.workers} local workers'})")
    if computed.any():
        per_point = np.nanmedian(ds.wall_time.values)
        print(f"point wall time: median {per_point:.2f} s, total {np.nansum(ds.wall_time.values):.1f} s over "
              f"{int(computed.sum())} points")
        if cached:
            print(f"{len(cached)} points were found on disk (a resumed sweep): no throughput figure")
        else:
            print(f"throughput: {np.nansum(ds.wall_time.values) / max(wall, 1e-9):.2f} points computed at once on "
                  f"average; {wall / status.size:.2f} s of wall time per point")
    print("end: load average %.2f %.2f %.2f" % os.getloadavg())
    return 0


if __name__ == "__main__":
    sys.exit(main())
