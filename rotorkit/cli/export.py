"""``rotorkit export``: write a preset (or a model file with overrides) as a TOML model file."""

import sys

from .common import add_scene_arguments, load_preset


def register(sub):
    ex = sub.add_parser("export", help="write a preset as a TOML model file (to stdout or --out)")
    add_scene_arguments(ex)
    ex.add_argument("--out", "-o", metavar="FILE", help="file to write (default: standard output)")
    ex.set_defaults(func=main)


def main(args):
    from ..files import check_output_file
    from ..modelfile import RUN_KEYS, dumps_model, save_model

    if args.out is not None:  # '' too: refused, not taken for "standard output"
        check_output_file(args.out)
    module, model, overrides = load_preset(args)
    outputs = getattr(module, "OUTPUTS", {})
    run = {k: outputs[k] for k in RUN_KEYS if k in outputs}
    description = getattr(module, "DESCRIPTION", None)
    if overrides:
        description = f"{description or model.name}; with " + ", ".join(f"{k}={v}" for k, v in overrides.items())
    if args.out is not None:
        path = save_model(model, args.out, run=run, description=description)
        print(f"wrote {path}", file=sys.stderr)
    else:
        sys.stdout.write(dumps_model(model, run=run, description=description))
    return 0
