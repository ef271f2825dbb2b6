"""Floquet multipliers of one periodic solution of the 100-coordinate beam rotor: each method's time, in one run.

    PYTHONPATH=. python bench/bench_floquet.py                  # median of 3 (1 for the slow methods)
    PYTHONPATH=. python bench/bench_floquet.py --repeat 5 --no-old

The rotor is bench/bench_fe.py's (24 Timoshenko elements, 25 nodes, 100
coordinates, 200 states; a rub stator at the first disk), its synchronous
harmonic-balance solution (``H = 3``, condensed onto the contact
coordinates, expanded to all 100) at 300 rad/s. Timed on that one
solution, the Jacobian compiled beforehand:

- ``collocation``: :func:`rotorkit.periodic.stability.monodromy_multipliers`
  (exponential collocation in the modal coordinates of the linear part,
  ``--steps`` per period, :mod:`rotorkit.periodic.floquet`); target (c) of
  issue 20, <= 0.5 s;
- ``hill``: :func:`rotorkit.periodic.stability.hill_multipliers` (a dense
  eigenproblem of size ``2n (2H + 1) = 1400`` with eigenvectors);
- ``dop853`` (the old monodromy path, ``--no-old`` skips it): the full
  variational equations, 200 x 200, by scipy's DOP853 at rtol 1e-10.

Every method runs with one BLAS thread (``OPENBLAS_NUM_THREADS=1`` unless
set): on this shared two-core machine a threaded BLAS oversubscribed by the
other processes made a 200 x 200 eigenvalue call take seconds instead of
tenths. It prints the medians, the ratios to the old path, and the agreement: the
largest distance from a multiplier of one method to the nearest of another,
and the collocation's change from ``steps`` to ``2 steps``.
"""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # see the notes: one BLAS thread for every method
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))


def load():
    return os.getloadavg()[0]


def gap(a, b):
    """Largest distance from a multiplier in ``a`` to the nearest in ``b``, both ways."""
    d = np.abs(np.asarray(a)[:, None] - np.asarray(b)[None, :])
    return float(max(np.max(np.min(d, axis=1)), np.max(np.min(d, axis=0))))


def timed(fn, repeat):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--nodes", type=int, default=25, help="beam nodes (4 coordinates each; default 25)")
    parser.add_argument("--repeat", type=int, default=3, help="repetitions of the fast method (median)")
    parser.add_argument("--slow-repeat", type=int, default=1, help="repetitions of Hill and DOP853")
    parser.add_argument("--steps", type=int, default=None, help="collocation steps per period (default the module's)")
    parser.add_argument("--no-old", action="store_true", help="skip the DOP853 monodromy (minutes)")
    args = parser.parse_args()
    from bench_fe import fe_rotor

    from rotorkit.analysis.periodic import periodic_solution
    from rotorkit.periodic.floquet import DEFAULT_STEPS
    from rotorkit.periodic.hb import HarmonicBalance
    from rotorkit.periodic.stability import hill_multipliers, monodromy_multipliers

    steps = args.steps or DEFAULT_STEPS
    print(f"load average {load():.1f} on {os.cpu_count()} cores", flush=True)
    t0 = time.perf_counter()
    system = fe_rotor(args.nodes).compile()
    solution = periodic_solution(system, harmonics=3, condense=True, stability="none")
    hb = HarmonicBalance(system, speed_parameter="R_speed", harmonics=3)
    frame = hb.frame()
    z = solution.coefficients[0].ravel()
    print(f"{hb.n} coordinates ({system.backend} back end), H = 3: set-up (derive, compile, condensed solution) "
          f"{time.perf_counter() - t0:.1f} s; max radius at the rub "
          f"{solution.max_radius(args.nodes // 3 + 1)[0]:.3g} m",
          flush=True)
    monodromy_multipliers(hb, z, frame, steps=8)  # warm: the Jacobian's first call is not timed
    fast, mc = timed(lambda: monodromy_multipliers(hb, z, frame, steps=steps)[0], args.repeat)
    fine = monodromy_multipliers(hb, z, frame, steps=2 * steps)[0]
    print(f"collocation monodromy ({steps} steps/period): {fast:.3f} s (target <= 0.5 s); change at {2 * steps} "
          f"steps {gap(mc, fine):.1e}; max |mu| {np.max(np.abs(mc)):.6f}; load {load():.1f}", flush=True)
    hill, mh = timed(lambda: hill_multipliers(hb, z, frame), args.slow_repeat)
    print(f"Hill ({2 * hb.size} x {2 * hb.size}): {hill:.3f} s ({hill / fast:.0f}x the collocation); "
          f"Hill - collocation gap {gap(mh, mc):.1e}; load {load():.1f}", flush=True)
    if not args.no_old:
        old, mo = timed(lambda: monodromy_multipliers(hb, z, frame, method="dop853")[0], args.slow_repeat)
        print(f"DOP853 monodromy (old path): {old:.1f} s; ratio old / collocation {old / fast:.0f}x; "
              f"DOP853 - collocation gap {gap(mo, mc):.1e}, DOP853 - Hill {gap(mo, mh):.1e}; load {load():.1f}",
              flush=True)


if __name__ == "__main__":
    main()
