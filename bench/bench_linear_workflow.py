"""The everyday linear workflow on the 80-coordinate compressor rotor, each step in a fresh process.

    PYTHONPATH=. python bench/bench_linear_workflow.py                     # every task, cold and warm, 3 runs
    PYTHONPATH=. python bench/bench_linear_workflow.py --repeat 5 --tasks campbell unbalance
    PYTHONPATH=. python bench/bench_linear_workflow.py --cache warm        # warm cache only

The rotor is ``examples/compressor.toml`` (19 Timoshenko elements, 4 disks,
two speed-dependent anisotropic bearings, one cross-coupled; issue 24).
Each task is one fresh ``python`` process doing what a user types, from
``import rotorkit`` to the answer (model file load included):

``campbell``   load + ``campbell(model, 33 speeds 0..1600 rad/s)``
``map``        load + ``critical_speed_map`` of the rotor with its bearings
               replaced by 1 N/m supports (a model needs a stiffness path
               to ground), supports varied at stations 3 and 18, 13
               stiffnesses 1e6..1e10 N/m x 50 speeds 0..1600 rad/s
``unbalance``  load + ``unbalance_response(model, ..., 600 speeds)``
``static``     load + ``static_deflection(model)`` (gravity)
``equations``  ``rotorkit equations examples/compressor.toml`` (the CLI)
``cli-campbell``, ``cli-unbalance``, ``cli-static``, ``cli-modes``
               the linear CLI commands on the file as a user types them
               (``rotorkit campbell FILE --speeds 0:1600:33``, ``rotorkit
               unbalance FILE --speeds 10:1600:600 --unbalance 8:1.5e-3
               --station 8``, ``rotorkit static FILE``, ``rotorkit modes
               FILE``), tables printed, CSV and figures written (to a
               temporary folder): the figures (matplotlib) are part of it
``load``       ``import rotorkit`` + the model file alone (the fixed part of
               every task above: numpy and rotorkit's own modules)
``python``     ``import numpy`` alone: the floor under every task (the
               interpreter, this environment's ``site`` with its ``.pth``
               hooks, numpy), measured in the same run

``--pyc`` lets Python keep rotorkit's bytecode (in a temporary
``PYTHONPYCACHEPREFIX``, filled by the untimed first run of a warm task), as
an installed package has it (pip compiles the ``.pyc`` files on install);
without it, an environment with ``PYTHONDONTWRITEBYTECODE=1`` (this
machine's) compiles every rotorkit module from source in every process.

``--root DIR`` runs the tasks against the rotorkit of another tree (e.g. an
older checkout, for a before/after table; tasks that tree cannot run fail).

BLAS runs on one thread (``OPENBLAS_NUM_THREADS=1``, as in
``bench/bench_linear.py``): on this shared 2-core machine a threaded dense
eigen-solution of the 160 x 160 state matrix ran 10-20 times slower than
one thread (oversubscription), which no user's workstation shows.

Cache states: ``cold`` is an empty model cache (``ROTORKIT_CACHE_DIR`` a new
temporary folder for each run: the derivation once, then the task); ``warm``
is a cache filled by one earlier run of the same task (not timed), as on a
user's second day. The times are those of the whole process (interpreter
start, imports and all), medians of ``--repeat`` runs: wall-clock, and CPU
(user + system of the child process; on a loaded machine the better guide,
since wall time there includes waiting for a core). The load average is
printed with them. On a shared machine absolute times vary
between runs: quote the command, the medians and the load together.
"""

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FILE = ROOT / "examples" / "compressor.toml"

_LOAD = "import numpy as np, rotorkit as rk\nmodel = rk.load_model({file!r})\n"
TASKS = {
    "campbell": _LOAD + (
        "from rotorkit.linear.campbell import campbell\n"
        "diagram = campbell(model, np.linspace(0.0, 1600.0, 33), n_modes=6)\n"
        "assert len(diagram.speeds) == 33\n"),
    "map": _LOAD + (
        "from rotorkit import ElasticSupport, Model\n"
        "from rotorkit.elements import LinearBearing\n"
        "from rotorkit.linear.linear_model import linear_model\n"
        "from rotorkit.linear.critical_map import critical_speed_map\n"
        "shaft = Model([e for e in model.elements if not isinstance(e, LinearBearing)]\n"
        "              + [ElasticSupport(station=s, stiffness=1.0) for s in (3, 18)], name='compressor_shaft')\n"
        "result = critical_speed_map(linear_model(shaft), supports=(3, 18), stiffnesses=np.logspace(6, 10, 13),\n"
        "                            speed_range=(0.0, 1600.0), n_speeds=50)\n"
        "assert result.speeds.shape[0] == 13\n"),
    "unbalance": _LOAD + (
        "from rotorkit.linear.unbalance import Unbalance, unbalance_response\n"
        "response = unbalance_response(model, [Unbalance(station=8, magnitude=1.5e-3)],\n"
        "                              np.linspace(10.0, 1600.0, 600))\n"
        "assert response.components['R'].shape == (600, 80)\n"),
    "static": _LOAD + (
        "from rotorkit.linear.static import static_deflection\n"
        "result = static_deflection(model)\n"
        "assert result.deflection['y10'] < 0\n"),
    "load": _LOAD,
    "python": "import numpy as np\n",
    "equations": None,  # the CLI
    "cli-campbell": None,
    "cli-unbalance": None,
    "cli-static": None,
    "cli-modes": None,
}
#: the linear CLI commands: arguments after the file
CLI = {
    "cli-campbell": ["campbell", "{file}", "--speeds", "0:1600:33"],
    "cli-unbalance": ["unbalance", "{file}", "--speeds", "10:1600:600", "--unbalance", "8:1.5e-3", "--station", "8"],
    "cli-static": ["static", "{file}"],
    "cli-modes": ["modes", "{file}"],
}


def command(task, file, out=None):
    if task == "equations":
        return [sys.executable, "-m", "rotorkit.cli", "equations", str(file)]
    if task in CLI:
        return [sys.executable, "-m", "rotorkit.cli"] + [a.format(file=str(file)) for a in CLI[task]] + [
            "--out", str(out)]
    return [sys.executable, "-c", TASKS[task].format(file=str(file))]


def _children_cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run(task, file, cache, root=ROOT, pyc=None):
    """(wall s, CPU s) of one fresh process doing ``task``; ``pyc``: a folder for Python's bytecode cache."""
    env = dict(os.environ, ROTORKIT_CACHE_DIR=str(cache), PYTHONPATH=str(root), OPENBLAS_NUM_THREADS="1",
               OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    if pyc is not None:  # as an installed package: rotorkit's modules from their .pyc, not compiled again
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(pyc)
    with tempfile.TemporaryDirectory(prefix="rotorkit-bench-out-") as out:  # the CLI tasks write there
        cpu0, t0 = _children_cpu(), time.perf_counter()
        # cwd comes first on the child's sys.path: run in the tree whose rotorkit is measured
        proc = subprocess.run(command(task, file, out), env=env, capture_output=True, text=True, cwd=root)
        elapsed, cpu = time.perf_counter() - t0, _children_cpu() - cpu0
    if proc.returncode != 0:
        raise SystemExit(f"{task} failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    return elapsed, cpu


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--tasks", nargs="+", default=list(TASKS), choices=list(TASKS))
    parser.add_argument("--cache", nargs="+", default=["cold", "warm"], choices=("cold", "warm"))
    parser.add_argument("--file", default=str(FILE), help="model file (default examples/compressor.toml)")
    parser.add_argument("--root", default=str(ROOT), help="tree whose rotorkit is run (default this one)")
    parser.add_argument("--pyc", action="store_true",
                        help="let Python keep rotorkit's bytecode (.pyc, in a temporary PYTHONPYCACHEPREFIX filled by "
                             "the untimed first run of a warm task) as an installed package has it; by default the "
                             "environment decides (PYTHONDONTWRITEBYTECODE=1 compiles every module in every process)")
    args = parser.parse_args(argv)
    bytecode = ("rotorkit's .pyc kept (--pyc)" if args.pyc else
                "no .pyc (PYTHONDONTWRITEBYTECODE)" if os.environ.get("PYTHONDONTWRITEBYTECODE") else "")
    print(f"{Path(args.file).name}: fresh process per run, from interpreter start; medians of {args.repeat} "
          f"(min..max); one BLAS thread; {bytecode + '; ' if bytecode else ''}"
          f"load average before the run: {os.getloadavg()[0]:.2f}")
    print(f"{'task':<10} {'cache':<5} {'wall s':>7} {'min..max s':>14} {'CPU s':>6} {'min..max s':>14} {'load':>5}")
    with tempfile.TemporaryDirectory(prefix="rotorkit-bench-") as tmp:
        for task in args.tasks:
            for state in args.cache:
                times = []
                pyc = Path(tmp) / f"pyc-{state}-{task}" if args.pyc else None
                if state == "warm":
                    cache = Path(tmp) / f"warm-{task}"
                    run(task, args.file, cache, args.root, pyc)  # fill the caches, not timed
                for i in range(args.repeat):
                    if state == "cold":
                        cache = Path(tmp) / f"cold-{task}-{i}"
                        pyc = Path(tmp) / f"pyc-cold-{task}-{i}" if args.pyc else None
                    times.append(run(task, args.file, cache, args.root, pyc))
                wall, cpu = [t for t, _ in times], [c for _, c in times]
                print(f"{task:<10} {state:<5} {statistics.median(wall):>7.2f} {min(wall):>6.2f}..{max(wall):<6.2f} "
                      f"{statistics.median(cpu):>6.2f} {min(cpu):>6.2f}..{max(cpu):<6.2f} "
                      f"{os.getloadavg()[0]:>5.2f}", flush=True)


if __name__ == "__main__":
    main()
