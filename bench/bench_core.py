"""Core costs, measured in one run: RHS evaluation, derive + compile, the preset run.

Run: ``python bench/bench_core.py`` (add ``--quick`` to skip the 6 s run).
Prints medians of repeated timings and ratios measured in this run; these
machines are shared, so compare ratios, not absolute times across runs.
"""

import argparse
import statistics
import sys
import time
import timeit
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import al31f_handwritten as hw  # noqa: E402

import rotorkit as rk  # noqa: E402
from rotorkit.symbolic import lagrange  # noqa: E402


def median_call(fn, number=2000, repeat=15):
    return statistics.median(timeit.repeat(fn, number=number, repeat=repeat)) / number


def state():
    rng = np.random.default_rng(0)
    y = rng.normal(size=32) * np.r_[np.full(16, 5e-5), np.full(16, 5e-3)]
    y[1], y[8] = 1.2e-4, 0.6e-4  # past the rub clearance
    y[6] += 2e-5  # bearing engaged
    return y


def bench_rhs():
    y, t = state(), 2.5
    P = hw.params()
    rows = {}
    for backend in rk.available_backends():
        system = rk.preset("al31f").compile(backend=backend)
        system.rhs(t, y)
        rows[f"generated, {backend} back end, system.rhs(t, y)"] = median_call(lambda: system.rhs(t, y))
        if backend == "numba":
            core, p, out = system.core, system.prepared_parameters, np.empty(32)
            rows["generated, numba core(t, y, p, out) called from Python"] = median_call(lambda: core(t, y, p, out))
    rows["hand-written numpy (np.linalg.solve)"] = median_call(lambda: hw.rhs_numpy(t, y, P), number=200)
    if "numba" in rk.available_backends():
        fn, p, out = hw.make_rhs_numba(), hw.pack(P), np.empty(32)
        fn(t, y, p, out)
        rows["hand-written numba core called from Python"] = median_call(lambda: fn(t, y, p, out))
    base = rows.get("hand-written numba core called from Python")
    print("\nOne AL-31F RHS evaluation (median):")
    for name, sec in rows.items():
        ratio = f"  {sec / base:6.2f} x hand-written numba" if base else ""
        print(f"  {name:<58s} {sec * 1e6:8.2f} us{ratio}")


def chain_model(n_stations):
    elements = [rk.Rotor(name="R", stations=tuple(range(n_stations)), speed=100.0)]
    elements += [rk.Disk(station=i, mass=1.0, radius=0.1, eccentricity=1e-5) for i in range(n_stations)]
    elements += [rk.ShaftSegment(start=i, end=i + 1, bending_stiffness=1e5, bending_damping=1.0)
                 for i in range(n_stations - 1)]
    elements += [rk.ElasticSupport(station=0, stiffness=1e5), rk.ElasticSupport(station=n_stations - 1, stiffness=1e5)]
    return rk.Model(elements)


def bench_derive():
    print("\nDerive + generate + load (cold in-process caches):")
    for label, model in (("AL-31F preset, 16 DOF", rk.preset("al31f")), ("chain of 32 disks, 64 DOF", chain_model(32))):
        lagrange._CACHE.clear()
        from rotorkit import system as system_module

        system_module._MODULES.clear()
        t0 = time.perf_counter()
        model.equations()
        t1 = time.perf_counter()
        model.compile(backend="python")
        t2 = time.perf_counter()
        print(f"  {label:<28s} derive {t1 - t0:6.2f} s, generate + load {t2 - t1:6.2f} s")


def bench_run():
    system = rk.preset("al31f").compile()
    t0 = time.perf_counter()
    result = rk.simulate(system, (0.0, 6.0))
    wall = time.perf_counter() - t0
    s = result.stats
    print(f"\nAL-31F 0-6 s, defaults (solve_ivp {s['method']}, rtol {s['rtol']:g}, atol {s['atol']:g}, "
          f"{system.backend} RHS): wall {wall:.2f} s, {s['nfev']} RHS evaluations, "
          f"{wall / s['nfev'] * 1e6:.2f} us per evaluation including solve_ivp")


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    bench_rhs()
    bench_derive()
    if not args.quick:
        bench_run()
