"""``rotorkit sweep``: an n-D parameter sweep (grid, list or Latin hypercube), local or on Dask, resumable."""

import sys

from ..errors import ParameterError
from .common import check_parameter_name, parse_overrides, positive_float, positive_int, save_figure


def register(sub):
    sw = sub.add_parser("sweep", help="n-D parameter sweep: spectra, orders, Poincare samples per point "
                                      "(local processes or a Dask cluster, resumable)")
    sw.add_argument("preset", metavar="SCENE",
                    help="preset name (e.g. al31f, see 'rotorkit list') or path to a model file (.toml)")
    sw.add_argument("--param", required=True, action="append", metavar="NAME=START:STOP:N",
                    help="a swept parameter; repeat for a grid (first slowest): rub_stiffness=5e5:2e7:40, "
                         "lp_speed=log:500:3000:20, or a list friction_coefficient=0,0.1,0.2")
    sw.add_argument("--zip", action="store_true",
                    help="pair the --param lists point by point (an explicit list of points) instead of a grid")
    sw.add_argument("--lhs", type=int, metavar="N",
                    help="Latin hypercube of N points within each --param's first and last value (log ranges "
                         "sampled in log)")
    sw.add_argument("--seed", type=int, default=0, help="seed of the Latin hypercube (default 0)")
    sw.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="override a preset parameter for every point")
    sw.add_argument("--signal", action="append", metavar="SIGNAL",
                    help="signal whose spectrum and orders are stored (x2, alpha2-alpha5); repeatable; default the "
                         "scene's bending and torsion outputs, else x of the first station")
    sw.add_argument("--order", action="append", default=[], metavar="ORDER",
                    help="store the peak amplitude of a speed order: 1/2, 1, 3/2 (of the first rotor), "
                         "'HP - LP', '1/2 LP'; repeatable")
    sw.add_argument("--poincare", action="append", metavar="SIGNAL",
                    help="signal sampled once per revolution (default: the spectra's signals); repeatable")
    sw.add_argument("--t-end", type=float, help="simulated time (s); default the preset's")
    sw.add_argument("--window", type=float, nargs=2, default=(2.2, 3.8), metavar=("T0", "T1"),
                    help="time window of the spectra, orders and Poincare samples (s); default 2.2 3.8")
    sw.add_argument("--energy", action="store_true", help="store each point's energy-balance residual")
    sw.add_argument("--out", help="output folder (default rotorkit-out/<preset>-sweep-<params>)")
    sw.add_argument("--workers", type=positive_int, default=2, help="local processes (default 2)")
    sw.add_argument("--scheduler", metavar="ADDRESS",
                    help="run on a Dask cluster: the scheduler's address, e.g. tcp://10.0.0.5:8786 "
                         "(needs rotorkit[distributed])")
    sw.add_argument("--max-points", type=positive_int, default=100_000, help="refuse larger sweeps (default 100000)")
    sw.add_argument("--fmax", type=positive_float, default=5000.0, help="largest frequency drawn in cascades (rad/s)")
    sw.set_defaults(func=main)


def _space(args):
    from ..sweep import Grid, PointList, latin_hypercube, parse_range

    ranges = [parse_range(p, args.max_points) for p in args.param]
    names = [n for n, _ in ranges]
    if len(set(names)) != len(names):
        raise ParameterError(f"--param names a parameter twice ({', '.join(names)})")
    if args.lhs is not None:
        if args.zip:
            raise ParameterError("--lhs and --zip exclude each other")
        bounds = {n: (min(v), max(v)) for n, v in ranges}
        log = [n for (n, _), text in zip(ranges, args.param) if text.split("=", 1)[1].strip().lower().startswith("log:")]
        return latin_hypercube(bounds, args.lhs, seed=args.seed, log=log, max_points=args.max_points)
    if args.zip:
        lengths = {len(v) for _, v in ranges}
        if len(lengths) != 1:
            raise ParameterError(f"--zip needs --param lists of one length (got {sorted(lengths)})")
        return PointList(names, list(zip(*[v for _, v in ranges])), max_points=args.max_points)
    return Grid(dict(ranges), max_points=args.max_points)


def main(args):
    from ..files import check_output_folder
    from ..plotting.maps import plot_bifurcation, plot_order_map, plot_status_map
    from ..plotting.spectra import plot_cascade, speed_orders
    from ..sweep import Cascade, Scene, run_sweep
    from .common import FileScene, scene_module

    module = scene_module(args)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    space = _space(args)
    for name in space.names:
        check_parameter_name(name, known, args.preset, what="--param")
    overrides = parse_overrides(args, known)
    # a model file travels to the workers as its elements (data), a preset by name
    scene = Scene.from_model(module.model, outputs=module.OUTPUTS) if isinstance(module, FileScene) else args.preset
    out = args.out if args.out is not None else f"rotorkit-out/{args.preset}-sweep-{'-'.join(space.names)}"
    out = check_output_folder(out, ours=False)  # '', a file or a device: refused before any run

    def progress(event):
        print(f"  {event}", file=sys.stderr, flush=True)

    kwargs = {"t_end": args.t_end} if args.t_end is not None else {}
    ds = run_sweep(scene, space, out_dir=out, overrides=overrides, workers=args.workers,
                   scheduler=args.scheduler, progress=progress, orders=args.order, signals=args.signal, poincare=args.poincare,
                   window=tuple(args.window), energy=args.energy, max_points=args.max_points, **kwargs)
    written = []
    dims = list(ds.status.dims)
    if len(dims) == 1:
        name = space.names[0]
        cascade = Cascade.from_dataset(ds)
        speed = float(overrides.get("lp_speed", module.DEFAULTS.get("lp_speed", 0.0)) or 0.0)
        ratio = float(overrides.get("speed_ratio", module.DEFAULTS.get("speed_ratio", 1.0)))
        if name == "lp_speed":
            orders = lambda value: speed_orders(value, ratio)  # noqa: E731
        elif name == "speed_ratio":
            orders = lambda value: speed_orders(speed, value)  # noqa: E731
        else:
            orders = speed_orders(speed, ratio) if speed else None
        if len(space.names) == 1:
            for signal in cascade.signals:
                ax = plot_cascade(cascade, signal, orders=orders, fmax=args.fmax)
                written.append(save_figure(ax.figure, out / f"cascade_{signal.replace('-', '_minus_')}.png"))
            for signal in ds.poincare_signal.values:
                ax = plot_bifurcation(ds, str(signal))
                written.append(save_figure(ax.figure, out / f"bifurcation_{str(signal).replace('-', '_minus_')}.png"))
    elif len(dims) == 2:
        ax = plot_status_map(ds)
        written.append(save_figure(ax.figure, out / "status_map.png"))
        for order in ds.order.values:
            for signal in ds.signal.values:
                ax = plot_order_map(ds, str(order), str(signal))
                safe = f"{signal}_order_{order}".replace("/", "_").replace(" ", "").replace("-", "_minus_")
                written.append(save_figure(ax.figure, out / f"map_{safe}.png"))
    status = ds.status.values.ravel()
    counts = {st: int((status == st).sum()) for st in ("ok", "failed", "runaway", "missing")}
    print(f"{status.size} points: " + ", ".join(f"{n} {st}" for st, n in counts.items() if n))
    flat = ds.message.values.ravel()
    for i in range(status.size):
        if status[i] in ("failed", "runaway"):
            point = ", ".join(f"{k} = {v:g}" for k, v in space.point(i).items())
            print(f"  {point}: {status[i]}: {str(flat[i]).splitlines()[0] if flat[i] else ''}")
    for p in written:
        print(f"wrote {p}")
    print(f"dataset {out / 'sweep.nc'} (xarray.open_dataset); point files in {out / 'points'} "
          "(an interrupted sweep resumes there)")
    return 0
