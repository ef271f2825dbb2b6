"""The 1,000-point rub-stiffness x LP-speed map of the AL-31F preset (not run in the tests).

40 rub stiffnesses (log, 5e5-2e7 N/m) x 25 LP speeds (500-3000 rad/s), each
point a 4 s run (spectra and orders over 2.2-3.8 s). Stores the 1/2, 1 and
3/2 LP orders and HP - LP, Poincare samples of x2, and draws the 1/2-order
map and the status map (where the response ran away).

    PYTHONPATH=. python bench/al31f_rub_map.py OUT [--scheduler tcp://HOST:8786] [--workers N]

Cost: about 1,000 x the cost of one preset point (see bench/sweep_overhead.py
for that cost on your machine); on 2 local cores expect hours, not minutes;
on a cluster it divides by the number of workers. Interrupt it at will: a
rerun resumes.
"""

import argparse
import sys
from pathlib import Path

import numpy as np


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path)
    parser.add_argument("--scheduler")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--stiffnesses", type=int, default=40)
    parser.add_argument("--speeds", type=int, default=25)
    args = parser.parse_args(argv)

    from rotorkit.plotting.maps import plot_order_map, plot_status_map
    from rotorkit.sweep import Grid, run_sweep

    space = Grid({"rub_stiffness": np.geomspace(5e5, 2e7, args.stiffnesses),
                  "lp_speed": np.linspace(500.0, 3000.0, args.speeds)})
    ds = run_sweep("al31f", space, out_dir=args.out, t_end=4.0, window=(2.2, 3.8), workers=args.workers,
                   scheduler=args.scheduler, orders=["1/2 LP", "LP", "3/2 LP", "HP - LP"], poincare=["x2"],
                   poincare_revolutions=32, progress=lambda e: print(e, flush=True))
    for name, ax in (("map_half_order.png", plot_order_map(ds, "1/2 LP", "x2", logy=True, log=True)),
                     ("status_map.png", plot_status_map(ds, logy=True))):
        ax.figure.savefig(args.out / name, dpi=120)
        print(f"wrote {args.out / name}")
    print(f"wall time per point (median): {float(ds.wall_time.median()):.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
