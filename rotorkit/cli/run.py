"""``rotorkit run``: simulate a scene and write plots and signals."""

import json
import sys
import time
from pathlib import Path

from ..errors import SimulationError
from .common import add_scene_arguments, load_preset, positive_float, progress_printer
from .figures import FigureProcess, write_figures


def register(sub):
    run = sub.add_parser("run", help="simulate a preset or model file and write plots and signals")
    add_scene_arguments(run)
    run.add_argument("--out", help="output folder (default rotorkit-out/<preset>)")
    run.add_argument("--t-end", type=positive_float, help="end time in s (default: the preset's, 6 s for al31f)")
    run.add_argument("--method", default="DOP853", help="solve_ivp method (default DOP853)")
    run.add_argument("--rtol", type=positive_float, default=1e-6, help="relative tolerance (default 1e-6)")
    run.add_argument("--atol", type=positive_float, default=1e-9, help="absolute tolerance in SI units (default 1e-9)")
    run.add_argument("--sample-rate", type=positive_float, default=10_000.0, help="output samples per second (default 10000)")
    run.add_argument("--backend", default="auto", choices=("auto", "c", "numba", "python"),
                     help="code back end (auto: c when a C compiler is found, else numba when installed)")
    run.add_argument("--engine", default="auto", choices=("auto", "compiled", "scipy"),
                     help="integration engine (auto: compiled with the c or numba back end)")
    run.add_argument("--check-convergence", action="store_true",
                     help="also run at 100 times tighter tolerances and report how far the two differ "
                          "(about twice the time; see docs/envelope.md)")
    run.add_argument("--no-figures", action="store_true", help="write the signals and the summary, no figures")
    run.set_defaults(func=main)


def main(args):
    start = time.perf_counter()
    helper = None if args.no_figures else FigureProcess.start()  # first: imports matplotlib while this one works
    try:
        return _run(args, start, helper)
    finally:
        if helper is not None:
            helper.close()


def _run(args, start, helper):
    from ..files import check_output_folder
    from ..simulate import simulate

    _compile_integrator_ahead(args)  # first: it has the longest way to go, and the preset's import is its head start
    module, model, _ = load_preset(args)  # reads the scene (a model file names args.preset); derives nothing
    out = check_output_folder(args.out if args.out is not None else f"rotorkit-out/{args.preset}")  # before any work
    outputs = getattr(module, "OUTPUTS", {})
    t_end = args.t_end if args.t_end is not None else outputs.get("t_end", 1.0)
    system = model.compile(backend=args.backend)
    compiled = time.perf_counter()
    print(f"{model!r}\ncompiled in {compiled - start:.2f} s (backend {system.backend})")
    options = dict(method=args.method, rtol=args.rtol, atol=args.atol, sample_rate=args.sample_rate,
                   engine=args.engine, progress=progress_printer())
    if args.check_convergence:
        options["check_convergence"] = True
    measurement = None
    try:
        if outputs.get("sensors"):  # the preset's virtual sensors, each at its own rate
            from ..sensors import measure
            from ..validation import initial_state

            measurement = measure(system, (0.0, t_end), outputs["sensors"],
                                  y0=initial_state(system, outputs.get("start")), **options)
            result = measurement.result
        else:
            result = simulate(system, (0.0, t_end), **options)
    except SimulationError as err:
        if err.partial is not None and err.partial.t.size:
            path = _keep(err.partial, out, "signals-partial.npz")
            print(f"partial result written to {path}", file=sys.stderr)
        raise
    stats = result.stats
    print(f"simulated 0-{t_end:g} s in {stats['wall_time']:.2f} s: {stats['nfev']} RHS evaluations, "
          f"{stats['engine']} engine, method {stats['method']}, rtol {stats['rtol']:g}, atol {stats['atol']:g}")
    if "convergence" in stats:
        print(f"convergence check: {stats['convergence']['message']}")
    from ..files import write_folder
    from ..interrupts import check

    check()  # a Ctrl-C swallowed since the run ended: stop before writing
    try:
        written = write_folder(out, lambda folder: write_outputs(result, outputs, folder, measurement,
                                                                 figures=not args.no_figures, helper=helper))
    except OSError as exc:  # late failure (disk full, folder removed): the data is kept
        path = _keep(result, None, "signals.npz")
        print(f"rotorkit: error: {exc}\nthe signals are kept in {path}", file=sys.stderr)
        return 1
    for p in written:
        print(f"wrote {p}")
    return 0


def _compile_integrator_ahead(args):
    """On a cold cache, build the integration loop beside this process's derivation and compilation of the model.

    c back end: gcc in a thread's child process (:func:`rotorkit.engines.rk_c.build_in_background`); numba: another
    process (:func:`rotorkit.engines.rk_numba.compile_loop_in_background`). Nothing happens when the run will not
    use the compiled engine or the loop is loaded already.
    """
    from ..simulate import COMPILED_METHODS
    from ..system import resolve_backend

    if args.engine == "scipy" or args.method not in COMPILED_METHODS:
        return None
    backend = resolve_backend(args.backend)
    if backend == "c":
        from ..engines.rk_c import build_in_background

        return build_in_background()
    if backend != "numba":
        return None
    from ..engines.rk_numba import compile_loop_in_background

    return compile_loop_in_background()


def _keep(result, out, name):
    """Save ``result`` into ``out``, or (if that fails) into a new temporary folder; the path written."""
    import tempfile

    if out is not None:
        try:
            out.mkdir(parents=True, exist_ok=True)
            return result.save(out / name)
        except OSError:
            pass
    return result.save(Path(tempfile.mkdtemp(prefix="rotorkit-rescue-")) / name)


def write_outputs(result, outputs, out, measurement=None, *, figures=True, helper=None):
    """Write a run's signals, its preset's standard figures (and sensor records) and a summary into the folder ``out``.

    ``main`` calls it through :func:`rotorkit.files.write_folder`, so the files land together. The figures
    (:func:`rotorkit.cli.figures.write_figures`; none with ``figures=False``) are drawn by ``helper`` (a
    :class:`~rotorkit.cli.figures.FigureProcess`) while this process writes the signals, or here without one.
    """
    from ..files import atomic_write_text

    out.mkdir(parents=True, exist_ok=True)
    remote = figures and helper is not None and helper.submit(result, outputs, out, measurement)
    written = [result.save(out / "signals.npz")]
    if remote:
        written += helper.collect()
    elif figures:
        written += write_figures(result, outputs, out, measurement)
    summary = {"name": result.name, "stats": {k: v for k, v in result.stats.items()},
               "parameters": result.parameters}
    atomic_write_text(out / "summary.json", json.dumps(summary, indent=2, default=float))
    written.append(out / "summary.json")
    return written
