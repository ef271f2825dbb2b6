"""``rotorkit modes``: modal analysis at the scene's operating point (log decrement, whirl, shapes)."""

from .common import nonnegative_int, positive_int, save_figure
from .linear_common import add_linear_arguments, compiled_scene, output_folder


def register(sub):
    p = sub.add_parser("modes", help="natural frequencies, damping, log decrement and whirl at one speed")
    add_linear_arguments(p)
    p.add_argument("--rub-engaged", action="store_true", help="linearise with the rub contact engaged along the sag")
    p.add_argument("--shapes", type=nonnegative_int, default=4, help="number of mode-shape figures to write (default 4)")
    p.add_argument("--cage-samples", type=positive_int, default=16, help="cage positions averaged (default 16)")
    p.add_argument("--modes", type=positive_int, default=8, dest="n_modes",
                   help="number of modes printed (default 8; the CSV holds all)")
    p.set_defaults(func=main)


def main(args):
    from ..linear.modes import natural_frequencies

    system, parameter = compiled_scene(args)
    modes = natural_frequencies(system, rub_engaged=True if args.rub_engaged else None,
                                cage_samples=args.cage_samples)
    out = output_folder(args, "modes")
    from ..units import display_factor

    speed = system.parameters[parameter] * display_factor(args.units)
    print(f"modes of {system.name} at {parameter} = {speed:g} {args.units}")
    print(modes.table(units=args.units, n_modes=args.n_modes))
    modes.to_csv(out / "modes.csv", units=args.units)
    for mode in range(1, min(args.shapes, len(modes)) + 1):
        save_figure(modes.plot_mode_shape(mode, units=args.units).figure, out / f"mode{mode}.png")
        save_figure(modes.plot_orbits(mode, units=args.units).figure, out / f"mode{mode}_orbits.png")
    print(f"wrote {out / 'modes.csv'} and {min(args.shapes, len(modes))} mode-shape figures to {out}")
    return 0
