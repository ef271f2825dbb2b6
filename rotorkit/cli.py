"""Command line: ``rotorkit run``, ``rotorkit equations``, ``rotorkit list``."""

import argparse
import json
import re
import sys
import time
from pathlib import Path

from .errors import ParameterError, RotorkitError, SimulationError

__all__ = ["main", "parse_assignment"]

_TRUE, _FALSE = {"true", "yes", "on", "1"}, {"false", "no", "off", "0"}
#: a --set value: a plain decimal number, optionally followed by a unit expression (letters, /, *, ^, spaces)
_QUANTITY = re.compile(r"^\s*([+-]?(?:inf|(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d{1,3})?))\s*"
                       r"((?![eE][+-]?\d)(?:1\s*/\s*)?[A-Za-zµ°Ω][A-Za-zµ°Ω0-9_ /*^.\-]*)?\s*$")


def parse_assignment(text, defaults=None):
    """Parse ``name=value`` strictly: a float, a pint quantity (``"2e6 N/m"``) or a switch.

    Parameters
    ----------
    text : str
    defaults : dict, optional
        Known names -> default values; a bool default makes the value a switch.

    Returns
    -------
    (str, object)
    """
    if "=" not in text:
        raise ParameterError(f"--set {text!r}: expected name=value, e.g. rub_stiffness=2e6")
    name, raw = (s.strip() for s in text.split("=", 1))
    if not name.isidentifier():
        raise ParameterError(f"--set {text!r}: {name!r} is not a parameter name")
    if defaults is not None and isinstance(defaults.get(name), bool):
        low = raw.lower()
        if low in _TRUE | _FALSE:
            return name, low in _TRUE
        raise ParameterError(f"--set {name}={raw!r}: expected true or false")
    match = _QUANTITY.match(raw)
    if not match:
        raise ParameterError(
            f"--set {name}={raw!r}: not a number or a quantity with units (e.g. 2e6 or '2e6 N/m')"
        )
    number, unit = match.group(1), match.group(2)
    value = float(number)  # a non-finite value is refused by the parameter's own check
    if not unit:
        return name, value
    from .units import registry

    if re.search(r"\d\s*\*\*|\*\*\s*\d{3,}", unit):
        raise ParameterError(f"--set {name}={raw!r}: the unit {unit!r} is not a unit expression")
    try:
        quantity = value * registry().Unit(unit)
    except Exception as exc:
        raise ParameterError(f"--set {name}={raw!r}: {unit!r} is not a unit pint knows (e.g. N/m, mm, rpm)") from exc
    return name, quantity


def _progress_printer():
    state = {"last": -1}
    tty = sys.stderr.isatty()

    def report(fraction, t):
        if tty:
            bar = "#" * int(30 * fraction)
            sys.stderr.write(f"\r  simulating [{bar:<30}] {100 * fraction:5.1f} %  t = {t:.3f} s")
            if fraction >= 1:
                sys.stderr.write("\n")
        else:
            decile = int(10 * fraction)
            if decile > state["last"]:
                state["last"] = decile
                sys.stderr.write(f"  simulating: {100 * fraction:5.1f} %  t = {t:.3f} s\n")
        sys.stderr.flush()

    return report


def _cmd_run(args):
    from .presets import preset_module
    from .simulate import simulate

    module = preset_module(args.preset)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    overrides = dict(parse_assignment(s, known) for s in args.set)
    outputs = getattr(module, "OUTPUTS", {})
    t_end = args.t_end if args.t_end is not None else outputs.get("t_end", 1.0)
    start = time.perf_counter()
    model = module.build(**overrides)
    system = model.compile(backend=args.backend)
    compiled = time.perf_counter()
    print(f"{model!r}\ncompiled in {compiled - start:.2f} s (backend {system.backend})")
    try:
        result = simulate(system, (0.0, t_end), method=args.method, rtol=args.rtol, atol=args.atol,
                          sample_rate=args.sample_rate, engine=args.engine, progress=_progress_printer())
    except SimulationError as err:
        if err.partial is not None and err.partial.t.size:
            out = Path(args.out or f"rotorkit-out/{args.preset}")
            path = err.partial.save(out / "signals-partial.npz")
            print(f"partial result written to {path}", file=sys.stderr)
        raise
    stats = result.stats
    print(f"simulated 0-{t_end:g} s in {stats['wall_time']:.2f} s: {stats['nfev']} RHS evaluations, "
          f"{stats['engine']} engine, method {stats['method']}, rtol {stats['rtol']:g}, atol {stats['atol']:g}")
    out = Path(args.out or f"rotorkit-out/{args.preset}")
    written = _write_outputs(result, outputs, out)
    for p in written:
        print(f"wrote {p}")
    return 0


def _write_outputs(result, outputs, out):
    from .files import atomic_write_text
    from .plotting.basic import plot_orbit, plot_signals

    out.mkdir(parents=True, exist_ok=True)
    written = [result.save(out / "signals.npz")]
    station = outputs.get("orbit_station")
    clearance = result.parameters.get(outputs.get("clearance_parameter", ""), None)
    if station is not None:
        ax = plot_orbit(result, station, clearance=clearance)
        written.append(_save_figure(ax.figure, out / f"orbit_station{station}.png"))
    for key, scale, unit in (("bending", 1e6, "µm"), ("torsion", 1e6, "µrad")):
        name = outputs.get(key)
        if name:
            ax = plot_signals(result, name, scale=scale, unit_label=unit)
            written.append(_save_figure(ax.figure, out / f"{name.replace('-', '_minus_')}.png"))
    summary = {"name": result.name, "stats": {k: v for k, v in result.stats.items()},
               "parameters": result.parameters}
    atomic_write_text(out / "summary.json", json.dumps(summary, indent=2, default=float))
    written.append(out / "summary.json")
    return written


def _save_figure(fig, path):
    import io

    from .files import atomic_write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120)
    atomic_write_bytes(path, buf.getvalue())
    return path


def _cmd_equations(args):
    from .presets import preset_module

    module = preset_module(args.preset)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    model = module.build(**dict(parse_assignment(s, known) for s in args.set))
    eom = model.equations()
    if args.latex:
        print(eom.latex())
    else:
        print(f"{model!r}\n\n{model.parameter_table()}\n\n{eom}")
    return 0


def _cmd_list(args):
    from .presets import list_presets, preset_module

    for name in list_presets():
        print(f"{name}: {preset_module(name).DESCRIPTION}")
    return 0


def _parse_cases(text):
    cases = []
    for item in text.split(","):
        engine, _, method = item.strip().partition(":")
        if engine not in ("compiled", "scipy", "scipy+events") or not method:
            raise ParameterError(f"--cases {item!r}: expected engine:method, e.g. compiled:DOP853, scipy:Radau "
                                 "or scipy+events:DOP853")
        cases.append((engine, method))
    return tuple(cases)


def _parse_floats(text, name):
    try:
        return tuple(float(v) for v in text.split(","))
    except ValueError:
        raise ParameterError(f"{name} {text!r}: expected comma-separated numbers, e.g. 1e-4,1e-6") from None


def _cmd_accuracy(args):
    import csv
    import io

    from . import accuracy
    from .files import atomic_write_text
    from .plotting.basic import new_axes
    from .plotting.work_precision import plot_error_growth, plot_work_precision
    from .presets import preset_module
    from .simulate import simulate

    module = preset_module(args.preset)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    system = module.build(**dict(parse_assignment(s, known) for s in args.set)).compile()
    outputs = getattr(module, "OUTPUTS", {})
    signals = tuple(n for n in (outputs.get("bending"), outputs.get("torsion")) if n)
    t_end = args.t_end if args.t_end is not None else outputs.get("t_end", 1.0)
    cases = _parse_cases(args.cases) if args.cases else accuracy.DEFAULT_CASES
    tolerances = _parse_floats(args.tolerances, "--tolerances") if args.tolerances else accuracy.DEFAULT_TOLERANCES
    window = _parse_floats(args.window, "--window")
    print(f"reference: DOP853 rtol {args.reference_rtol:g} ...", flush=True)
    reference = accuracy.reference_run(system, (0.0, t_end), rtol=args.reference_rtol)
    check = accuracy.reference_run(system, (0.0, t_end), rtol=args.reference_rtol * 10)
    ref_pw, ref_sp = accuracy.errors(check, reference, signals, window)
    print(f"reference took {reference.stats['wall_time']:.2f} s; its own error (vs rtol x10): pointwise "
          + ", ".join(f"{k} {v:.1e}" for k, v in ref_pw.items()) + "; spectral "
          + ", ".join(f"{k} {v:.1e}" for k, v in ref_sp.items()))
    header = f"{'engine':12s} {'method':7s} {'rtol':>7s} {'wall s':>8s} {'nfev':>9s} " + " ".join(
        f"{'pt ' + n:>16s} {'spec ' + n:>18s}" for n in signals)
    print(header)

    def report(run):
        cols = " ".join(f"{run.pointwise.get(n, float('nan')):16.2e} {run.spectral.get(n, float('nan')):18.2e}"
                        for n in signals)
        status = "" if run.success else f"  FAILED: {run.message}"
        print(f"{run.engine:12s} {run.method:7s} {run.rtol:7.0e} {run.wall_time:8.2f} {run.nfev:9d} {cols}{status}",
              flush=True)

    runs, _ = accuracy.study(system, (0.0, t_end), cases=cases, tolerances=tolerances, signals=signals,
                             window=window, reference=reference, budget=args.budget, report=report)
    out = Path(args.out or f"rotorkit-out/{args.preset}-accuracy")
    out.mkdir(parents=True, exist_ok=True)
    rows = accuracy.to_rows(runs, signals)
    buf = io.StringIO()
    writer = csv.DictWriter(buf, fieldnames=list(rows[0]))
    writer.writeheader()
    writer.writerows(rows)
    atomic_write_text(out / "accuracy.csv", buf.getvalue())

    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 8.5), layout="constrained")
    axes = fig.subplots(2, len(signals), squeeze=False)
    for col, name in enumerate(signals):
        plot_work_precision(runs, name, "pointwise", ax=axes[0, col])
        plot_work_precision(runs, name, "spectral", ax=axes[1, col])
    fig.suptitle(f"{args.preset}: error against wall time, 0-{t_end:g} s (reference DOP853 rtol {args.reference_rtol:g}; "
                 f"spectra {window[0]:g}-{window[1]:g} s)")
    written = [out / "accuracy.csv", _save_figure(fig, out / "work_precision.png")]
    growth = {}
    engine = "compiled" if system.backend == "numba" else "scipy"
    for rtol in (1e-4, 1e-6, 1e-8):
        growth[f"DOP853 rtol {rtol:g}"] = simulate(system, (0.0, t_end), rtol=rtol, atol=rtol * accuracy.ATOL_PER_RTOL,
                                                   engine=engine)
    ax = plot_error_growth(growth, reference, signals[0], ax=new_axes(None, figsize=(7, 4)))
    ax.set_title("pointwise error of x2 over the run (DOP853 against the reference)")
    written.append(_save_figure(ax.figure, out / "error_growth.png"))
    for p in written:
        print(f"wrote {p}")
    return 0


def _cmd_stiffness(args):
    from .analysis.stiffness import stiffness_report
    from .presets import preset_module
    from .simulate import simulate

    module = preset_module(args.preset)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    system = module.build(**dict(parse_assignment(s, known) for s in args.set)).compile()
    trial = simulate(system, (0.0, args.t_end), sample_rate=1000.0)
    report = stiffness_report(system, trial)
    print(f"fastest time scale {report.fastest_time_scale:.3g} s, slowest {report.slowest_time_scale:.3g} s, "
          f"stiffness ratio {report.ratio:.3g} (states at rest and along 0-{args.t_end:g} s)")
    print(f"suggested method: {report.suggested_method}: {report.reason}")
    return 0


def _cmd_validate(args):
    from .presets import preset_module
    from .validation import Study, format_table

    module = preset_module(args.preset)
    claims = getattr(module, "CLAIMS", ())
    if not claims:
        raise ParameterError(f"preset {args.preset!r} defines no CLAIMS to validate")
    outputs = getattr(module, "OUTPUTS", {})
    signals = {"bending": outputs["bending"], "torsion": outputs["torsion"]}

    def progress(done, overrides, status):
        text = ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}" for k, v in overrides.items())
        print(f"  run {done}: {text or 'defaults'}: {status}", file=sys.stderr, flush=True)

    study = Study(args.preset, signals, t_end=outputs.get("t_end", 6.0), progress=progress)
    results = [claim(study) for claim in claims]
    table = format_table(results)
    print(table)
    if args.out:
        from .files import atomic_write_text

        out = Path(args.out)
        atomic_write_text(out / "claims.txt", table + "\n")
        print(f"wrote {out / 'claims.txt'}")
    return 0


def _cmd_sweep(args):
    from .plotting.spectra import plot_cascade, speed_orders
    from .presets import preset_module
    from .sweep import parse_range, run_sweep

    module = preset_module(args.preset)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    name, values = parse_range(args.param)
    if name not in module.DEFAULTS:
        import difflib

        near = difflib.get_close_matches(name, list(module.DEFAULTS), n=3)
        raise ParameterError(f"--param {name!r} is not a parameter of {args.preset}"
                             + (f"; did you mean {', '.join(near)}?" if near else ""))
    overrides = dict(parse_assignment(s, known) for s in args.set)
    out = Path(args.out or f"rotorkit-out/{args.preset}-sweep-{name}")

    def progress(done, total, value, status):
        print(f"  [{done:3d}/{total}] {name} = {value:g}: {status}", file=sys.stderr, flush=True)

    cascade = run_sweep(args.preset, name, values, out_dir=out, overrides=overrides, workers=args.workers,
                        progress=progress)
    speed = float(overrides.get("lp_speed", module.DEFAULTS.get("lp_speed", 0.0)) or 0.0)
    ratio = float(overrides.get("speed_ratio", module.DEFAULTS.get("speed_ratio", 1.0)))
    if name == "lp_speed":
        orders = lambda value: speed_orders(value, ratio)  # noqa: E731
    elif name == "speed_ratio":
        orders = lambda value: speed_orders(speed, value)  # noqa: E731
    else:
        orders = speed_orders(speed, ratio) if speed else None
    written = []
    for signal in cascade.signals:
        ax = plot_cascade(cascade, signal, orders=orders, fmax=args.fmax)
        written.append(_save_figure(ax.figure, out / f"cascade_{signal.replace('-', '_minus_')}.png"))
    counts = {st: int((cascade.status == st).sum()) for st in ("ok", "failed", "runaway")}
    print(f"{len(values)} points: " + ", ".join(f"{n} {st}" for st, n in counts.items() if n))
    for i in range(len(values)):
        if cascade.status[i] != "ok":
            print(f"  {name} = {values[i]:g}: {cascade.status[i]}: {cascade.messages[i].splitlines()[0]}")
    for p in written:
        print(f"wrote {p}")
    print(f"point spectra in {out} (an interrupted sweep resumes there)")
    return 0


def _cmd_cache(args):
    from .codegen import cache

    if args.action == "clear":
        print(f"removed {cache.clear()} cached model(s) from {cache.cache_dir()}")
    else:
        folder, count, size = cache.info()
        print(f"{folder}: {count} cached model(s), {size / 1e6:.1f} MB")
    return 0


def build_parser():
    parser = argparse.ArgumentParser(prog="rotorkit", description="Rotordynamics models: derive, compile, simulate.")
    sub = parser.add_subparsers(dest="command", required=True)

    run = sub.add_parser("run", help="simulate a preset and write plots and signals")
    run.add_argument("preset", help="preset name, e.g. al31f (see 'rotorkit list')")
    run.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                     help="override a preset parameter (SI number or quantity, e.g. rub_stiffness=2e6)")
    run.add_argument("--out", help="output folder (default rotorkit-out/<preset>)")
    run.add_argument("--t-end", type=float, help="end time in s (default: the preset's, 6 s for al31f)")
    run.add_argument("--method", default="DOP853", help="solve_ivp method (default DOP853)")
    run.add_argument("--rtol", type=float, default=1e-6)
    run.add_argument("--atol", type=float, default=1e-9)
    run.add_argument("--sample-rate", type=float, default=10_000.0, help="output samples per second")
    run.add_argument("--backend", default="auto", choices=("auto", "python", "numba"))
    run.add_argument("--engine", default="auto", choices=("auto", "compiled", "scipy"),
                     help="integration engine (auto: compiled when numba is available)")
    run.set_defaults(func=_cmd_run)

    eq = sub.add_parser("equations", help="print the derived equations of a preset")
    eq.add_argument("preset")
    eq.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    eq.add_argument("--latex", action="store_true", help="print LaTeX instead of text")
    eq.set_defaults(func=_cmd_equations)

    acc = sub.add_parser("accuracy", help="work-precision study: methods, engines, tolerances vs a tight reference")
    acc.add_argument("preset")
    acc.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    acc.add_argument("--out", help="output folder (default rotorkit-out/<preset>-accuracy)")
    acc.add_argument("--t-end", type=float)
    acc.add_argument("--cases", help="engine:method list, e.g. compiled:DOP853,scipy:Radau,scipy+events:DOP853 "
                     "(default: all but events)")
    acc.add_argument("--tolerances", help="rtol list, e.g. 1e-4,1e-6,1e-8 (default 1e-3 ... 1e-10); atol = 1e-3 rtol")
    acc.add_argument("--reference-rtol", type=float, default=1e-12)
    acc.add_argument("--window", default="2.2,3.8", help="spectral window start,end in s")
    acc.add_argument("--budget", type=float, default=60.0,
                     help="skip a method's tighter tolerances once one run takes longer than this (s)")
    acc.set_defaults(func=_cmd_accuracy)

    st = sub.add_parser("stiffness", help="time scales of a scene and the integration method that fits")
    st.add_argument("preset")
    st.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    st.add_argument("--t-end", type=float, default=0.5, help="length of the trial run whose states are scanned (s)")
    st.set_defaults(func=_cmd_stiffness)

    sw = sub.add_parser("sweep", help="spectrum cascade over a swept parameter (parallel, resumable)")
    sw.add_argument("preset")
    sw.add_argument("--param", required=True, metavar="NAME=START:STOP:N",
                    help="e.g. rub_stiffness=5e5:2e7:40, friction_coefficient=0:0.3:16, lp_speed=log:500:3000:20, "
                         "or a list friction_coefficient=0,0.1,0.2")
    sw.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    sw.add_argument("--out", help="output folder (default rotorkit-out/<preset>-sweep-<param>)")
    sw.add_argument("--workers", type=int, default=2, help="local processes (default 2)")
    sw.add_argument("--fmax", type=float, default=5000.0, help="largest frequency drawn (rad/s)")
    sw.set_defaults(func=_cmd_sweep)

    va = sub.add_parser("validate", help="check the paper's claims from simulated spectra and print the table")
    va.add_argument("preset")
    va.add_argument("--out", help="also write claims.txt here")
    va.set_defaults(func=_cmd_validate)

    ca = sub.add_parser("cache", help="show or clear the cache of generated models")
    ca.add_argument("action", choices=("info", "clear"))
    ca.set_defaults(func=_cmd_cache)

    ls = sub.add_parser("list", help="list the bundled presets")
    ls.set_defaults(func=_cmd_list)
    return parser


def main(argv=None):
    """Entry point of the ``rotorkit`` command: returns 0, or 2 on a usage or input error."""
    try:
        args = build_parser().parse_args(argv)
    except SystemExit as exit_:  # argparse printed its usage message
        return int(exit_.code or 0)
    try:
        return args.func(args)
    except RotorkitError as err:
        print(f"rotorkit: error: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
