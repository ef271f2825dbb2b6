"""``rotorkit static``: static deflection under gravity or a manoeuvre load, and support reactions."""

from .common import save_figure
from .linear_common import add_linear_arguments, linear_scene, output_folder


def register(sub):
    p = sub.add_parser("static", help="static deflection and support reactions")
    add_linear_arguments(p)
    p.add_argument("--t", default="0", help="time of the load, s unless a unit is given (e.g. 2.5 or '2500 ms'): "
                                            "a manoeuvre's load at that instant")
    p.add_argument("--length-units", default="um", help="deflection units of the printed table (default um)")
    p.set_defaults(func=main)


def main(args):
    from ..linear.static import static_deflection

    from ..units import display_factor, to_si

    t = to_si(args.t, "s", "--t")
    display_factor(args.length_units, "length", "--length-units")  # refused before any derivation
    system, _ = linear_scene(args)  # a linear model: K q = F from its cached matrices, nothing compiled
    result = static_deflection(system, t)
    out = output_folder(args, "static")
    print(result.table(length_units=args.length_units))
    result.to_csv(out / "static.csv")
    save_figure(result.plot(length_units=args.length_units).figure, out / "static.png")
    print(f"wrote static.csv and static.png to {out}")
    return 0
