"""``rotorkit accuracy``: work-precision study of methods, engines and tolerances against a tight reference."""

from pathlib import Path

from ..errors import ParameterError
from ..system import COMPILED_BACKENDS
from .common import add_scene_arguments, load_preset, positive_float, save_figure


def register(sub):
    acc = sub.add_parser("accuracy", help="work-precision study: methods, engines, tolerances vs a tight reference")
    add_scene_arguments(acc)
    acc.add_argument("--out", help="output folder (default rotorkit-out/<preset>-accuracy)")
    acc.add_argument("--t-end", type=positive_float, help="end time in s (default: the preset's)")
    acc.add_argument("--cases", help="engine:method list, e.g. compiled:DOP853,scipy:Radau,scipy+events:DOP853 "
                     "(default: all but events)")
    acc.add_argument("--tolerances", help="rtol list, e.g. 1e-4,1e-6,1e-8 (default 1e-3 ... 1e-10); atol = 1e-3 rtol")
    acc.add_argument("--reference-rtol", type=positive_float, default=1e-12, help="rtol of the reference run (default 1e-12)")
    acc.add_argument("--window", default="2.2,3.8", help="spectral window start,end in s")
    acc.add_argument("--budget", type=positive_float, default=60.0,
                     help="skip a method's tighter tolerances once one run takes longer than this (s)")
    acc.set_defaults(func=main)



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


def main(args):
    import csv
    import io

    from .. import accuracy
    from ..files import atomic_write_text
    from ..plotting.basic import new_axes
    from ..plotting.work_precision import plot_error_growth, plot_work_precision
    from ..simulate import simulate

    module, model, _ = load_preset(args)
    system = model.compile()
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
    written = [out / "accuracy.csv", save_figure(fig, out / "work_precision.png")]
    growth = {}
    engine = "compiled" if system.backend in COMPILED_BACKENDS else "scipy"
    for rtol in (1e-4, 1e-6, 1e-8):
        growth[f"DOP853 rtol {rtol:g}"] = simulate(system, (0.0, t_end), rtol=rtol, atol=rtol * accuracy.ATOL_PER_RTOL,
                                                   engine=engine)
    ax = plot_error_growth(growth, reference, signals[0], ax=new_axes(None, figsize=(7, 4)))
    ax.set_title("pointwise error of x2 over the run (DOP853 against the reference)")
    written.append(save_figure(ax.figure, out / "error_growth.png"))
    for p in written:
        print(f"wrote {p}")
    return 0


