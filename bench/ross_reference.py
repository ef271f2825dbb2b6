"""Reference timings of ROSS (petrobras/ross) on rotorkit's examples/compressor.toml rotor (not part of rotorkit).

    python -m venv /tmp/venv-ross && /tmp/venv-ross/bin/pip install ross-rotordynamics "plotly<6"
    /tmp/venv-ross/bin/python bench/ross_reference.py [--repeat 3]      # driver: each task in a fresh process
    /tmp/venv-ross/bin/python bench/ross_reference.py --task campbell   # one task

ROSS is never a dependency of rotorkit: this script runs only in a virtual
environment of its own (above), to give reference figures for
docs/performance.md.

The rotor is built from the model file's data (tomllib; units converted by
hand): 19 Timoshenko shaft elements (shear, rotary inertia, gyroscopics),
4 disks (mass, inertias), 2 bearings with speed-tabulated coefficients.
Tasks, as in rotorkit's bench/bench_linear_workflow.py: load (import ross +
build the rotor), campbell (33 speeds 0..1600 rad/s, 6 frequencies),
unbalance (600 speeds 10..1600 rad/s, 1.5e-3 kg m at station 8), static
(gravity), map (undamped critical speed map run_ucs, 13 stiffnesses 1e6..1e10
N/m). Times are wall and CPU (user + system) of the whole process.
"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
import tomllib

FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "compressor.toml")
UNITS = {"mm": 1e-3, "m": 1.0, "kg": 1.0, "kg*m**2": 1.0, "MN/m": 1e6, "kN*s/m": 1e3, "GPa": 1e9,
         "kg/m**3": 1.0, "um": 1e-6}


def si(text):
    if not isinstance(text, str):
        return float(text)
    number, unit = text.split(maxsplit=1)
    return float(number) * UNITS[unit]


def build():
    import ross as rs

    data = tomllib.load(open(FILE, "rb"))["element"]
    shaft, disks, bearings = [], [], []
    materials = {}
    for e in data:
        if e["type"] == "BeamSegment":
            m = e["material"]
            key = (si(m["density"]), si(m["youngs_modulus"]), si(m["shear_modulus"]))
            if key not in materials:
                materials[key] = rs.Material(name=f"steel_rk{len(materials)}", rho=key[0], E=key[1], G_s=key[2])
            shaft.append(rs.ShaftElement(L=si(e["length"]), idl=0.0, odl=si(e["outer_diameter"]),
                                         material=materials[key], n=e["start"] - 1, shear_effects=True,
                                         rotary_inertia=True, gyroscopic=True))
        elif e["type"] == "Disk":
            disks.append(rs.DiskElement(n=e["station"] - 1, m=si(e["mass"]), Id=si(e["diametral_inertia"]),
                                        Ip=si(e["polar_inertia"])))
        elif e["type"] == "LinearBearing":
            coefficients = {k: [si(v) for v in e[k]] for k in ("kxx", "kyy", "cxx", "cyy", "kxy", "kyx") if k in e}
            bearings.append(rs.BearingElement(n=e["station"] - 1, frequency=[float(w) for w in e["speeds"]],
                                              **coefficients))
    return rs.Rotor(shaft, disks, bearings)


def task(name):
    import numpy as np

    rotor = build()
    if name == "campbell":
        rotor.run_campbell(np.linspace(0.0, 1600.0, 33), frequencies=6)
    elif name == "unbalance":
        rotor.run_unbalance_response(node=7, unbalance_magnitude=1.5e-3, unbalance_phase=0.0,
                                     frequency=np.linspace(10.0, 1600.0, 600))
    elif name == "static":
        rotor.run_static()
    elif name == "map":
        rotor.run_ucs(stiffness_range=(6, 10), num=13, num_modes=16)
    elif name != "load":
        raise SystemExit(f"unknown task {name}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--task")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--tasks", nargs="+", default=["load", "campbell", "unbalance", "static", "map"])
    args = parser.parse_args()
    if args.task:
        task(args.task)
        return
    print(f"ROSS reference, {FILE}: fresh process per run, medians of {args.repeat}; "
          f"load average before: {os.getloadavg()[0]:.2f}")
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    subprocess.run([sys.executable, __file__, "--task", "load"], env=env, check=True, capture_output=True)  # warm
    for name in args.tasks:
        wall, cpu = [], []
        for _ in range(args.repeat):
            usage = resource.getrusage(resource.RUSAGE_CHILDREN)
            c0, t0 = usage.ru_utime + usage.ru_stime, time.perf_counter()
            proc = subprocess.run([sys.executable, __file__, "--task", name], env=env, capture_output=True,
                                  text=True)
            wall.append(time.perf_counter() - t0)
            usage = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu.append(usage.ru_utime + usage.ru_stime - c0)
            if proc.returncode:
                print(f"{name} failed:\n{proc.stderr[-2000:]}")
                break
        else:
            print(f"{name:<10} wall {statistics.median(wall):7.2f} s  CPU {statistics.median(cpu):7.2f} s  "
                  f"load {os.getloadavg()[0]:.2f}", flush=True)


if __name__ == "__main__":
    main()
