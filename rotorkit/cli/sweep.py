"""``rotorkit sweep``: a spectrum cascade over a swept parameter (parallel, resumable)."""

import sys
from pathlib import Path

from .common import check_parameter_name, parse_assignment, positive_float, positive_int, save_figure


def register(sub):
    sw = sub.add_parser("sweep", help="spectrum cascade over a swept parameter (parallel, resumable)")
    sw.add_argument("preset", help="preset name, e.g. al31f (see 'rotorkit list')")
    sw.add_argument("--param", required=True, metavar="NAME=START:STOP:N",
                    help="e.g. rub_stiffness=5e5:2e7:40, friction_coefficient=0:0.3:16, lp_speed=log:500:3000:20, "
                         "or a list friction_coefficient=0,0.1,0.2")
    sw.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                    help="override a preset parameter for every point")
    sw.add_argument("--out", help="output folder (default rotorkit-out/<preset>-sweep-<param>)")
    sw.add_argument("--workers", type=positive_int, default=2, help="local processes (default 2)")
    sw.add_argument("--fmax", type=positive_float, default=5000.0, help="largest frequency drawn (rad/s)")
    sw.set_defaults(func=main)



def main(args):
    from ..plotting.spectra import plot_cascade, speed_orders
    from ..presets import preset_module
    from ..sweep import parse_range, run_sweep

    module = preset_module(args.preset)
    known = {**module.DEFAULTS, **getattr(module, "SWITCHES", {})}
    name, values = parse_range(args.param)
    check_parameter_name(name, module.DEFAULTS, args.preset, what="--param")
    overrides = {}
    for text in args.set:
        key, value = parse_assignment(text, known)
        check_parameter_name(key, known, args.preset)
        overrides[key] = value
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
        written.append(save_figure(ax.figure, out / f"cascade_{signal.replace('-', '_minus_')}.png"))
    counts = {st: int((cascade.status == st).sum()) for st in ("ok", "failed", "runaway")}
    print(f"{len(values)} points: " + ", ".join(f"{n} {st}" for st, n in counts.items() if n))
    for i in range(len(values)):
        if cascade.status[i] != "ok":
            print(f"  {name} = {values[i]:g}: {cascade.status[i]}: {cascade.messages[i].splitlines()[0]}")
    for p in written:
        print(f"wrote {p}")
    print(f"point spectra in {out} (an interrupted sweep resumes there)")
    return 0


