"""The C integration loop (rotorkit.engines.rk_c) against the numba loop (rk_numba), measured in one run.

Run: ``python bench/bench_c_loop.py`` (``--quick`` for fewer repeats and no cold numba compile).

Prints

* the time per accepted step of each loop on the same problems (a Duffing
  oscillator, where the loop's own work dominates, and a chain of cubic
  oscillators, 64 states), with the same right-hand side in C (gcc, as
  rotorkit's ``c`` back end builds it) and in numba; both take exactly the
  same steps (checked). Medians of interleaved repeats; the ratio C / numba;
* the one-time costs of getting each loop ready in a fresh process (import
  of the engine module included, interpreter start-up excluded): numba
  compiling its loop into an empty cache, numba loading it from its cache,
  gcc building the C loop into an empty cache, and loading the built C loop
  from the cache. Each in its own process, caches in a temporary folder.

These machines are shared: compare the ratios of one run, not absolute times
across runs, and note the load average printed with them.
"""

import argparse
import ctypes
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from rotorkit.codegen import cbuild  # noqa: E402
from rotorkit.engines import rk_c  # noqa: E402

DUFFING_P = np.array([0.3, 1.0, 0.5, 0.4, 1.1])
CHAIN = 32  # masses: 64 states

C_CORES = r"""
#include <math.h>
void duffing(double t, const double *y, const double *p, double *d)
{
    const double x = y[0], v = y[1];
    d[0] = v;
    d[1] = -p[0] * v - p[1] * x - p[2] * (x * x * x) + p[3] * cos(p[4] * t);
}
/* a chain of unit masses, linear springs p[0] between neighbours and to the ground at both ends, cubic springs
   p[1], damping p[2], the first mass driven by cos(p[3] t) */
void chain(double t, const double *y, const double *p, double *d)
{
    const int n = %(n)d;
    for (int i = 0; i < n; i++)
        d[i] = y[n + i];
    for (int i = 0; i < n; i++) {
        const double left = i > 0 ? y[i] - y[i - 1] : y[i];
        const double right = i < n - 1 ? y[i] - y[i + 1] : y[i];
        d[n + i] = -p[0] * (left + right) - p[1] * (left * left * left + right * right * right) - p[2] * y[n + i];
    }
    d[n] += cos(p[3] * t);
}
""" % {"n": CHAIN}
CHAIN_P = np.array([1e4, 1e6, 0.5, 30.0])


def numba_cores():
    import numba

    @numba.njit
    def duffing(t, y, p, d):
        x = y[0]
        v = y[1]
        d[0] = v
        d[1] = -p[0] * v - p[1] * x - p[2] * (x * x * x) + p[3] * np.cos(p[4] * t)

    @numba.njit
    def chain(t, y, p, d):
        n = CHAIN
        for i in range(n):
            d[i] = y[n + i]
        for i in range(n):
            left = y[i] - y[i - 1] if i > 0 else y[i]
            right = y[i] - y[i + 1] if i < n - 1 else y[i]
            d[n + i] = -p[0] * (left + right) - p[1] * (left * left * left + right * right * right) - p[2] * y[n + i]
        d[n] += np.cos(p[3] * t)

    return {"duffing": duffing, "chain": chain}


def per_step(repeat):
    from rotorkit.engines import rk_numba

    with tempfile.TemporaryDirectory(prefix="rotorkit-bench-cores-") as folder:
        lib = cbuild.library(Path(folder), "cores", C_CORES)  # stays loaded when its file is gone
    c = {name: ctypes.cast(getattr(lib, name), ctypes.c_void_p).value for name in ("duffing", "chain")}
    nb = numba_cores()
    y_chain = np.zeros(2 * CHAIN)
    y_chain[0] = 1e-3
    problems = {
        "Duffing, 2 states, 0-2000 s": ("duffing", 0.0, 2000.0, [1.0, 0.0], DUFFING_P),
        f"chain of {CHAIN} cubic oscillators, {2 * CHAIN} states, 0-2 s": ("chain", 0.0, 2.0, y_chain, CHAIN_P),
    }
    print(f"\nTime per accepted step (DOP853, rtol 1e-6, atol 1e-9, 1000 samples; median of {repeat}, interleaved):")
    for label, (name, t0, t1, y0, p) in problems.items():
        t_eval = np.linspace(t0, t1, 1000)
        runs = {"C": lambda: rk_c.integrate(c[name], t0, t1, y0, p, t_eval),
                "numba": lambda: rk_numba.integrate(nb[name], t0, t1, y0, p, t_eval)}
        sols = {key: run() for key, run in runs.items()}  # warm-up (and the numba core's compilation)
        a, b = sols["C"], sols["numba"]
        assert (a.nfev, a.n_accepted, a.n_rejected) == (b.nfev, b.n_accepted, b.n_rejected), (a, b)
        deviation = np.max(np.abs(a.y - b.y)) / np.max(np.abs(b.y))
        times = {key: [] for key in runs}
        for _ in range(repeat):
            for key, run in runs.items():
                began = time.perf_counter()
                run()
                times[key].append(time.perf_counter() - began)
        step = {key: statistics.median(values) / a.n_accepted for key, values in times.items()}
        print(f"  {label}: {a.n_accepted} steps, nfev {a.nfev} (identical), samples differ by {deviation:.1e} rel.")
        print(f"    C {step['C'] * 1e6:8.3f} us/step, numba {step['numba'] * 1e6:8.3f} us/step, "
              f"ratio C / numba {step['C'] / step['numba']:.3f}")


PROBES = {
    "numba loop": "from rotorkit.engines import rk_numba; rk_numba._compiled_loop()",
    "C loop": "from rotorkit.engines import rk_c; rk_c._loop()",
    "numpy": "import numpy",
}


def ready_time(what, cache):
    """Seconds from importing the engine to its loop being ready, in a fresh process using ``cache``."""
    code = ("import time; began = time.perf_counter(); " + PROBES[what]
            + "; print(time.perf_counter() - began)")
    env = dict(os.environ, ROTORKIT_CACHE_DIR=str(cache), PYTHONPATH=str(ROOT), ROTORKIT_BACKGROUND_COMPILE="0")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=ROOT,
                          timeout=600, check=True)
    return float(done.stdout.strip().splitlines()[-1])


def one_time(repeat, cold_numba):
    print(f"\nOne-time cost of getting the loop ready in a fresh process (import included; median of {repeat}):")
    rows = {}
    with tempfile.TemporaryDirectory(prefix="rotorkit-bench-cache-") as base:
        builds = []
        for i in range(repeat):
            cache = Path(base) / f"c-cold-{i}"
            builds.append(ready_time("C loop", cache))
        rows["C loop, gcc build into an empty cache"] = builds
        rows["C loop, load from the cache"] = [ready_time("C loop", Path(base) / "c-cold-0") for _ in range(repeat)]
        warm = Path(base) / "numba"
        compiles = [ready_time("numba loop", warm)]  # also fills the cache for the loads below
        if cold_numba:
            compiles += [ready_time("numba loop", Path(base) / f"numba-cold-{i}") for i in range(1, min(repeat, 2))]
            rows["numba loop, compile into an empty cache"] = compiles
        rows["numba loop, load from the cache"] = [ready_time("numba loop", warm) for _ in range(repeat)]
        rows["(for reference: import numpy, part of each)"] = [ready_time("numpy", warm) for _ in range(repeat)]
    for label, values in rows.items():
        print(f"  {label:<42s} {statistics.median(values):7.3f} s  (runs: {', '.join(f'{v:.3f}' for v in values)})")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, no cold numba compile timing")
    args = parser.parse_args()
    if cbuild.compiler() is None:
        sys.exit("no C compiler found: the C loop cannot be built (install gcc or set $CC)")
    print(f"load average before: {' '.join(f'{v:.2f}' for v in os.getloadavg())}; gcc {cbuild.compiler()}; "
          f"{os.cpu_count()} cores")
    per_step(3 if args.quick else 11)
    one_time(2 if args.quick else 5, cold_numba=not args.quick)
    print(f"\nload average after: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
