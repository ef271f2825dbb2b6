"""``rotorkit static``: static deflection under gravity or a manoeuvre load, and support reactions."""

from .common import save_figure
from .linear_common import add_linear_arguments, compiled_scene, output_folder, write_text


def register(sub):
    p = sub.add_parser("static", help="static deflection and support reactions")
    add_linear_arguments(p)
    p.add_argument("--t", type=float, default=0.0, help="time of the load (s): a manoeuvre's load at that instant")
    p.set_defaults(func=main)


def main(args):
    from ..analysis.static import static_deflection

    system, _ = compiled_scene(args)
    result = static_deflection(system, args.t)
    out = output_folder(args, "static")
    print(result.table())
    write_text(out / "static.csv", result.to_csv())
    save_figure(result.plot().figure, out / "static.png")
    print(f"wrote static.csv and static.png to {out}")
    return 0
