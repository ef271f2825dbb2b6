"""``rotorkit campbell``: Campbell and stability diagrams, critical speeds, instability onset."""

from .common import positive_int, save_figure
from .linear_common import add_linear_arguments, linear_scene, output_folder, parse_speeds


def register(sub):
    p = sub.add_parser("campbell", help="Campbell and stability diagrams with critical speeds located")
    add_linear_arguments(p, speeds=True)
    p.add_argument("--modes", type=int, default=6, help="number of tracked modes (default 6)")
    p.add_argument("--orders", type=float, nargs="+", default=[1.0], help="excitation orders (default 1)")
    p.add_argument("--cage-samples", type=positive_int, default=4, help="cage positions averaged per speed (default 4)")
    p.set_defaults(func=main)


def main(args):
    from ..linear.campbell import campbell

    given = parse_speeds(args.speeds, None) if args.speeds is not None else None  # checked before deriving
    system, parameter = linear_scene(args)  # a linear model is not compiled
    speeds = given if given is not None else parse_speeds(None, system.parameters[parameter])
    diagram = campbell(system, speeds, n_modes=args.modes, speed_parameter=parameter, orders=args.orders,
                       cage_samples=args.cage_samples)
    out = output_folder(args, "campbell")
    from ..units import display_factor

    print(diagram.table(units=args.units))
    onset = diagram.instability_onset
    shown = None if onset is None else onset * display_factor(args.units)
    print("stable over the whole range (log decrements within rounding of zero count as zero)" if onset is None
          else f"instability onset at {parameter} = {shown:.6g} {args.units}")
    diagram.to_csv(out / "campbell.csv", units=args.units)
    save_figure(diagram.plot(units=args.units).figure, out / "campbell.png")
    save_figure(diagram.plot_stability(units=args.units).figure, out / "stability.png")
    print(f"wrote campbell.csv, campbell.png and stability.png to {out}")
    return 0
