"""Engines, methods and start-up, measured in one run (AL-31F preset, 0-6 s).

Run: ``python bench/bench_engines.py`` (``--slow`` adds scipy's LSODA,
Radau and BDF, which take minutes). Prints ratios measured in this run.

1. The generated RHS against the hand-written compiled one, both driven by
   the same compiled Dormand-Prince loop over the same run: the cost of an
   evaluation inside compiled code, where call overhead does not hide it.
   Then the c back end (generated C in the C loop) against the same
   hand-written numba reference.
2. Engines, methods and back ends at the default tolerance.
3. Cold start (fresh, empty cache folders) against warm start of
   ``rotorkit run al31f``, with the c and the numba back end: wall and CPU
   time, and the time beyond the simulation
   (``python bench/bench_engines.py --sections 3``).
4. The model's own cold chain step by step (import and preset, derivation,
   code generation, building the right-hand side with gcc or numba), each in
   a fresh process with an empty cache (``--sections 4``).
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import al31f_handwritten as hw  # noqa: E402

import rotorkit as rk  # noqa: E402
from rotorkit.engines.rk_numba import integrate  # noqa: E402

SPAN = (0.0, 6.0)


def timed(fn, repeat=5):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def segmented(core, p_for, events, rtol=1e-6, atol=1e-9, integrate=integrate):
    """The preset run in the compiled loop, restarting at the roll steps like simulate()."""
    cuts = [SPAN[0], *events, SPAN[1]]
    y, nfev = np.zeros(32), 0
    for a, b in zip(cuts[:-1], cuts[1:]):
        sol = integrate(core, a, b, y, p_for(a, b), np.array([b]), rtol=rtol, atol=atol)
        assert sol.success, sol.message
        y, nfev = sol.y_reached, nfev + sol.nfev
    return nfev, y


def bench_rhs_in_loop():
    system = rk.preset("al31f").compile(backend="numba")
    generated = lambda: segmented(system.core, lambda a, b: system.within(a, b).prepared_parameters,  # noqa: E731
                                  system.time_events)
    P = hw.params()
    hand_core, packed = hw.make_rhs_numba(), hw.pack(P)
    # the hand-written core switches the roll at t >= roll_end; nudge like System.within does
    hand = lambda: segmented(hand_core, lambda a, b: packed, (2.0, 4.0))  # noqa: E731
    fns = {"generated": generated, "hand": hand}
    if "c" in rk.available_backends():
        from rotorkit.engines.rk_c import integrate as integrate_c

        c_system = rk.preset("al31f").compile(backend="c")
        fns["c"] = lambda: segmented(c_system.core.address,  # noqa: E731
                                     lambda a, b: c_system.within(a, b).prepared_parameters, c_system.time_events,
                                     integrate=integrate_c)
    for fn in fns.values():
        fn()  # compile
    runs = {name: [] for name in fns}
    for _ in range(7):  # interleaved, so a change of the machine's load hits both alike
        for name, fn in fns.items():
            t0 = time.perf_counter()
            out = fn()
            runs[name].append((time.perf_counter() - t0, out))
    t_gen, (n_gen, y_gen) = statistics.median(t for t, _ in runs["generated"]), runs["generated"][0][1]
    t_hand, (n_hand, _) = statistics.median(t for t, _ in runs["hand"]), runs["hand"][0][1]
    ratios = sorted((g / n_gen) / (h / n_hand) for (g, _), (h, _) in zip(runs["generated"], runs["hand"]))
    print("\n1. RHS inside the compiled DOP853 loop, AL-31F 0-6 s (median of 7, interleaved):")
    print(f"   generated RHS:    {t_gen:.3f} s, {n_gen} evaluations, {t_gen / n_gen * 1e9:6.0f} ns per evaluation+step")
    print(f"   hand-written RHS: {t_hand:.3f} s, {n_hand} evaluations, {t_hand / n_hand * 1e9:6.0f} ns per evaluation+step")
    print(f"   ratio generated / hand-written (per evaluation): {(t_gen / n_gen) / (t_hand / n_hand):.2f} "
          f"(pairwise: {ratios[0]:.2f}-{ratios[-1]:.2f})")
    if "c" in runs:
        t_c, (n_c, y_c) = statistics.median(t for t, _ in runs["c"]), runs["c"][0][1]
        ratios = sorted((g / n_c) / (h / n_hand) for (g, _), (h, _) in zip(runs["c"], runs["hand"]))
        print(f"   c back end (generated C in the C loop): {t_c:.3f} s, {n_c} evaluations, "
              f"{t_c / n_c * 1e9:6.0f} ns per evaluation+step; max |y_c - y_numba| / max |y| = "
              f"{np.max(np.abs(y_c - y_gen)) / np.max(np.abs(y_gen)):.1e}")
        print(f"   ratio c / hand-written numba (per evaluation): {(t_c / n_c) / (t_hand / n_hand):.2f} "
              f"(pairwise: {ratios[0]:.2f}-{ratios[-1]:.2f})")
    return t_hand


def bench_engines(slow, t_hand):
    backends = [b for b in ("numba", "c") if b in rk.available_backends()]
    systems = {b: rk.preset("al31f").compile(backend=b) for b in backends}
    rows = [("compiled", "DOP853", b) for b in backends] + [("compiled", "RK45", b) for b in backends]
    rows += [("scipy", "DOP853", "numba"), ("scipy", "RK45", "numba")]
    if slow:
        rows += [("scipy", "LSODA", "numba"), ("scipy", "Radau", "numba"), ("scipy", "BDF", "numba")]
    print("\n2. simulate(), AL-31F 0-6 s, rtol 1e-6, atol 1e-9:")
    for system in systems.values():
        rk.simulate(system, (0.0, 0.01))  # load the engine
    results = {}
    for engine, method, backend in rows:
        repeat = 3 if engine == "compiled" else 1
        wall, res = timed(lambda: rk.simulate(systems[backend], SPAN, engine=engine, method=method), repeat=repeat)
        results[(engine, method)] = results.get((engine, method), wall)
        print(f"   {engine:9s} {method:7s} {backend:6s} {wall:8.2f} s  {res.stats['nfev']:9d} evaluations  "
              f"{wall / t_hand:7.1f} x the hand-written compiled reference loop")
    base = results[("compiled", "DOP853")]
    print(f"   scipy DOP853 / compiled DOP853: {results[('scipy', 'DOP853')] / base:.1f}")


def run_cli(env, out):
    """One ``rotorkit run al31f`` in a fresh process: (wall s, CPU s of the process, simulate's wall s)."""
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "rotorkit.cli", "run", "al31f", "--out", out],
                          env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    assert proc.returncode == 0, proc.stderr
    line = next(s for s in proc.stdout.splitlines() if s.startswith("simulated"))
    sim = float(line.split(" in ")[1].split(" s")[0])
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, sim


def _median_runs(runs):
    return tuple(statistics.median(r[i] for r in runs) for i in range(3))


def bench_start(repeat=3):
    """Cold (every run in fresh, empty cache folders) and warm starts of the command, medians of ``repeat`` runs.

    Cold runs compile the integration loop in a second process while the model is derived and compiled
    (``rotorkit.engines.rk_numba.compile_loop_in_background``); "serial" turns that off
    (``ROTORKIT_BACKGROUND_COMPILE=0``). CPU times are those of the command and the processes it waited for
    (the background compilation included: the run collects it before integrating).
    """
    print(f"\n3. `rotorkit run al31f` (0-6 s, plots and signals written), cold vs warm, median of {repeat}:")
    base = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "ROTORKIT_BACKGROUND_COMPILE")}
    base["MPLBACKEND"] = "Agg"
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        cases = [("c", {"ROTORKIT_BACKEND": "c"})] if "c" in rk.available_backends() else []
        cases += [("numba", {"ROTORKIT_BACKEND": "numba"}),
                  ("numba serial", {"ROTORKIT_BACKEND": "numba", "ROTORKIT_BACKGROUND_COMPILE": "0"})]
        for label, extra in cases:
            runs = []
            for k in range(repeat):  # fresh cache folders every time: nothing is left from an earlier run
                env = dict(base, ROTORKIT_CACHE_DIR=f"{tmp}/{label.replace(' ', '_')}{k}", **extra)
                runs.append(run_cli(env, f"{tmp}/out"))
            rows[f"cold, {label}"] = runs
        for label, extra in cases[:2]:
            env = dict(base, ROTORKIT_CACHE_DIR=f"{tmp}/{label}0", **extra)  # warm: the first cold run's cache
            rows[f"warm, {label}"] = [run_cli(env, f"{tmp}/out") for _ in range(repeat)]
    for label, runs in rows.items():
        wall, cpu, sim = _median_runs(runs)
        spread = f"{min(r[0] for r in runs):.2f}-{max(r[0] for r in runs):.2f}"
        print(f"   {label:19s} {wall:6.2f} s wall ({spread}), {cpu:6.2f} s CPU, simulate {sim:.2f} s, "
              f"beyond the simulation {wall - sim:5.2f} s wall")
    for code in ("import rotorkit", "import rotorkit, matplotlib.figure", "import rotorkit, numba"):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        print(f"   (python -c '{code}': {time.perf_counter() - t0:.2f} s)")
    print(f"   load average (1, 5, 15 min): {', '.join(f'{x:.2f}' for x in os.getloadavg())}")


STEPS = """
import json, sys, time
t0 = time.perf_counter()
import rotorkit as rk
from rotorkit.system import _generated
model = rk.preset("al31f")
t1 = time.perf_counter()
model.equations()
t2 = time.perf_counter()
module = _generated(model, "unrolled", False)
t3 = time.perf_counter()
if sys.argv[1] == "c":
    from rotorkit.codegen.cmodel import c_functions
    c_functions(module)
else:
    model.compile(backend="numba")
t4 = time.perf_counter()
print(json.dumps([t1 - t0, t2 - t1, t3 - t2, t4 - t3]))
"""


def bench_cold_steps(repeat=3):
    """The model's own cold chain, step by step, each run a fresh process with an empty cache (median, range)."""
    import json

    print(f"\n4. cold steps of the preset's model (fresh process and cache; median (range) of {repeat}):")
    backends = [b for b in ("c", "numba") if b in rk.available_backends()]
    with tempfile.TemporaryDirectory() as tmp:
        for backend in backends:
            runs = []
            for k in range(repeat):
                env = dict(os.environ, ROTORKIT_CACHE_DIR=f"{tmp}/{backend}{k}", ROTORKIT_QUIET="1")
                out = subprocess.run([sys.executable, "-c", STEPS, backend], env=env, capture_output=True, text=True,
                                     check=True)
                runs.append(json.loads(out.stdout.splitlines()[-1]))
            cells = [f"{statistics.median(r[i] for r in runs):.2f} ({min(r[i] for r in runs):.2f}-"
                     f"{max(r[i] for r in runs):.2f})" for i in range(4)]
            print(f"   {backend:6s} import + preset {cells[0]} s, derive {cells[1]} s, generate {cells[2]} s, "
                  f"build the right-hand side {cells[3]} s")
    print(f"   load average (1, 5, 15 min): {', '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--slow", action="store_true", help="also scipy LSODA, Radau, BDF (minutes)")
    parser.add_argument("--sections", default="1,2,3", help="comma-separated sections to run (default 1,2,3)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per start-up row of section 3 (default 3)")
    args = parser.parse_args()
    sections = {int(x) for x in args.sections.split(",")}
    t_hand = bench_rhs_in_loop() if sections & {1, 2} else None
    if 2 in sections:
        bench_engines(args.slow, t_hand)
    if 3 in sections:
        bench_start(args.repeat)
    if 4 in sections:
        bench_cold_steps(args.repeat)
