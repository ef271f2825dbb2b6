"""``rotorkit periodic``: periodic steady states of a nonlinear rotor along a parameter (harmonic balance)."""

import sys

from ..errors import ParameterError
from .common import add_scene_arguments, save_figure
from .linear_common import output_folder, write_text


def register(sub):
    p = sub.add_parser("periodic", help="periodic response by harmonic balance and continuation: branch, "
                                        "stability, bifurcations")
    add_scene_arguments(p)
    p.add_argument("--param", required=True, metavar="NAME=START:STOP",
                   help="continuation parameter and range (SI), e.g. R_speed=60:200 or rub1_clearance=1e-4:3e-4")
    p.add_argument("--harmonics", type=int, default=5, help="harmonics H of the base frequency (default 5)")
    p.add_argument("--subharmonic", type=int, default=1, metavar="NU",
                   help="base frequency Omega / NU (default 1: synchronous)")
    p.add_argument("--station", action="append", default=[], help="station whose response is plotted (default all)")
    p.add_argument("--speed-parameter", help="rotor speed setting the base frequency (default: the first rotor's)")
    p.add_argument("--stability", default="hill", choices=("hill", "monodromy", "none"),
                   help="Floquet multipliers by Hill's method (default), the monodromy matrix, or none")
    p.add_argument("--max-points", type=int, default=500, help="point budget of the branch (default 500)")
    p.add_argument("--backend", default="auto", choices=("auto", "c", "numba", "python"), help="code back end")
    p.add_argument("--out", help="output folder (default rotorkit-out/<scene>)")
    p.set_defaults(func=main)


def _parse_param(text):
    name, _, rest = text.partition("=")
    parts = rest.split(":")
    try:
        start, stop = float(parts[0]), float(parts[1])
    except (ValueError, IndexError):
        raise ParameterError(f"--param {text!r}: expected NAME=START:STOP (SI), e.g. R_speed=60:200") from None
    if len(parts) != 2 or not name.strip():
        raise ParameterError(f"--param {text!r}: expected NAME=START:STOP (SI), e.g. R_speed=60:200")
    return name.strip(), start, stop


def main(args):
    from .figures import FigureProcess, warm_up_figures, warm_up_netcdf

    # first: a helper imports matplotlib and xarray (with dask installed, dask too: 2-3 s together) while this
    # process loads the model and follows the branch; it then writes the files
    helper = FigureProcess.start(warm_ups=(warm_up_figures, warm_up_netcdf))
    try:
        return _main(args, helper)
    finally:
        if helper is not None:
            helper.close()


def _main(args, helper):
    from ..analysis.periodic import continuation
    from .common import load_preset

    name, start, stop = _parse_param(args.param)
    _, model, _ = load_preset(args)
    system = model.compile(backend=args.backend)

    def progress(count, value):
        if count % 10 == 0:
            sys.stderr.write(f"  periodic: {count} points, {name} = {value:.6g}\n")
            sys.stderr.flush()

    branch = continuation(system, name, (start, stop), speed_parameter=args.speed_parameter,
                          harmonics=args.harmonics, subharmonic=args.subharmonic, stability=args.stability,
                          max_points=args.max_points, progress=progress)
    out = output_folder(args, "periodic")
    stations = args.station or sorted({c[1:] for c in branch.coordinate_names if c.startswith("x")
                                       and f"y{c[1:]}" in branch.coordinate_names})
    if helper is not None and helper.call(write_outputs, branch, stations, out):
        helper.collect()
    else:
        write_outputs(branch, stations, out)
    print(f"periodic branch: {len(branch)} points, {name} from {start:g} to {stop:g} ({branch.reason})")
    for b in branch.bifurcations:
        print(f"  {b.kind} at {name} = {b.parameter:.6g}")
    if branch.stable is not None:
        print(f"  stable points: {int(branch.stable.sum())} of {len(branch)}")
    print(f"  worst truncation estimate (fine-grid residual / force scale): {branch.residual_error.max():.3g}")
    print(f"wrote {out / 'periodic_branch.nc'}, {out / 'periodic_branch.csv'} and the response figures")
    return 0


def write_outputs(branch, stations, out):
    """Write ``periodic_branch.nc``, ``periodic_branch.csv`` (max radius of each station per point) and a
    response figure per station into the folder ``out``; returns their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    written = [out / "periodic_branch.nc", out / "periodic_branch.csv"]
    branch.save(written[0])
    rows = [f"{branch.parameter_name},stable," + ",".join(f"max_radius_{s}_m" for s in stations)]
    radii = [branch.max_radius(s) for s in stations]
    for i, value in enumerate(branch.parameter):
        stable = "" if branch.stable is None else str(int(branch.stable[i]))
        rows.append(",".join([f"{value:.10g}", stable] + [f"{r[i]:.10g}" for r in radii]))
    write_text(written[1], "\n".join(rows) + "\n")
    for s in stations:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        branch.plot_response(s, ax=ax)
        fig.tight_layout()
        written.append(save_figure(fig, out / f"periodic_response_{s}.png"))
        plt.close(fig)
    return written
