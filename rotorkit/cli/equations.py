"""``rotorkit equations``: print the derived equations of a scene."""

from .common import add_scene_arguments, load_preset


def register(sub):
    eq = sub.add_parser("equations", help="print the derived equations of a preset or model file")
    add_scene_arguments(eq)
    eq.add_argument("--latex", action="store_true", help="print LaTeX instead of text")
    eq.set_defaults(func=main)


def main(args):
    from ..codegen.linear_cache import equations_text

    _, model, _ = load_preset(args)
    if args.latex:  # the printed equations are cached per structure: a warm cache derives nothing
        print(equations_text(model, latex=True))
    else:
        print(f"{model!r}\n\n{model.parameter_table()}\n\n{equations_text(model)}")
    return 0
